//! `cogging`: motor cogging, `A sin(p N qᵢ)`, periodic in the motor angle
//! (N the gear ratio). Diagnosed on a grid of periods per motor turn, each a
//! sine and a cosine column per joint; needs a rotor on some joint.

use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Size,
    SizeContext, Values,
};
use crate::effects::compliance::has_motor_side;
use crate::sim::Truth;

/// Motor cogging.
pub struct Cogging;

const AMPLITUDE: ParamSpec = ParamSpec::new(
    "cogging_amplitude",
    "N·m",
    0.2,
    Range::Any,
    "Cogging amplitude A.",
);
const PERIOD: ParamSpec = ParamSpec::new(
    "cogging_period",
    "1/turn",
    6.0,
    Range::Positive,
    "Cogging periods p per motor turn.",
);
/// The periods per motor turn the diagnosis tries: 1 … this.
const PERIODS: usize = 12;

impl Effect for Cogging {
    fn name(&self) -> &'static str {
        "cogging"
    }

    fn motion(&self) -> &'static str {
        "slow steady rotation over many motor turns"
    }

    fn summary(&self) -> &'static str {
        "Motor cogging, periodic in the motor angle"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![AMPLITUDE, PERIOD]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let (a, per) = (p.get(AMPLITUDE.name)?, p.get(PERIOD.name)?);
        truth.add_torque(move |s| a * (per * s.gear * s.q).sin());
        Ok(())
    }

    fn inapplicable(&self, model: &crate::dynamics::Model) -> Option<&'static str> {
        (!has_motor_side(model)).then_some(super::elasticity::NO_MOTOR_SIDE)
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, 2 * PERIODS * shape.joints)
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        cx.amplitudes(beta, "cogging amplitude", "N·m")
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let d = cx.data;
        let gear: Vec<f64> = (0..cx.joints()).map(|i| cx.gear(i)).collect();
        let variants = (1..=PERIODS)
            .map(|p| {
                let p = p as f64;
                let mut cols = cx.per_joint(|k, i| (p * gear[i] * d.q[k][i]).sin());
                cols.extend(cx.per_joint(|k, i| (p * gear[i] * d.q[k][i]).cos()));
                let n = cx.joints();
                Columns::variant(format!("period {p} per motor turn"), cols, 1)
                    .in_joints((0..n).chain(0..n))
                    .keyed("periods_per_motor_turn", p)
            })
            .collect();
        Ok(Hypothesis::grid(variants))
    }
}
