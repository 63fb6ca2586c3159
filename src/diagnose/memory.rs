//! The diagnosis' memory plan: what the candidate library holds, and which
//! of its optional parts fit the limit.

use super::error::DiagnoseError;
use super::warning::DiagnoseWarning;
use crate::dynamics::Model;
use crate::effects::{Library, Part, Shape};

/// What a diagnosis will hold for its candidates (bytes).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// The essential hypotheses: the diagnosis is refused if they do not fit.
    pub essential: u64,
    /// The optional groups, in the library's order, each left out (with a
    /// warning) when it does not fit beside what is already planned.
    pub optional: Vec<OptionalGroup>,
}

/// One optional group of hypotheses.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OptionalGroup {
    /// Its name (`"inertial"`, `"compliance"`).
    pub group: &'static str,
    /// Its effects, in the library's order.
    pub effects: Vec<&'static str>,
    /// Their bytes, the shared part counted once.
    pub bytes: u64,
}

/// The [`MemoryEstimate`] of diagnosing `samples` samples of `model` with
/// the effects of `library` that apply to it ([`crate::effects::Effect::memory`]).
pub fn memory_estimate(library: &Library, model: &Model, samples: usize) -> MemoryEstimate {
    let shape = Shape {
        joints: model.dof(),
        bodies: model.num_bodies(),
        samples,
    };
    let mut est = MemoryEstimate {
        essential: 0,
        optional: vec![],
    };
    for e in library
        .effects()
        .iter()
        .filter(|e| e.inapplicable(model).is_none())
    {
        let m = e.memory(&shape);
        match m.part {
            Part::Essential => est.essential += m.bytes,
            Part::Optional { group, shared } => {
                match est.optional.iter_mut().find(|g| g.group == group) {
                    Some(g) => {
                        g.effects.push(e.name());
                        g.bytes += m.bytes;
                    }
                    None => est.optional.push(OptionalGroup {
                        group,
                        effects: vec![e.name()],
                        bytes: m.bytes + shared,
                    }),
                }
            }
        }
    }
    est
}

/// The effects left out to fit `limit` bytes: the essential hypotheses
/// must fit (else the diagnosis is refused); each optional group, in
/// order, is kept if it fits beside what is kept, else left out with a
/// warning.
pub fn plan(
    est: &MemoryEstimate,
    limit: u64,
    warnings: &mut Vec<DiagnoseWarning>,
) -> Result<Vec<&'static str>, DiagnoseError> {
    let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
    if est.essential > limit {
        return Err(DiagnoseError::TooLarge {
            needed_gib: gib(est.essential),
            limit_gib: gib(limit),
        });
    }
    let mut used = est.essential;
    let mut left_out = vec![];
    for g in &est.optional {
        if used + g.bytes <= limit {
            used += g.bytes;
        } else {
            warnings.push(DiagnoseWarning::NotConsidered {
                effects: g.effects.iter().map(|s| s.to_string()).collect(),
                needed_gib: gib(g.bytes),
                limit_gib: gib(limit),
            });
            left_out.extend(&g.effects);
        }
    }
    Ok(left_out)
}

#[cfg(test)]
mod tests {
    use super::{DiagnoseError, memory_estimate, plan};
    use crate::dynamics::cheetah3;
    use crate::effects::Library;

    /// The leg's library over 2,000 samples: 142 essential columns (16
    /// bytes per sample, joint and column), the inertial group's 60 columns
    /// and the compliance group's linearisation plus 6 columns; a limit
    /// keeps the groups that fit in order, and refuses a diagnosis whose
    /// essential part does not fit.
    #[test]
    fn the_plan_keeps_the_groups_that_fit_in_order() {
        let leg = cheetah3::model();
        let est = memory_estimate(&Library::builtin(), &leg, 2000);
        let col = 16 * 2000 * 3;
        assert_eq!(est.essential, 142 * col);
        let groups: Vec<(&str, Vec<&str>)> = est
            .optional
            .iter()
            .map(|g| (g.group, g.effects.clone()))
            .collect();
        assert_eq!(
            groups,
            [
                ("inertial", vec!["rotor_inertia", "link_inertia"]),
                ("compliance", vec!["elasticity", "backlash"])
            ]
        );
        assert_eq!(est.optional[0].bytes, 60 * col);
        assert!(est.optional[1].bytes > 6 * col);
        let (inertial, compliance) = (est.optional[0].bytes, est.optional[1].bytes);
        let mut w = vec![];
        assert!(matches!(
            plan(&est, est.essential - 1, &mut w),
            Err(DiagnoseError::TooLarge { .. })
        ));
        let out = plan(&est, est.essential + inertial, &mut w).unwrap();
        assert_eq!(out, ["elasticity", "backlash"]);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].to_string()
                .starts_with("elasticity, backlash: not considered")
        );
        // the compliance group alone would fit, but the inertial group comes first
        let mut w = vec![];
        let out = plan(&est, est.essential + compliance, &mut w).unwrap();
        assert_eq!(out, ["elasticity", "backlash"]);
        let all = plan(&est, est.essential + inertial + compliance, &mut vec![]).unwrap();
        assert!(all.is_empty());
    }

    /// Effects that cannot apply to a model cost nothing: without rotors,
    /// no cogging columns (72) and no compliance group, but a ripple's
    /// (2 × 12 periods × 3 joints), which needs joints without one.
    #[test]
    fn inapplicable_effects_are_not_counted() {
        let leg = cheetah3::model();
        let mut bare = leg.clone();
        bare.rotors.clear();
        let bare = crate::dynamics::Model::new("bare", bare.joints, vec![], bare.gravity).unwrap();
        let est = memory_estimate(&Library::builtin(), &bare, 2000);
        let col = 16 * 2000 * 3;
        assert_eq!(est.essential, (142 - 72 + 72) * col);
        assert_eq!(est.optional.len(), 1);
        assert_eq!(est.optional[0].effects, ["link_inertia"]);
    }
}
