//! `backlash`: a dead band of half-width b in a compliant transmission
//! (as `elasticity`, whose stiffness and damping it shares). The diagnosis
//! searches the dead band too.

use super::elasticity::{DAMPING, NO_MOTOR_SIDE, STIFFNESS, memory, searched, transmission};
use crate::dynamics::Model;
use crate::effects::compliance::has_motor_side;
use crate::effects::{
    Columns,
    Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Values,
};
use crate::sim::Truth;

/// Backlash in a compliant transmission.
pub struct Backlash;

const WIDTH: ParamSpec = ParamSpec::new(
    "backlash_width",
    "rad",
    0.005,
    Range::NonNegative,
    "Dead-band half-width b.",
);

impl Effect for Backlash {
    fn name(&self) -> &'static str {
        "backlash"
    }

    fn motion(&self) -> &'static str {
        "velocity reversals under a small load"
    }

    fn summary(&self) -> &'static str {
        "Backlash (a dead band) in a compliant transmission"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![WIDTH, STIFFNESS, DAMPING]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        truth.set_compliance(transmission(p, p.get(WIDTH.name)?)?);
        Ok(())
    }

    fn inapplicable(&self, model: &Model) -> Option<&'static str> {
        (!has_motor_side(model)).then_some(NO_MOTOR_SIDE)
    }

    fn memory(&self, shape: &Shape) -> Memory {
        memory(shape)
    }

    fn expense(&self) -> u32 {
        2
    }

    fn prepare(&self, cx: &Context) {
        let _ = cx.linearisation();
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        searched(cx, true)
    }

    fn replay(&self, cx: &Context, key: &[(String, f64)]) -> Result<Columns, EffectError> {
        super::elasticity::replayed(cx, key, true, self.name())
    }
}
