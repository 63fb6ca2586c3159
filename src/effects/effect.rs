//! The [`Effect`] trait: everything about one effect a real robot may have
//! and a nominal rigid-body model may lack, in one implementation.

use super::context::Context;
use super::error::EffectError;
use super::hypothesis::{Columns, Hypothesis, Memory, Shape};
use super::params::ParamSpec;
use super::size::{Size, SizeContext};
use super::values::Values;
use crate::dynamics::{FrictionTerm, Model};
use crate::sim::Truth;

/// An effect: its name and parameters, how the simulator's true robot has
/// it, and how a diagnosis looks for it in a residual.
///
/// A new effect is one type implementing this trait, added to a
/// [`super::Library`] (the built-in ones: one file each under
/// `src/effects/builtin/`, one line in its registry). Only [`Self::name`],
/// [`Self::summary`], [`Self::apply`] and [`Self::hypothesis`] are
/// required; `examples/custom_effect.rs` defines one outside the crate.
///
/// Units: torques in N·m (N for a prismatic joint), angles in rad,
/// velocities in rad/s, time in s.
pub trait Effect: Send + Sync {
    /// The name on the command line, in files and reports (`snake_case`,
    /// unique in a library).
    fn name(&self) -> &'static str;

    /// What it is, in one line.
    fn summary(&self) -> &'static str;

    /// Its parameters, with units, nominal values and ranges (none by
    /// default). A robot's sidecar `[effects]` table and `NAME=VALUE`
    /// overrides change the values [`Self::apply`] receives.
    fn params(&self) -> Vec<ParamSpec> {
        vec![]
    }

    /// Simulation: adds the effect to the true robot `truth` with the
    /// values `p` of its parameters (every one [`Self::params`] declares).
    /// Effects are applied in the library's order.
    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError>;

    /// Diagnosis: why the effect cannot be proposed for `model`, if it
    /// cannot (reported as a warning); `None` by default.
    fn inapplicable(&self, _model: &Model) -> Option<&'static str> {
        None
    }

    /// Diagnosis: what building [`Self::hypothesis`] holds in memory (by
    /// default, one essential column per joint).
    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, shape.joints)
    }

    /// Diagnosis: a relative estimate of how long [`Self::hypothesis`]
    /// takes; the most expensive hypotheses are started first (0 by
    /// default; a search by simulation is more).
    fn expense(&self) -> u32 {
        0
    }

    /// Diagnosis: computes, before the hypotheses are built in parallel,
    /// what this effect shares with others through `cx` (the linearised
    /// link dynamics), so that it is computed once with every core rather
    /// than by one build while the others wait (nothing by default; an error
    /// is left for [`Self::hypothesis`] to report).
    fn prepare(&self, _cx: &Context) {}

    /// Diagnosis: the hypothesis for the data in `cx` — regressor columns
    /// where the effect is linear in its magnitudes, a grid of variants
    /// over a nonlinear parameter, or the result of a search on the
    /// training part (`cx.train`) for a nonlinear effect. An error skips
    /// the effect with a warning.
    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError>;

    /// Diagnosis: why the fitted coefficients `beta` of `variant` are
    /// physically doubtful, if they are (`joints`: the joint names). A fit
    /// at an open edge of a grid is flagged by the diagnosis itself.
    fn doubt(&self, _variant: &Columns, _beta: &[f64], _joints: &[String]) -> Option<String> {
        None
    }

    /// Diagnosis: why the coefficient `beta` of column `col` of `variant` is
    /// beyond what the effect can physically be, if it is (a 60 % torque
    /// gain error, a 0.5 s delay of a torque sensor): then it is absorbing
    /// something else. A per-joint hypothesis is not kept on a joint with
    /// such a coefficient; another one with one is not accepted. None by
    /// default.
    fn implausible(&self, _variant: &Columns, _col: usize, _beta: f64) -> Option<String> {
        None
    }

    /// Diagnosis: the report's detail line for a fitted variant (by
    /// default the variant's own).
    fn detail(&self, variant: &Columns, _beta: &[f64]) -> String {
        variant.detail.clone()
    }

    /// Diagnosis: fitted values the report's JSON carries under their own
    /// key (none by default; `joint_offset` gives `joint_offsets`). A key
    /// must not be one of the report's own fields (`effect`, `detail`, …).
    fn fitted(&self, _variant: &Columns, _beta: &[f64]) -> Vec<(&'static str, Vec<f64>)> {
        vec![]
    }

    /// Diagnosis: the kind of motion that shows this effect most ("slow
    /// motion near zero velocity"), which the report names when it is
    /// tied with another: a motion rich in one and poor in the other tells
    /// them apart (`excite --separate` designs one).
    fn motion(&self) -> &'static str {
        "a motion that varies its columns unlike the other's"
    }

    /// Diagnosis: the term of the friction law this effect is, if it is
    /// one (`coulomb` is [`FrictionTerm::Coulomb`]). A nominal model whose
    /// law has the term refits its coefficients with the law, so the
    /// effect is not proposed beside it (none by default).
    fn law_term(&self) -> Option<FrictionTerm> {
        None
    }

    /// Diagnosis: whether the effect is a change of the nominal model's own
    /// bodies (`link_inertia`, `rotor_inertia`; not a body of its own, as a
    /// payload is). Given the data the nominal was identified on, the
    /// diagnosis refits those bodies with the law, so such an effect is not
    /// proposed beside them (false by default).
    fn changes_nominal_bodies(&self) -> bool {
        false
    }

    /// Diagnosis: the sizes an accepted effect reports, computed from the
    /// coefficients `beta` of `variant` (the diagnosis gives each an
    /// interval by evaluating them on the coefficients' replicates, so the
    /// list's length and order must depend on the zeros of `beta` only).
    /// By default, one per nonzero coefficient of a column in one joint.
    fn sizes(&self, _variant: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        cx.per_joint(beta, "coefficient", "1", 1.0)
    }

    /// A model file: the columns of the variant recorded as `key`
    /// ([`Columns::key`]) for the data and model of `cx` — to predict with
    /// an accepted effect, or identify it again. By default the hypothesis'
    /// variant with that key; an error names the effect when there is none
    /// (a search's result is not rebuilt on other data).
    fn replay(&self, cx: &Context, key: &[(String, f64)]) -> Result<Columns, EffectError> {
        let same = |a: &[(String, f64)]| {
            a.len() == key.len()
                && (a.iter().zip(key))
                    .all(|((n, x), (m, y))| n == m && (x - y).abs() <= 1e-9 * (1.0 + y.abs()))
        };
        self.hypothesis(cx)?
            .variants
            .into_iter()
            .find(|v| same(&v.key))
            .ok_or_else(|| EffectError::NotReplayable {
                effect: self.name().into(),
                key: key
                    .iter()
                    .map(|(n, v)| format!("{n} = {v}"))
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }
}
