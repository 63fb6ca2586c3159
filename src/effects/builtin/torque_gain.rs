//! `torque_gain`: a torque-constant (gain) error, the measured torque
//! `(1 + ε) τ`. Diagnosed with one column per joint, the nominal model's
//! torque τ̂ᵢ in joint i's rows: a gain ε_i per joint (one sensor's
//! calibration, or one motor's torque constant).

use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Size,
    SizeContext, Values,
};
use crate::sim::Truth;

/// A torque gain error.
pub struct TorqueGain;

const GAIN_ERROR: ParamSpec = ParamSpec::new(
    "gain_error",
    "1",
    0.1,
    Range::Above(-1.0),
    "Torque gain error ε (measured (1 + ε) τ).",
);

/// The largest relative gain error a torque sensor's or a motor's torque
/// constant's calibration is taken to have.
const MAX_GAIN_ERROR: f64 = 0.3;

impl Effect for TorqueGain {
    fn name(&self) -> &'static str {
        "torque_gain"
    }

    fn motion(&self) -> &'static str {
        "large torques of every kind on the same joint (gravity, inertia and friction together)"
    }

    fn summary(&self) -> &'static str {
        "A torque-constant (gain) error"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![GAIN_ERROR]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        truth.set_gain(1.0 + p.get(GAIN_ERROR.name)?);
        Ok(())
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, shape.joints)
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let th = cx.nominal_torques()?;
        Ok(Hypothesis::per_joint(cx.per_joint(|k, i| th[k][i])))
    }

    /// A gain error beyond ±[`MAX_GAIN_ERROR`] is no calibration error.
    fn implausible(&self, _: &Columns, _: usize, beta: f64) -> Option<String> {
        (beta.abs() > MAX_GAIN_ERROR).then(|| {
            format!("a gain error of {:.0} %, beyond ±{:.0} %", 100.0 * beta, 100.0 * MAX_GAIN_ERROR)
        })
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        cx.per_joint(beta, "gain error", "%", 100.0)
    }
}
