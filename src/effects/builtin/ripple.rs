//! `ripple`: a torque ripple periodic in the joint angle, `A sin(p qᵢ)` on
//! every revolute joint without a modelled rotor (a harmonic drive's wave
//! generator, a sensor's eccentricity: `p` periods per joint turn; a joint
//! with a rotor has `cogging`, periodic in the motor angle). Diagnosed on
//! a grid of periods per joint turn, each a sine and a cosine column per
//! such joint (an amplitude and a phase each) whose motion over the
//! training part covers at least one period.

use crate::dynamics::{JointKind, Model};
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Size,
    SizeContext, Values,
};
use crate::sim::Truth;

/// Position-periodic torque ripple.
pub struct Ripple;

const AMPLITUDE: ParamSpec = ParamSpec::new(
    "ripple_amplitude",
    "N·m",
    0.5,
    Range::Any,
    "Ripple amplitude A.",
);
const PERIOD: ParamSpec = ParamSpec::new(
    "ripple_period",
    "1/turn",
    5.0,
    Range::Positive,
    "Ripple periods p per joint turn.",
);
/// The periods per joint turn the diagnosis tries, the first to the last
/// (one and two per turn are the rigid body's own shapes: a gravity torque
/// `sin q`, an inertia product's `sin q cos q`).
const PERIODS: (usize, usize) = (3, 14);

/// The periods a joint's motion must cover for a ripple on it to be
/// proposed.
const MIN_PERIODS: f64 = 1.0;

/// The joints a ripple can be on: revolute, without a rotor.
fn ripple_joints(model: &Model) -> Vec<usize> {
    (0..model.dof())
        .filter(|&i| model.joints[i].kind == JointKind::Revolute && model.rotor_of(i).is_none())
        .collect()
}

impl Effect for Ripple {
    fn name(&self) -> &'static str {
        "ripple"
    }

    fn motion(&self) -> &'static str {
        "slow steady rotation over several motor turns"
    }

    fn summary(&self) -> &'static str {
        "Torque ripple periodic in the joint angle (joints without a rotor)"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![AMPLITUDE, PERIOD]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let (a, per) = (p.get(AMPLITUDE.name)?, p.get(PERIOD.name)?);
        let on = ripple_joints(&truth.robot().model);
        truth.add_torque(move |s| {
            if on.contains(&s.joint) {
                a * (per * s.q).sin()
            } else {
                0.0
            }
        });
        Ok(())
    }

    fn inapplicable(&self, model: &Model) -> Option<&'static str> {
        ripple_joints(model)
            .is_empty()
            .then_some("every joint has a rotor or is prismatic: cogging is its ripple")
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, 2 * (PERIODS.1 - PERIODS.0 + 1) * shape.joints)
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        cx.amplitudes(beta, "ripple amplitude", "N·m")
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let d = cx.data;
        let span: Vec<(usize, f64)> = ripple_joints(cx.model)
            .into_iter()
            .map(|j| {
                // on the training part: what the fit sees
                let train = (0..cx.train.min(d.len())).map(|k| d.q[k][j]);
                let (lo, hi) = train.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
                    (a.min(q), b.max(q))
                });
                (j, hi - lo)
            })
            .collect();
        let variants = (PERIODS.0..=PERIODS.1)
            .filter_map(|p| {
                let p = p as f64;
                let column =
                    |trig: fn(f64) -> f64, j: usize| cx.joint_column(j, |k| trig(p * d.q[k][j]));
                // a joint that moves less than a period: a ripple there
                // is any smooth function of q (an offset, a slope)
                let on: Vec<usize> = (span.iter())
                    .filter(|(_, range)| p * range >= 2.0 * MIN_PERIODS * std::f64::consts::PI)
                    .map(|&(j, _)| j)
                    .collect();
                let cols: Vec<Vec<f64>> = (on.iter())
                    .flat_map(|&j| [column(f64::sin, j), column(f64::cos, j)])
                    .collect();
                (!cols.is_empty()).then(|| {
                    Columns::variant(format!("{p} periods per joint turn"), cols, 1)
                        .in_joints(on.iter().flat_map(|&j| [j, j]))
                        .keyed("periods_per_turn", p)
                })
            })
            .collect();
        Ok(Hypothesis::grid(variants))
    }
}
