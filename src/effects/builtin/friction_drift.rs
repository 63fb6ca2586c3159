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
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Size,
    SizeContext, Values,
};
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

    fn motion(&self) -> &'static str {
        "a long run, or runs repeated as the robot warms up"
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
        if cx.samples() == 0 {
            return Ok(Hypothesis::none());
        }
        let train = cx.train.min(cx.samples()).max(1);
        let mean_t = cx.data.t[..train].iter().sum::<f64>() / train as f64;
        Ok(drift(cx, mean_t)?.map_or_else(Hypothesis::none, Hypothesis::single))
    }

    /// The drift from the recorded reference time `t_ref_s`.
    fn replay(&self, cx: &Context, key: &[(String, f64)]) -> Result<Columns, EffectError> {
        let t_ref = key.iter().find(|(k, _)| k == "t_ref_s").map(|(_, v)| *v);
        let none = |why: &str| EffectError::NotReplayable {
            effect: self.name().into(),
            key: why.into(),
        };
        let t_ref = t_ref.ok_or_else(|| none("no t_ref_s"))?;
        drift(cx, t_ref)?.ok_or_else(|| none("no joint with friction on these data"))
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        cx.per_joint(beta, "friction drift", "1/min", 1.0)
    }
}

/// Per joint with friction, `(t − t_ref)/60 · f̂ᵢ`: the nominal friction
/// torque (every term but the offset) times the minutes from `t_ref`;
/// `None` when no joint has friction on these data.
fn drift(cx: &Context, t_ref: f64) -> Result<Option<Columns>, EffectError> {
    let (d, f) = (cx.data, cx.friction);
    let load = !f.coefficients(FrictionTerm::Load).iter().all(|c| *c == 0.0);
    let tau = if load { Some(cx.rigid_torques()?) } else { None };
    let friction = |k: usize, i: usize| {
        let offset = f.coefficients(FrictionTerm::Offset).get(i).copied().unwrap_or(0.0);
        f.torque(i, d.qd[k][i], tau.map_or(0.0, |t| t[k][i])) - offset
    };
    let moving: Vec<usize> = (0..cx.joints())
        .filter(|&i| (0..cx.samples()).any(|k| friction(k, i) != 0.0))
        .collect();
    if moving.is_empty() {
        return Ok(None);
    }
    let cols = moving
        .iter()
        .map(|&i| cx.joint_column(i, |k| (d.t[k] - t_ref) / 60.0 * friction(k, i)))
        .collect();
    Ok(Some(Columns::linear(cols).in_joints(moving).keyed("t_ref_s", t_ref)))
}
