//! `time_delay`: the torque is measured at the state `δ` seconds earlier.
//! Diagnosed on a grid of delays of whole samples: the column is
//! `τ̂(t − s·dt) − τ̂(t)` (first order in the nominal model's torque).

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
/// The delays, in samples, the diagnosis tries.
const SHIFTS: [usize; 8] = [1, 2, 3, 5, 8, 12, 20, 30];

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
        Memory::columns(shape, SHIFTS.len())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let (d, n) = (cx.data, cx.joints());
        let th = cx.nominal_torques()?;
        let dt = if d.len() > 1 {
            (d.t[d.len() - 1] - d.t[0]) / (d.len() - 1) as f64
        } else {
            1e-3
        };
        let variants = SHIFTS
            .iter()
            .map(|&s| {
                let mut c = vec![0.0; d.len() * n];
                for k in 0..d.len() {
                    let j = k.saturating_sub(s);
                    for i in 0..n {
                        c[k * n + i] = th[j][i] - th[k][i];
                    }
                }
                let ms = 1e3 * s as f64 * dt;
                Columns::variant(format!("delay {ms:.0} ms"), vec![c], 1)
            })
            .collect();
        Ok(Hypothesis::grid(variants))
    }
}
