//! A robot description's identification facts (the sidecar's per-body
//! levels, `[identify] total_mass`, `equal` and `prior_mass_weight`) applied to an
//! [`Identification`].

use super::builder::Identification;
use super::error::IdentifyError;
use super::problem::Level;
use crate::dynamics::RobotDescription;

/// Applies `robot`'s facts: levels replace the common one; a total mass and
/// pairs of equal bodies become constraints; the masses' extra weight is
/// the robot's (used with the Euclidean prior on, unless the caller sets one).
pub(crate) fn apply<'m>(
    mut s: Identification<'m>,
    robot: &'m RobotDescription,
) -> Result<Identification<'m>, IdentifyError> {
    let facts = &robot.identification;
    for (name, level) in robot.model.body_names().iter().zip(&facts.levels) {
        if let Some(l) = level {
            let level = Level::parse(l).ok_or_else(|| IdentifyError::Option {
                option: "level",
                message: format!(
                    "body '{name}': level '{l}' is not one of none, semi, consistent, ellipsoid"
                ),
            })?;
            s = s.level(name, level)?;
        }
    }
    s = s.robot_mass_weight(facts.prior_mass_weight);
    if let Some(m) = facts.total_mass {
        s = s.constrain(move |p, v| {
            p.add_eq(v.total_mass(), m)?;
            Ok(())
        });
    }
    for (a, b) in &facts.equal {
        s = s.constrain(move |p, v| {
            v.body(a)?.add_equal(p, v.body(b)?)?;
            Ok(())
        });
    }
    Ok(s)
}
