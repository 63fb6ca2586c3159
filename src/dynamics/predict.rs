//! Model torques for a batch of samples: `τ = RNEA(q, q̇, q̈) + τ_f(q̇)`, the
//! friction law of [`super::friction`].

use super::data::Data;
use super::error::DynamicsError;
use super::friction::Friction;
use super::model::Model;
use super::rnea::rnea;
use super::samples::Samples;

/// Predicted joint torques, one row of n per sample of `q, q̇, q̈` (as
/// many samples as `q` has; `q̇, q̈` must have them too); a torque that is
/// not finite is an error naming the sample and joint.
pub fn predict_torques(
    model: &Model,
    friction: &Friction,
    q: &Samples,
    qd: &Samples,
    qdd: &Samples,
) -> Result<Samples, DynamicsError> {
    let n = model.dof();
    friction.check_joints(n)?;
    for (what, v) in [("q̇ samples", qd), ("q̈ samples", qdd)] {
        if v.len() != q.len() {
            return Err(DynamicsError::Dimension {
                what: what.into(),
                expected: q.len(),
                found: v.len(),
            });
        }
    }
    let mut data = Data::new(model);
    let mut out = Samples::with_capacity(n, q.len());
    for k in 0..q.len() {
        let tau = rnea(model, &mut data, &q[k], &qd[k], &qdd[k])?;
        out.push_with(|i| friction.add_to(tau[i], i, qd[k][i]));
        if let Some(i) = out[k].iter().position(|x| !x.is_finite()) {
            return Err(DynamicsError::NonFinite {
                sample: k,
                what: format!("the torque of joint '{}'", model.joints[i].name),
            });
        }
    }
    Ok(out)
}
