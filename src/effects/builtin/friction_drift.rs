//! `friction_drift`: friction that changes as the drives warm, the true
//! robot's Coulomb and viscous friction scaled by `1 + r t` (t in minutes
//! since the record began). Diagnosed with one column per joint, `(t −
//! t̄)·f_i`: the nominal model's friction torque f_i times the time from
//! the training part's mean t̄ — a constant error of the friction's size
//! is `coulomb`'s or `viscous`'s and barely projects on it. (The diagnosis
//! lets every velocity-dependent term of the nominal law drift alike —
//! Stribeck and load friction too — where the simulator drifts the two it
//! scales.)

use crate::dynamics::{FrictionTerm, sign};
use crate::effects::{Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Values};
use crate::sim::Truth;

/// Friction drift over time.
pub struct FrictionDrift;

const RATE: ParamSpec = ParamSpec::new(
    "friction_drift",
    "1/min",
    -0.4,
    Range::Within(-10.0, 10.0),
    "Relative change r of Coulomb and viscous friction per minute (negative: falls as the drives warm).",
);

impl Effect for FrictionDrift {
    fn name(&self) -> &'static str {
        "friction_drift"
    }

    fn summary(&self) -> &'static str {
        "Friction that drifts with time (drives warming)"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![RATE]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let r = p.get(RATE.name)? / 60.0;
        let f = truth.friction_mut();
        let c = f.coefficients(FrictionTerm::Coulomb).to_vec();
        let v = f.coefficients(FrictionTerm::Viscous).to_vec();
        let at = |x: &[f64], j: usize| x.get(j).copied().unwrap_or(0.0);
        truth.add_torque(move |s| {
            r * s.t * (at(&c, s.joint) * sign(s.qd) + at(&v, s.joint) * s.qd)
        });
        Ok(())
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, shape.joints)
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let (d, f) = (cx.data, cx.friction);
        let load = !f.coefficients(FrictionTerm::Load).iter().all(|c| *c == 0.0);
        let tau = if load { Some(cx.nominal_torques()?) } else { None };
        let friction = |k: usize, i: usize| {
            let offset = f.coefficients(FrictionTerm::Offset).get(i).copied().unwrap_or(0.0);
            f.torque(i, d.qd[k][i], tau.map_or(0.0, |t| t[k][i])) - offset
        };
        let moving: Vec<usize> = (0..cx.joints())
            .filter(|&i| (0..cx.samples()).any(|k| friction(k, i) != 0.0))
            .collect();
        if moving.is_empty() {
            return Ok(Hypothesis::none());
        }
        if cx.samples() == 0 {
            return Ok(Hypothesis::none());
        }
        let train = cx.train.min(cx.samples()).max(1);
        let mean_t = d.t[..train].iter().sum::<f64>() / train as f64;
        let cols = moving
            .iter()
            .map(|&i| cx.joint_column(i, |k| (d.t[k] - mean_t) / 60.0 * friction(k, i)))
            .collect();
        Ok(Hypothesis::linear(cols))
    }
}
