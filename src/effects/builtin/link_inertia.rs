//! `link_inertia`: the links' inertias are off. The true robot's links are
//! the model's scaled by `1 + s` (every parameter, so they stay physically
//! consistent); the diagnosis proposes a correction of every link's 10
//! parameters (each kept consistent), in the optional `inertial` part of
//! the memory plan.

use super::rotor_inertia::nominal_bodies;
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Size,
    SizeContext, Values,
};
use crate::sim::Truth;

/// The links' inertias.
pub struct LinkInertia;

const ERROR: ParamSpec = ParamSpec::new(
    "link_inertia_error",
    "1",
    0.1,
    Range::Above(-1.0),
    "Relative error s of the links' inertial parameters: the true links are (1 + s) × the model's.",
);

impl Effect for LinkInertia {
    fn name(&self) -> &'static str {
        "link_inertia"
    }

    fn motion(&self) -> &'static str {
        "varied accelerations and configurations of every joint"
    }

    fn summary(&self) -> &'static str {
        "The links' inertial parameters differ from the model's"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![ERROR]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        truth.scale_link_inertias(1.0 + p.get(ERROR.name)?);
        Ok(())
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::optional(shape, 10 * shape.joints, "inertial", 0)
    }

    /// Per link, the change of its mass (kg).
    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        let names = cx.model.body_names();
        (0..beta.len() / 10)
            .map(|b| Size::new(format!("mass change, {}", names[b]), "kg", beta[10 * b]))
            .collect()
    }

    fn changes_nominal_bodies(&self) -> bool {
        true
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let links = cx.model.dof();
        let cols = cx.regressor_columns(10 * links, |y, i, c| y[(i, c)])?;
        Ok(Hypothesis::single(Columns {
            cols,
            bodies: nominal_bodies(cx, 0..links),
            into_bodies: (0..links).collect(),
            ..Columns::default()
        }))
    }
}
