//! `payload`: an unmodelled point mass at the model's tool point (a
//! sidecar's `[tool]`). Diagnosed as one column, the torque of a unit mass
//! there, with a mass ≥ 0.

use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Values,
};
use crate::moments::InertialParams;
use crate::sim::Truth;
use nalgebra::Matrix3;

/// A payload at the tool point.
pub struct Payload;

const MASS: ParamSpec = ParamSpec::new(
    "payload_mass",
    "kg",
    0.5,
    Range::NonNegative,
    "Payload mass at the tool point.",
);

const NO_TOOL: &str = "the model has no tool point (no moving body to carry a payload)";

impl Effect for Payload {
    fn name(&self) -> &'static str {
        "payload"
    }

    fn summary(&self) -> &'static str {
        "An unmodelled point mass at the tool point"
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![MASS]
    }

    fn apply(&self, p: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        let tool = truth.robot().model.tool.ok_or(EffectError::NotApplicable {
            effect: self.name().into(),
            reason: NO_TOOL,
        })?;
        let mass = p.get(MASS.name)?;
        let point = InertialParams::from_mass_com_inertia(mass, tool.point, Matrix3::zeros());
        truth.add_inertia(tool.body, &point)?;
        Ok(())
    }

    fn inapplicable(&self, model: &crate::dynamics::Model) -> Option<&'static str> {
        model.tool.is_none().then_some(NO_TOOL)
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, 1)
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let Some(tool) = cx.model.tool else {
            return Ok(Hypothesis::none());
        };
        let unit = InertialParams::from_mass_com_inertia(1.0, tool.point, Matrix3::zeros());
        let b = 10 * tool.body;
        let cols = cx.regressor_columns(1, |y, i, _| {
            (0..10).map(|c| y[(i, b + c)] * unit.0[c]).sum()
        })?;
        Ok(Hypothesis::single(Columns {
            cols,
            nonneg: true,
            ..Columns::default()
        }))
    }
}
