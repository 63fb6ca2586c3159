//! What every writer of the export asks of a model.

use super::error::ExportError;
use crate::dynamics::Friction;
use crate::moments::InertialParams;

/// `(mass, CoM, inertia about the CoM)` of body `body` for a URDF
/// `<inertial>`, which needs a positive mass (the CoM is undefined otherwise).
pub(super) fn urdf_inertial(
    body: &str,
    p: &InertialParams,
) -> Result<(f64, [f64; 3], [f64; 6]), ExportError> {
    if !(p.mass() > 0.0) {
        return Err(ExportError::Body {
            body: body.into(),
            message: format!(
                "mass {} kg: a URDF <inertial> needs a positive mass (the CoM is undefined)",
                p.mass()
            ),
        });
    }
    Ok(p.to_urdf())
}

/// Whether viscous or Coulomb friction was identified (not all zero): only
/// then is it written over the robot's own.
pub(super) fn has_friction(f: &Friction) -> bool {
    f.viscous.iter().chain(&f.coulomb).any(|&x| x != 0.0)
}
