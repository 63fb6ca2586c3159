//! `viscous`: viscous friction `s_v B_i q̇ᵢ`, the robot's nominal viscous
//! coefficients B (its description) scaled by `viscous_scale`.

use crate::dynamics::FrictionTerm;
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Size, SizeContext, Values,
};
use super::friction::{basis_hypothesis, scaled_nominal};
use crate::sim::Truth;

/// Viscous friction.
pub struct Viscous;

const VISCOUS_SCALE: ParamSpec = ParamSpec::new(
    "viscous_scale",
    "1",
    1.0,
    Range::Any,
    "Scale of the robot's nominal viscous friction (1: as described).",
);

impl Effect for Viscous {
    fn name(&self) -> &'static str {
        "viscous"
    }

    fn motion(&self) -> &'static str {
        "high speed"
    }

    fn law_term(&self) -> Option<FrictionTerm> {
        Some(FrictionTerm::Viscous)
    }

    fn implausible(&self, _: &Columns, _: usize, beta: f64) -> Option<String> {
        super::friction::term_implausible(FrictionTerm::Viscous, beta)
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        super::friction::term_sizes(beta, cx, FrictionTerm::Viscous, "viscous friction")
    }

    fn summary(&self) -> &'static str {
        "Viscous friction"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![VISCOUS_SCALE]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let scale = p.get(VISCOUS_SCALE.name)?;
        let v = scaled_nominal(truth, FrictionTerm::Viscous, scale, self.name());
        *truth.friction_mut().coefficients_mut(FrictionTerm::Viscous) = v;
        Ok(())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        Ok(basis_hypothesis(cx, FrictionTerm::Viscous))
    }
}
