//! [`Solved`]: the solver's answer, read by body and joint name, and the
//! names of the identified parameters.

use super::error::{IdentifyError, unknown};
use crate::conic::Status;
use crate::dynamics::{Friction, FrictionTerm, Model};

/// The solver's answer.
#[derive(Clone, Debug)]
pub struct Solved {
    /// θ = [π (links, rotors) | one block of n per friction term of
    /// `terms`]; read it by name with [`Solved::body`] and
    /// [`Solved::friction_coefficient`].
    pub theta: Vec<f64>,
    /// The friction terms identified (the model's
    /// [`Model::friction_terms`]).
    pub terms: Vec<FrictionTerm>,
    /// Body names, in parameter order.
    pub bodies: Vec<String>,
    /// Joint names.
    pub joints: Vec<String>,
    /// Solver status (`solved` for the direct least squares).
    pub status: Status,
    /// Interior-point iterations (0 for the direct solve).
    pub iterations: u32,
    /// Solve time (s).
    pub solve_time_s: f64,
    /// What the data can tell: rank, base parameters, their standard
    /// deviations, the parameters that enter no torque.
    pub identifiability: super::identifiability::Identifiability,
}

/// Parameter names: `<body>.<m|hx|…>`, then `<term>.<joint>` for each
/// friction term of the model (`viscous.<joint>`, `coulomb.<joint>`, …).
pub fn parameter_names(model: &Model) -> Vec<String> {
    model.layout().parameter_names()
}

impl Solved {
    /// The parameters of the body named `name`.
    pub fn body(&self, name: &str) -> Result<crate::moments::InertialParams, IdentifyError> {
        let b = self
            .bodies
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| unknown("body", name, self.bodies.iter().map(String::as_str)))?;
        Ok(crate::moments::InertialParams(std::array::from_fn(|k| {
            self.theta[10 * b + k]
        })))
    }

    /// Joint `joint`'s coefficient of the friction term `term` (0 for a
    /// term not identified).
    pub fn friction_coefficient(
        &self,
        term: FrictionTerm,
        joint: &str,
    ) -> Result<f64, IdentifyError> {
        let i = self
            .joints
            .iter()
            .position(|n| n == joint)
            .ok_or_else(|| unknown("joint", joint, self.joints.iter().map(String::as_str)))?;
        let (nb, n) = (self.bodies.len(), self.joints.len());
        Ok(match self.terms.iter().position(|&t| t == term) {
            Some(k) => self.theta[10 * nb + k * n + i],
            None => 0.0,
        })
    }

    /// Joint `joint`'s friction `(viscous B, Coulomb B_c)`.
    pub fn friction(&self, joint: &str) -> Result<(f64, f64), IdentifyError> {
        Ok((
            self.friction_coefficient(FrictionTerm::Viscous, joint)?,
            self.friction_coefficient(FrictionTerm::Coulomb, joint)?,
        ))
    }

    /// The identified friction of every joint (a Stribeck term's velocity:
    /// `stribeck_velocity`, the model's).
    pub fn friction_law(&self, stribeck_velocity: f64) -> Friction {
        let (nb, n) = (self.bodies.len(), self.joints.len());
        let basis = (self.terms.as_slice(), stribeck_velocity);
        Friction::from_terms(n, basis, |k, i| self.theta[10 * nb + k * n + i])
    }
}
