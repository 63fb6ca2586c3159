//! `coulomb`: Coulomb friction `s_c B_c,i sign(q̇ᵢ)`, the robot's nominal
//! Coulomb coefficients B_c (its description) scaled by `coulomb_scale`.

use crate::dynamics::FrictionTerm;
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Size, SizeContext, Values,
};
use super::friction::{basis_hypothesis, scaled_nominal};
use crate::sim::Truth;

/// Coulomb friction.
pub struct Coulomb;

/// The scale of the nominal Coulomb friction (shared with
/// `asymmetric_friction`, whose asymmetry is relative to it).
pub const COULOMB_SCALE: ParamSpec = ParamSpec::new(
    "coulomb_scale",
    "1",
    1.0,
    Range::Any,
    "Scale of the robot's nominal Coulomb friction (1: as described).",
);

impl Effect for Coulomb {
    fn name(&self) -> &'static str {
        "coulomb"
    }

    fn motion(&self) -> &'static str {
        "slow motion with many velocity reversals"
    }

    fn law_term(&self) -> Option<FrictionTerm> {
        Some(FrictionTerm::Coulomb)
    }

    fn implausible(&self, _: &Columns, _: usize, beta: f64) -> Option<String> {
        super::friction::term_implausible(FrictionTerm::Coulomb, beta)
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        super::friction::term_sizes(beta, cx, FrictionTerm::Coulomb, "Coulomb friction")
    }

    fn summary(&self) -> &'static str {
        "Coulomb friction"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![COULOMB_SCALE]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let scale = p.get(COULOMB_SCALE.name)?;
        let c = scaled_nominal(truth, FrictionTerm::Coulomb, scale, self.name());
        *truth.friction_mut().coefficients_mut(FrictionTerm::Coulomb) = c;
        Ok(())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        Ok(basis_hypothesis(cx, FrictionTerm::Coulomb))
    }
}
