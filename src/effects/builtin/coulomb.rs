//! `coulomb`: Coulomb friction `s_c B_c,i sign(q̇ᵢ)`, the robot's nominal
//! Coulomb coefficients B_c (its description) scaled by `coulomb_scale`.

use crate::dynamics::FrictionTerm;
use crate::effects::{Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Values};
use crate::sim::{SimWarning, Truth};

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

/// The true robot's Coulomb coefficients: the nominal ones times `scale`.
pub fn scaled_coulomb(truth: &Truth, scale: f64) -> Vec<f64> {
    let nominal = truth.robot().friction.coefficients(FrictionTerm::Coulomb);
    nominal.iter().map(|c| c * scale).collect()
}

impl Effect for Coulomb {
    fn name(&self) -> &'static str {
        "coulomb"
    }

    fn summary(&self) -> &'static str {
        "Coulomb friction"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![COULOMB_SCALE]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let c = scaled_coulomb(truth, p.get(COULOMB_SCALE.name)?);
        if c.iter().all(|x| *x == 0.0) {
            truth.warn(SimWarning::NominalFrictionZero {
                effect: self.name().into(),
            });
        }
        *truth.friction_mut().coefficients_mut(FrictionTerm::Coulomb) = c;
        Ok(())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let d = cx.data;
        Ok(Hypothesis::linear(cx.per_joint(|k, i| {
            FrictionTerm::Coulomb.basis(d.qd[k][i])
        })))
    }
}
