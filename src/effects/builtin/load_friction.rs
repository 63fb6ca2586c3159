//! `load_friction`: load-dependent Coulomb friction
//! `μ |τ_rigid,i| sign(q̇ᵢ)` on every joint, the friction law's `load` term
//! (a harmonic drive's friction grows with the torque it transmits;
//! τ_rigid the rigid model's torque, links and rotors). Diagnosed with the
//! nominal model's rigid torque as the load (as the law has it): the measured torque's noise would
//! enter both the column and the residual, a correlation that is no
//! friction.

use crate::dynamics::FrictionTerm;
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Size, SizeContext, Values,
};
use crate::sim::Truth;

/// Load-dependent friction.
pub struct LoadFriction;

const COEFFICIENT: ParamSpec = ParamSpec::new(
    "load_coefficient",
    "1",
    0.05,
    Range::NonNegative,
    "Load-friction coefficient μ (N·m of friction per N·m of load), every joint.",
);

impl Effect for LoadFriction {
    fn name(&self) -> &'static str {
        "load_friction"
    }

    fn motion(&self) -> &'static str {
        "large load torques (against gravity or a payload) at moderate speed"
    }

    fn law_term(&self) -> Option<FrictionTerm> {
        Some(FrictionTerm::Load)
    }

    fn implausible(&self, _: &Columns, _: usize, beta: f64) -> Option<String> {
        super::friction::term_implausible(FrictionTerm::Load, beta)
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        super::friction::term_sizes(beta, cx, FrictionTerm::Load, "load friction μ")
    }

    fn summary(&self) -> &'static str {
        "Load-dependent friction (a harmonic drive's: μ |τ| sign q̇)"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![COEFFICIENT]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let mu = p.get(COEFFICIENT.name)?;
        let n = truth.robot().model.dof();
        *truth.friction_mut().coefficients_mut(FrictionTerm::Load) = vec![mu; n];
        Ok(())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let (tau, d) = (cx.rigid_torques()?, cx.data);
        let load = FrictionTerm::Load;
        Ok(Hypothesis::per_joint(
            cx.per_joint(|k, i| load.basis(d.qd[k][i], tau[k][i], 1.0)),
        ))
    }
}
