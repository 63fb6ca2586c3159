//! `asymmetric_friction`: Coulomb friction that differs by direction,
//! `a s_c B_c,i |sign(q̇ᵢ)|` added to the Coulomb term: (1 + a)·B_c forward,
//! (1 − a)·B_c backward.

use super::coulomb::COULOMB_SCALE;
use super::friction::scaled_nominal;
use crate::dynamics::{FrictionTerm, sign};
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Size, SizeContext, Values,
};
use crate::sim::Truth;

/// Direction-dependent Coulomb friction.
pub struct AsymmetricFriction;

const ASYMMETRY: ParamSpec = ParamSpec::new(
    "asymmetry",
    "1",
    0.3,
    Range::Within(-1.0, 1.0),
    "Asymmetry a: Coulomb (1 + a)·B_c forward, (1 − a)·B_c backward.",
);

impl Effect for AsymmetricFriction {
    fn name(&self) -> &'static str {
        "asymmetric_friction"
    }

    fn motion(&self) -> &'static str {
        "motion at the same speeds in both directions"
    }

    fn law_term(&self) -> Option<FrictionTerm> {
        Some(FrictionTerm::Asymmetric)
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        super::friction::term_sizes(beta, cx, FrictionTerm::Asymmetric, "Coulomb asymmetry")
    }

    fn summary(&self) -> &'static str {
        "Coulomb friction that differs by direction"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![COULOMB_SCALE, ASYMMETRY]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let a = p.get(ASYMMETRY.name)?;
        let scale = p.get(COULOMB_SCALE.name)?;
        let c = scaled_nominal(truth, FrictionTerm::Coulomb, scale, self.name());
        truth.add_torque(move |s| a * c[s.joint] * sign(s.qd).abs());
        Ok(())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let d = cx.data;
        Ok(Hypothesis::per_joint(
            cx.per_joint(|k, i| sign(d.qd[k][i]).abs()),
        ))
    }
}
