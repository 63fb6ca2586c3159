//! A robot's set-up of an [`Identification`]: its prior and ellipsoids, and
//! its description's identification facts (the sidecar's per-body levels,
//! `[identify] total_mass`, `equal` and `prior_mass_weight`).

use super::builder::Identification;
use super::error::IdentifyError;
use super::options::Level;
use crate::dynamics::RobotDescription;

impl<'m> Identification<'m> {
    /// A robot's set-up: `level` for every body, its CAD prior with weight
    /// `weight`, its bounding ellipsoids where it has exactly one per body
    /// (computed only when a body needs one, now or after a later
    /// [`Self::level`] or [`Self::com_lmi`]: [`RobotDescription::bounding`]),
    /// and the per-body levels, constraints and masses' extra weight of its
    /// sidecar (the last used with the Euclidean prior on, [`Self::mass_weight`]).
    pub fn for_robot(
        robot: &'m RobotDescription,
        level: Level,
        weight: f64,
    ) -> Result<Self, IdentifyError> {
        let model = &robot.model;
        let mut s = Self::new(model)
            .level_all(level)
            .prior(weight, robot.prior_vector())?;
        s.robot = Some(robot);
        s.resolve_ellipsoids();
        apply(s, robot)
    }
}

/// Applies `robot`'s facts: levels replace the common one; a total mass and
/// pairs of equal bodies become constraints; the masses' extra weight is
/// the robot's (used with the Euclidean prior on, unless the caller sets one).
fn apply<'m>(
    mut s: Identification<'m>,
    robot: &'m RobotDescription,
) -> Result<Identification<'m>, IdentifyError> {
    let facts = &robot.identification;
    for (name, level) in robot.model.body_names().iter().zip(&facts.levels) {
        if let Some(l) = level {
            s = s.level(name, *l)?;
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
