//! `stribeck`: extra friction near zero velocity,
//! `F_s e^{−(q̇ᵢ/v_s)²} sign(q̇ᵢ)` on every joint. Diagnosed on a grid of
//! Stribeck velocities, open at both ends (a smaller or a larger v_s than
//! the grid's can hide beyond it).

use crate::dynamics::{FrictionTerm, sign};
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Size,
    SizeContext, Values,
};
use crate::sim::Truth;

/// Stribeck friction.
pub struct Stribeck;

const FORCE: ParamSpec = ParamSpec::new(
    "stribeck_force",
    "N·m",
    1.0,
    Range::Any,
    "Stribeck peak F_s.",
);
const VELOCITY: ParamSpec = ParamSpec::new(
    "stribeck_velocity",
    "rad/s",
    0.2,
    Range::Positive,
    "Stribeck velocity v_s.",
);
/// The Stribeck velocities (rad/s) the diagnosis tries.
const GRID: [f64; 4] = [0.05, 0.1, 0.2, 0.5];

impl Effect for Stribeck {
    fn name(&self) -> &'static str {
        "stribeck"
    }

    fn motion(&self) -> &'static str {
        "slow motion near zero velocity, below the Stribeck velocity"
    }

    fn law_term(&self) -> Option<FrictionTerm> {
        Some(FrictionTerm::Stribeck)
    }

    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        super::friction::term_sizes(beta, cx, FrictionTerm::Stribeck, "Stribeck friction F_s")
    }

    fn summary(&self) -> &'static str {
        "Stribeck friction (extra friction near zero velocity)"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![FORCE, VELOCITY]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let (f, vs) = (p.get(FORCE.name)?, p.get(VELOCITY.name)?);
        truth.add_torque(move |s| f * (-(s.qd / vs).powi(2)).exp() * sign(s.qd));
        Ok(())
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, GRID.len() * shape.joints)
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let d = cx.data;
        let variants = GRID
            .iter()
            .map(|&vs| {
                Columns::variant(
                    format!("Stribeck velocity {vs} rad/s"),
                    cx.per_joint(|k, i| (-(d.qd[k][i] / vs).powi(2)).exp() * sign(d.qd[k][i])),
                    1,
                )
                .in_joints(0..cx.joints())
                .keyed("stribeck_velocity", vs)
            })
            .collect();
        Ok(Hypothesis::grid(variants).open_below())
    }
}
