//! `joint_offset`: an encoder zero offset, the measured position the true
//! one minus δ (a calibration error; true q = measured q + δ). Diagnosed to
//! first order: per joint j the column `∂τ̂/∂q_j` (central difference,
//! h = 10⁻⁴ rad or m), whose coefficient is δ_j; the report gives the
//! offsets, and one beyond 0.2 rad (or m) is doubtful.

use crate::dynamics::predict::predict_torques;
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Size, SizeContext, Values,
};
use crate::sim::Truth;

/// An encoder zero offset.
pub struct JointOffset;

const OFFSET: ParamSpec = ParamSpec::new(
    "joint_offset",
    "rad or m",
    0.05,
    Range::Within(-0.5, 0.5),
    "Encoder zero offset δ, every joint: true q = measured q + δ.",
);
/// The largest encoder zero offset (rad or m) a calibration error is taken
/// to have.
const MAX_JOINT_OFFSET: f64 = 0.2;
/// The central difference's step (rad or m).
const H: f64 = 1e-4;

impl Effect for JointOffset {
    fn name(&self) -> &'static str {
        "joint_offset"
    }

    fn motion(&self) -> &'static str {
        "large position excursions against gravity"
    }

    fn summary(&self) -> &'static str {
        "An encoder zero offset: the measured position is the true one minus a constant (a calibration error)"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![OFFSET]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        truth.offset_positions(p.get(OFFSET.name)?);
        Ok(())
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let d = cx.data;
        let cols = (0..cx.joints())
            .map(|j| {
                let at = |s: f64| {
                    let mut q = d.q.clone();
                    q.iter_mut().for_each(|q| q[j] += s);
                    q
                };
                let plus = predict_torques(cx.model, cx.friction, &at(H), &d.qd, &d.qdd)?;
                let minus = predict_torques(cx.model, cx.friction, &at(-H), &d.qd, &d.qdd)?;
                Ok(plus
                    .iter()
                    .flatten()
                    .zip(minus.iter().flatten())
                    .map(|(a, b)| (a - b) / (2.0 * H))
                    .collect())
            })
            .collect::<Result<Vec<Vec<f64>>, EffectError>>()?;
        Ok(Hypothesis::single(Columns::linear(cols)))
    }

    fn implausible(&self, _: &Columns, _: usize, beta: f64) -> Option<String> {
        (beta.abs() > MAX_JOINT_OFFSET).then(|| {
            format!("an encoder offset of {beta:.3} rad (or m), beyond {MAX_JOINT_OFFSET}: more than a calibration error")
        })
    }

    fn doubt(&self, _: &Columns, beta: &[f64], joints: &[String]) -> Option<String> {
        let (j, b) = beta
            .iter()
            .enumerate()
            .find(|(_, b)| b.abs() > MAX_JOINT_OFFSET)?;
        Some(format!(
            "the offset of joint '{}' is {b:.3} rad (or m), beyond {MAX_JOINT_OFFSET}: more than a calibration error",
            joints.get(j).map_or("?", String::as_str)
        ))
    }

    fn detail(&self, _: &Columns, beta: &[f64]) -> String {
        let d: Vec<String> = beta.iter().map(|b| format!("{b:.3}")).collect();
        format!("δ = ({}) rad or m, true q = measured q + δ", d.join(", "))
    }

    fn fitted(&self, _: &Columns, beta: &[f64]) -> Vec<(&'static str, Vec<f64>)> {
        vec![("joint_offsets", beta.to_vec())]
    }

    /// Per joint, the offset δ_j (rad or m; true q = measured q + δ).
    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        (beta.iter().enumerate())
            .filter(|(_, b)| **b != 0.0)
            .map(|(j, b)| Size::new(format!("encoder offset, {}", cx.joint(j)), "rad", *b))
            .collect()
    }
}
