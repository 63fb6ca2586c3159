//! Model torques for a batch of samples: `τ = RNEA(q, q̇, q̈) + τ_f(q̇)`, the
//! friction law of [`super::friction`].

use super::data::Data;
use super::error::DynamicsError;
use super::friction::Friction;
use super::model::Model;
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
    friction.check_joints(n)?;
    let mut data = Data::new(model);
    let mut out = Vec::with_capacity(q.len());
    for k in 0..q.len() {
        let tau = rnea(model, &mut data, &q[k], &qd[k], &qdd[k])?;
        let row: Vec<f64> = (0..n)
            .map(|i| friction.add_to(tau[i], i, qd[k][i]))
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
