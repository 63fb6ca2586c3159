//! `rotor_inertia`: the rotors' reflected inertia and gyroscopic terms. The
//! true robot has the description's rotors; the diagnosis proposes a
//! correction of every rotor's 10 parameters (each kept physically
//! consistent), in the optional `inertial` part of the memory plan.

use crate::effects::{
    Columns, Context, Effect, EffectError, Hypothesis, Memory, Shape, Size, SizeContext, Values,
};
use crate::sim::{SimWarning, Truth};

/// The rotors' inertia.
pub struct RotorInertia;

impl Effect for RotorInertia {
    fn name(&self) -> &'static str {
        "rotor_inertia"
    }

    fn motion(&self) -> &'static str {
        "large accelerations of the geared joints"
    }

    fn summary(&self) -> &'static str {
        "The rotors' reflected inertia and gyroscopic terms"
    }

    fn apply(&self, _: &Values, truth: &mut Truth) -> Result<(), EffectError> {
        if truth.robot().model.rotors.is_empty() {
            truth.warn(SimWarning::Inert {
                effect: self.name().into(),
                why: "the robot has no rotors",
            });
        }
        truth.include_rotors();
        Ok(())
    }

    fn inapplicable(&self, model: &crate::dynamics::Model) -> Option<&'static str> {
        model
            .rotors
            .is_empty()
            .then_some("not proposed: the model has no rotors")
    }

    fn memory(&self, shape: &Shape) -> Memory {
        let rotors = shape.bodies - shape.joints;
        Memory::optional(shape, 10 * rotors, "inertial", 0)
    }

    /// Per rotor, the change of its axial inertia `I_zz` (kg·m²).
    fn sizes(&self, _: &Columns, beta: &[f64], cx: &SizeContext) -> Vec<Size> {
        let names = cx.model.body_names();
        let links = cx.model.dof();
        (0..beta.len() / 10)
            .map(|b| {
                let name = format!("axial inertia change, {}", names[links + b]);
                Size::new(name, "kg·m²", beta[10 * b + 9])
            })
            .collect()
    }

    fn changes_nominal_bodies(&self) -> bool {
        true
    }

    fn hypothesis(&self, cx: &Context) -> Result<Hypothesis, EffectError> {
        let (links, bodies) = (cx.model.dof(), cx.model.num_bodies());
        if bodies == links {
            return Ok(Hypothesis::none());
        }
        let nl = 10 * links;
        let cols = cx.regressor_columns(10 * (bodies - links), |y, i, c| y[(i, nl + c)])?;
        Ok(Hypothesis::single(Columns {
            cols,
            bodies: nominal_bodies(cx, links..bodies),
            into_bodies: (links..bodies).collect(),
            ..Columns::default()
        }))
    }
}

/// The nominal parameters of `bodies` (links then rotors), 10 each.
pub fn nominal_bodies(cx: &Context, bodies: std::ops::Range<usize>) -> Vec<[f64; 10]> {
    let p = cx.model.params();
    bodies
        .map(|b| std::array::from_fn(|k| p[10 * b + k]))
        .collect()
}
