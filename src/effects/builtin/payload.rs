//! `payload`: an unmodelled rigid body carried at the model's tool point
//! (a sidecar's `[tool]`; without one, on the last link). The simulator
//! adds a point mass at the tool point; the diagnosis proposes a rigid body
//! of its own on the tool's link — its 10 parameters, the regressor columns
//! of that link, with its pseudo-inertia `J ⪰ 0` (the paper's LMI applied
//! to the payload; a point mass is the special case of rank one) — and
//! reports its mass, its centre of mass from the tool point and its
//! inertia about that centre.

use crate::dynamics::Model;
use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, ParamSpec, Range, Shape, Size,
    SizeContext, Values,
};
use crate::moments::InertialParams;
use crate::sim::Truth;
use nalgebra::{Matrix3, Vector3};

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

/// The body a payload is on and the point it is measured from (in that
/// body's frame): the tool point, else the last link's origin; and
/// whether it is the tool.
pub fn carrier(model: &Model) -> Option<(usize, Vector3<f64>, bool)> {
    match model.tool {
        Some(t) => Some((t.body, t.point, true)),
        None => model.dof().checked_sub(1).map(|b| (b, Vector3::zeros(), false)),
    }
}

/// Where the payload's sizes are given from, in words.
fn from_where(model: &Model) -> String {
    match carrier(model) {
        Some((_, _, true)) => "from the tool point".into(),
        Some((b, _, false)) => format!(
            "from the origin of the last link '{}' (the model has no tool point)",
            model.body_names()[b]
        ),
        None => String::new(),
    }
}

impl Effect for Payload {
    fn name(&self) -> &'static str {
        "payload"
    }

    fn motion(&self) -> &'static str {
        "large accelerations and rotations of the tool"
    }

    fn summary(&self) -> &'static str {
        "An unmodelled rigid body at the tool point (or on the last link)"
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

    fn inapplicable(&self, model: &Model) -> Option<&'static str> {
        carrier(model).is_none().then_some(NO_TOOL)
    }

    fn memory(&self, shape: &Shape) -> Memory {
        Memory::columns(shape, 10)
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let Some((body, _, _)) = carrier(cx.model) else {
            return Ok(Hypothesis::none());
        };
        let b = 10 * body;
        let cols = cx.regressor_columns(10, |y, i, c| y[(i, b + c)])?;
        Ok(Hypothesis::single(Columns {
            cols,
            bodies: vec![[0.0; 10]],
            into_bodies: vec![body],
            ..Columns::default()
        }))
    }

    /// Its mass (kg), its centre of mass from the tool point (m, in the
    /// tool link's frame) and its principal moments about that centre
    /// (kg·m²).
    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        let Some((_, point, _)) = carrier(cx.model) else {
            return vec![];
        };
        let body = InertialParams(std::array::from_fn(|k| beta.get(k).copied().unwrap_or(0.0)));
        let m = body.mass();
        let c = if m > 1e-9 { body.com() - point } else { Vector3::zeros() };
        let moments = if m > 1e-9 {
            let mut v: Vec<f64> = body.inertia_com().symmetric_eigenvalues().iter().copied().collect();
            v.sort_by(f64::total_cmp);
            v
        } else {
            vec![0.0; 3]
        };
        let at = from_where(cx.model);
        let mut out = vec![Size::new("payload mass", "kg", m)];
        for (axis, v) in ["x", "y", "z"].iter().zip(c.iter()) {
            out.push(Size::new(format!("payload centre of mass {axis}, {at}"), "m", *v));
        }
        for (k, v) in moments.iter().enumerate() {
            out.push(Size::new(format!("payload principal moment {}", k + 1), "kg·m²", *v));
        }
        out
    }
}
