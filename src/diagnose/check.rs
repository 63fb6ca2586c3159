//! What data a diagnosis takes: enough samples with torques, the model's
//! joints, some motion (the diagnosed data and the nominal's own alike).

use super::error::DiagnoseError;
use crate::data::Dataset;
use crate::dynamics::Model;

/// The fewest samples a diagnosis takes.
pub const MIN_SAMPLES: usize = 100;

/// Checks that `data` can be diagnosed against `model`: enough samples
/// with torques, the model's joints, some motion.
pub fn check_data(model: &Model, data: &Dataset) -> Result<(), DiagnoseError> {
    if data.tau.len() != data.len() || data.len() < MIN_SAMPLES {
        return Err(DiagnoseError::TooFewSamples {
            needed: MIN_SAMPLES,
            found: if data.tau.len() == data.len() {
                data.len()
            } else {
                0
            },
        });
    }
    let names: Vec<String> = model.joint_names().iter().map(|s| s.to_string()).collect();
    if data.joints != names {
        return Err(DiagnoseError::Joints {
            expected: names,
            found: data.joints.clone(),
        });
    }
    let n = model.dof();
    if (0..n).all(|i| data.q.iter().all(|q| q[i] == data.q[0][i])) {
        return Err(DiagnoseError::NoMotion);
    }
    Ok(())
}
