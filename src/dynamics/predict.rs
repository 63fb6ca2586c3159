//! Model torques for a batch of samples: `τ = RNEA(q, q̇, q̈) + B q̇ + B_c sign(q̇)`.

use super::data::Data;
use super::error::DynamicsError;
use super::model::Model;
use super::params_file::Friction;
use super::regressor::sign;
use super::rnea::rnea;

/// Predicted joint torques, one `Vec` of length n per sample; a torque
/// that is not finite is an error naming the sample and joint.
pub fn predict_torques(
    model: &Model,
    friction: &Friction,
    q: &[Vec<f64>],
    qd: &[Vec<f64>],
    qdd: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, DynamicsError> {
    let n = model.dof();
    if friction.viscous.len() != n || friction.coulomb.len() != n {
        return Err(DynamicsError::Dimension {
            what: "friction coefficients".into(),
            expected: n,
            found: friction.viscous.len().min(friction.coulomb.len()),
        });
    }
    let mut data = Data::new(model);
    let mut out = Vec::with_capacity(q.len());
    for k in 0..q.len() {
        let tau = rnea(model, &mut data, &q[k], &qd[k], &qdd[k])?;
        let row: Vec<f64> = (0..n)
            .map(|i| tau[i] + friction.viscous[i] * qd[k][i] + friction.coulomb[i] * sign(qd[k][i]))
            .collect();
        if let Some(i) = row.iter().position(|x| !x.is_finite()) {
            return Err(DynamicsError::NonFinite {
                sample: k,
                what: format!("the torque of joint '{}'", model.joints[i].name),
            });
        }
        out.push(row);
    }
    Ok(out)
}
