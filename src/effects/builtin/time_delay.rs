//! `time_delay`: the torque is measured at the state `δ` seconds earlier.
//! Diagnosed on a grid of delays of whole samples: per joint the column
//! `τ̂ᵢ(t − s·dt) − τ̂ᵢ(t)` (first order in the nominal model's torque),
//! whose coefficient is 1 on a joint whose torque is that late (one
//! sensor's filter or bus) and 0 on one that is not.

use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Size,
    SizeContext, Values,
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

/// The data's median step between samples within a file (s): files
/// logged at different times are segments whose gaps are no step.
fn step(cx: &Context) -> f64 {
    let d = cx.data;
    let mut steps: Vec<f64> = (d.segment_ranges().into_iter())
        .flat_map(|r| d.t[r].windows(2).map(|w| w[1] - w[0]).collect::<Vec<_>>())
        .filter(|x| *x > 0.0 && x.is_finite())
        .collect();
    if steps.is_empty() {
        return 1e-3;
    }
    let mid = steps.len() / 2;
    *steps.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// The variant of a delay of `s` samples of step `dt`: per joint
/// `τ̂ᵢ(t − s·dt) − τ̂ᵢ(t)`.
fn shifted(cx: &Context, s: usize, dt: f64) -> Result<Columns, EffectError> {
    let th = cx.nominal_torques()?;
    let cols = cx.per_joint(|k, i| th[k.saturating_sub(s)][i] - th[k][i]);
    let ms = 1e3 * s as f64 * dt;
    let c = Columns::variant(format!("delay {ms:.0} ms"), cols, 1).in_joints(0..cx.joints());
    Ok(c.keyed("delay_s", s as f64 * dt))
}

impl Effect for TimeDelay {
    fn name(&self) -> &'static str {
        "time_delay"
    }

    fn motion(&self) -> &'static str {
        "fast changes of torque (high-frequency motion)"
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
        let dt = step(cx);
        let variants = SHIFTS
            .iter()
            .enumerate()
            .filter(|&(j, &s)| j == 0 || s as f64 * dt <= MAX_DELAY * (1.0 + 1e-9))
            .map(|(_, &s)| shifted(cx, s, dt))
            .collect::<Result<_, _>>()?;
        Ok(Hypothesis::grid(variants))
    }

    /// The shift of whole samples of these data nearest the recorded delay.
    fn replay(&self, cx: &Context, key: &[(String, f64)]) -> Result<Columns, EffectError> {
        let dt = step(cx);
        let delay = (key.iter().find(|(k, _)| k == "delay_s")).map(|(_, v)| *v);
        match delay {
            Some(s) if s.is_finite() && s > 0.0 => shifted(cx, ((s / dt).round() as usize).max(1), dt),
            _ => Err(EffectError::NotReplayable {
                effect: self.name().into(),
                key: "no positive delay_s".into(),
            }),
        }
    }

    /// A delay (coefficient × shift) beyond ±1.5 × [`MAX_DELAY`] is no
    /// sensor's lag: the column absorbs another dynamic mismatch.
    fn implausible(&self, v: &Columns, _: usize, beta: f64) -> Option<String> {
        let delay = beta * v.key_value("delay_s").unwrap_or(0.0);
        (delay.abs() > 1.5 * MAX_DELAY).then(|| {
            format!("a delay of {:.0} ms, beyond ±{:.0} ms", 1e3 * delay, 1.5e3 * MAX_DELAY)
        })
    }

    /// Per joint, the delay `coefficient × shift` in ms: the first-order
    /// column's coefficient is the share of the shift the joint's torque lags.
    fn sizes(&self, v: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        let shift = v.key_value("delay_s").unwrap_or(0.0);
        cx.per_joint(beta, "delay", "ms", 1e3 * shift)
    }
}

#[cfg(test)]
mod step_tests {
    use super::*;
    use crate::data::Dataset;
    use crate::dynamics::{Friction, cheetah3};

    /// Two files logged 600 s apart at 200 Hz: the step is 5 ms, not the
    /// record's duration over its samples.
    #[test]
    fn the_step_ignores_the_gap_between_files() {
        let model = cheetah3::model();
        let names = model.joint_names();
        let file = |t0: f64| {
            let mut d = Dataset::empty(&names);
            for k in 0..200 {
                d.t.push(t0 + 0.005 * k as f64);
                for s in [&mut d.q, &mut d.qd, &mut d.qdd, &mut d.tau] {
                    s.push(&[0.0; 3]);
                }
            }
            d
        };
        let mut d = file(0.0);
        d.append_segment(file(600.0));
        assert_eq!(d.segment_ranges().len(), 2);
        let friction = Friction::zeros(3);
        let zeros = vec![0.0; d.len() * 3];
        let cx = Context::new(&model, &friction, &d, &zeros, d.len());
        assert!((step(&cx) - 0.005).abs() < 1e-12, "{}", step(&cx));
    }
}
