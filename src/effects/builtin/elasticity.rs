//! `elasticity`: series elasticity of the transmission. The true robot's
//! links are driven from the motor side through a spring–damper per joint
//! (`sim::compliance`); the diagnosis searches a stiffness, damping and
//! axial inertia split per joint by simulating the linearised link
//! dynamics ([`crate::effects::compliance`]); needs a rotor on some joint.

use crate::dynamics::Model;
use crate::effects::compliance::{self, has_motor_side};
use crate::effects::{
    Columns,
    Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Values,
};
use crate::sim::Truth;
use crate::sim::compliance::Compliance;

/// Series elasticity.
pub struct Elasticity;

/// The transmission's stiffness (shared with `backlash`).
pub const STIFFNESS: ParamSpec = ParamSpec::new(
    "stiffness",
    "N·m/rad",
    2000.0,
    Range::Positive,
    "Transmission stiffness K.",
);
/// The transmission's damping (shared with `backlash`).
pub const DAMPING: ParamSpec = ParamSpec::new(
    "damping",
    "N·m·s/rad",
    5.0,
    Range::NonNegative,
    "Transmission damping D.",
);

/// Why a compliance cannot be proposed without a rotor.
pub const NO_MOTOR_SIDE: &str = "not proposed: the model has no rotors, so no motor side whose turns or compliance the data could show";

/// The spring–damper of `p` with dead band `backlash`.
pub fn transmission(p: &Values, backlash: f64) -> Result<Compliance, EffectError> {
    Ok(Compliance {
        stiffness: p.get(STIFFNESS.name)?,
        damping: p.get(DAMPING.name)?,
        backlash,
    })
}

/// What a compliance search holds: one column per joint, and the
/// linearisation it shares with the other compliance hypotheses.
pub fn memory(shape: &Shape) -> Memory {
    let shared = compliance::memory_bytes(shape.joints, shape.samples);
    Memory::optional(shape, shape.joints, "compliance", shared)
}

/// The compliance hypothesis recorded as `key`, simulated on the data of
/// `cx` (with a dead band if `backlash`).
pub fn replayed(cx: &Context, key: &[(String, f64)], backlash: bool, effect: &str) -> Result<Columns, EffectError> {
    let p = compliance::from_key(key, cx.joints()).ok_or_else(|| EffectError::NotReplayable {
        effect: effect.into(),
        key: "no stiffness_i, damping_i, backlash_i and axial_shift_i for every joint".into(),
    })?;
    let lin = cx.linearisation()?;
    compliance::columns_of(lin, &p, backlash).ok_or(EffectError::SearchFailed)
}

/// The fitted compliance hypothesis (with a dead band if `backlash`).
pub fn searched(cx: &Context, backlash: bool) -> Result<Hypothesis, EffectError> {
    let lin = cx.linearisation()?;
    let fit = compliance::fit(lin, cx.residual, cx.train, backlash).ok_or(EffectError::SearchFailed)?;
    let cols = compliance::columns(lin, &fit, backlash).ok_or(EffectError::SearchFailed)?;
    Ok(Hypothesis::single(cols))
}

impl Effect for Elasticity {
    fn name(&self) -> &'static str {
        "elasticity"
    }

    fn motion(&self) -> &'static str {
        "fast changes of torque (high accelerations at high frequency)"
    }

    fn summary(&self) -> &'static str {
        "Series elasticity of the transmission"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![STIFFNESS, DAMPING]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        truth.set_compliance(transmission(p, 0.0)?);
        Ok(())
    }

    fn inapplicable(&self, model: &Model) -> Option<&'static str> {
        (!has_motor_side(model)).then_some(NO_MOTOR_SIDE)
    }

    fn memory(&self, shape: &Shape) -> Memory {
        memory(shape)
    }

    fn expense(&self) -> u32 {
        1
    }

    fn prepare(&self, cx: &Context) {
        let _ = cx.linearisation();
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        searched(cx, false)
    }

    fn replay(&self, cx: &Context, key: &[(String, f64)]) -> Result<Columns, EffectError> {
        replayed(cx, key, false, self.name())
    }
}
