//! `time_delay`: the torque is measured at the state `δ` seconds earlier.
//! Diagnosed on a grid of delays of whole samples: per joint the column
//! `τ̂ᵢ(t − s·dt) − τ̂ᵢ(t)` (first order in the nominal model's torque),
//! whose coefficient is 1 on a joint whose torque is that late (one
//! sensor's filter or bus) and 0 on one that is not.

use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Values,
};
use crate::sim::Truth;

/// A delay between state and torque.
pub struct TimeDelay;

const DELAY: ParamSpec = ParamSpec::new(
    "delay",
    "s",
    0.005,
    Range::Within(0.0, 1.0),
    "Delay δ between state and torque.",
);
/// The delays, in samples, the diagnosis tries (those within
/// [`MAX_DELAY`]; the first always).
const SHIFTS: [usize; 8] = [1, 2, 3, 5, 8, 12, 20, 30];
/// The longest delay (s) a torque measurement is taken to have: a
/// sensor's filter and a bus, not the tens of samples of a slow log, where
/// a long shift is a smoothed derivative that absorbs any dynamic mismatch.
const MAX_DELAY: f64 = 0.05;

impl Effect for TimeDelay {
    fn name(&self) -> &'static str {
        "time_delay"
    }

    fn summary(&self) -> &'static str {
        "A delay between the measured state and the measured torque"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![DELAY]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        truth.set_delay(p.get(DELAY.name)?);
        Ok(())
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, SHIFTS.len() * shape.joints)
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let d = cx.data;
        let th = cx.nominal_torques()?;
        let dt = if d.len() > 1 {
            (d.t[d.len() - 1] - d.t[0]) / (d.len() - 1) as f64
        } else {
            1e-3
        };
        let variants = SHIFTS
            .iter()
            .enumerate()
            .filter(|&(j, &s)| j == 0 || s as f64 * dt <= MAX_DELAY * (1.0 + 1e-9))
            .map(|(_, &s)| {
                let cols = cx.per_joint(|k, i| th[k.saturating_sub(s)][i] - th[k][i]);
                let ms = 1e3 * s as f64 * dt;
                Columns::variant(format!("delay {ms:.0} ms"), cols, 1)
            })
            .collect();
        Ok(Hypothesis::grid(variants))
    }
}
