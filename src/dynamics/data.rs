//! Per-evaluation workspace (Pinocchio's `Data`): every buffer an algorithm
//! writes, allocated once by [`Data::new`].

use super::model::Model;
use super::spatial::Transform;
use nalgebra::{DMatrix, DVector, Matrix6, SMatrix, Vector6};

/// 6 × 10 body regressor block: `f = A(v, a) π`.
pub type BodyRegressor = SMatrix<f64, 6, 10>;

/// Buffers for one model. Algorithms overwrite what their docs say.
#[derive(Clone, Debug)]
pub struct Data {
    /// `X_up[i]`: parent body frame → body i at the current q.
    pub x_up: Vec<Transform>,
    /// Body spatial velocities (body frames).
    pub v: Vec<Vector6<f64>>,
    /// Body spatial accelerations, including −gravity at the base (body frames).
    pub a: Vec<Vector6<f64>>,
    /// Net body forces, then (after the backward pass) forces transmitted by each joint.
    pub f: Vec<Vector6<f64>>,
    /// Rotor transforms (parent body → spun rotor frame).
    pub x_rotor: Vec<Transform>,
    /// Rotor velocities.
    pub v_rotor: Vec<Vector6<f64>>,
    /// Rotor accelerations.
    pub a_rotor: Vec<Vector6<f64>>,
    /// Rotor forces.
    pub f_rotor: Vec<Vector6<f64>>,
    /// Generalized force from [`rnea`](super::rnea) ([`Model::nv`]: a
    /// free flyer's base wrench, force then moment in base coordinates,
    /// then the joint torques / forces).
    pub tau: DVector<f64>,
    /// Mass matrix from [`crba`](super::crba) (nv × nv).
    pub mass_matrix: DMatrix<f64>,
    /// Composite inertias (CRBA).
    pub ic: Vec<Matrix6<f64>>,
    /// Per body: base frame → body frame (a free flyer's algorithms).
    pub x_base: Vec<Transform>,
    /// Regressor (nv × [`Model::regressor_columns`]) from
    /// [`regressor`](super::regressor).
    pub regressor: DMatrix<f64>,
    /// Per joint, the load (N·m) the regressor's `load` friction column
    /// is scaled by ([`FrictionTerm::Load`](super::FrictionTerm::Load)):
    /// the caller sets it before [`regressor`](super::regressor) (the
    /// identification: the measured torques). NaN until set, so that a
    /// regressor of a model with that term is not finite until it is.
    pub load: Vec<f64>,
    /// Per body: the axes of the joints that move it, in its frame.
    pub(crate) axes: Vec<Vec<(usize, Vector6<f64>)>>,
}

impl Data {
    /// Buffers sized for `model`.
    pub fn new(model: &Model) -> Self {
        let (n, nv) = (model.dof(), model.nv());
        let nr = model.rotors.len();
        let z = Vector6::zeros();
        Self {
            x_up: vec![Transform::identity(); n],
            v: vec![z; n],
            a: vec![z; n],
            f: vec![z; n],
            x_rotor: vec![Transform::identity(); nr],
            v_rotor: vec![z; nr],
            a_rotor: vec![z; nr],
            f_rotor: vec![z; nr],
            tau: DVector::zeros(nv),
            mass_matrix: DMatrix::zeros(nv, nv),
            ic: vec![Matrix6::zeros(); n],
            x_base: vec![Transform::identity(); n],
            regressor: DMatrix::zeros(nv, model.regressor_columns()),
            load: vec![f64::NAN; n],
            axes: (0..n).map(|_| Vec::with_capacity(n)).collect(),
        }
    }
}
