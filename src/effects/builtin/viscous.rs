//! `viscous`: viscous friction `s_v B_i q̇ᵢ`, the robot's nominal viscous
//! coefficients B (its description) scaled by `viscous_scale`.

use crate::dynamics::FrictionTerm;
use crate::effects::{Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Values};
use crate::sim::{SimWarning, Truth};

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

    fn summary(&self) -> &'static str {
        "Viscous friction"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![VISCOUS_SCALE]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let s = p.get(VISCOUS_SCALE.name)?;
        let nominal = truth.robot().friction.coefficients(FrictionTerm::Viscous);
        let v: Vec<f64> = nominal.iter().map(|c| c * s).collect();
        if v.iter().all(|x| *x == 0.0) {
            truth.warn(SimWarning::NominalFrictionZero {
                effect: self.name().into(),
            });
        }
        *truth.friction_mut().coefficients_mut(FrictionTerm::Viscous) = v;
        Ok(())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let d = cx.data;
        Ok(Hypothesis::linear(cx.per_joint(|k, i| {
            FrictionTerm::Viscous.basis(d.qd[k][i])
        })))
    }
}
