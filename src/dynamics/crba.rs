//! Composite-rigid-body algorithm for the joint-space mass matrix, with
//! rotors, and forward dynamics on top of it.

use super::data::Data;
use super::error::DynamicsError;
use super::model::Model;
use super::rnea::check_len;
use super::spatial::Transform;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector6};

/// The 6×6 matrix of a motion transform.
pub fn transform_matrix(x: &Transform) -> Matrix6<f64> {
    let mut m = Matrix6::zeros();
    let ers = -x.e * crate::moments::skew(&x.r);
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&x.e);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&ers);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&x.e);
    m
}

fn spin_subspace(axis: &nalgebra::Vector3<f64>, n: f64) -> Vector6<f64> {
    Vector6::new(axis.x, axis.y, axis.z, 0.0, 0.0, 0.0) * n
}

/// The mass matrix `M(q)` (nv × nv, kg·m² for revolute joints; a free
/// flyer's base rows and columns first, in its (linear, angular) order)
/// into `data.mass_matrix`, by composite rigid bodies (the base's the
/// composite of the whole robot); `q` of length [`Model::nq`] (a free
/// flyer's quaternion checked). Also overwrites `data.x_up`,
/// `data.x_rotor`, `data.ic`.
pub fn crba<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
) -> Result<&'a DMatrix<f64>, DynamicsError> {
    check_len("q", q, model.nq())?;
    if model.is_floating() {
        model.base_pose(q)?;
    }
    let joints = &q[model.nq() - model.dof()..];
    let base = composite(model, data, joints);
    if model.is_floating() {
        const LIN_ANG: [usize; 6] = [3, 4, 5, 0, 1, 2];
        for r in 0..6 {
            for c in 0..6 {
                data.mass_matrix[(r, c)] = base[(LIN_ANG[r], LIN_ANG[c])];
            }
        }
    }
    Ok(&data.mass_matrix)
}

/// The joint block and a free flyer's base–joint coupling of the mass
/// matrix at joint positions `q` (n); returns the base's composite inertia
/// (spatial, base frame; zero for a fixed base, whose weld absorbs it).
fn composite(model: &Model, data: &mut Data, q: &[f64]) -> Matrix6<f64> {
    let (n, o) = (model.dof(), model.root_nv());
    for i in 0..n {
        data.x_up[i] = model.joint_transform(i, q[i]);
        data.ic[i] = model.joints[i].inertia.spatial();
    }
    for (k, r) in model.rotors.iter().enumerate() {
        data.x_rotor[k] = model.rotor_transform(k, q[r.joint]);
    }
    data.mass_matrix.fill(0.0);
    let mut base = model
        .base()
        .map_or(Matrix6::zeros(), |b| b.inertia.spatial());
    // rotors: their inertia rides on the parent body, their spin couples joint i
    for (k, r) in model.rotors.iter().enumerate() {
        let i = r.joint;
        let ir = r.inertia.spatial();
        let sr = spin_subspace(&r.axis, r.gear_ratio);
        let fr = ir * sr;
        data.mass_matrix[(o + i, o + i)] += sr.dot(&fr);
        let xm = transform_matrix(&data.x_rotor[k]);
        let on_parent = xm.transpose() * ir * xm;
        let f = data.x_rotor[k].apply_force_transpose(&fr);
        match model.joints[i].parent {
            Some(p) => data.ic[p] += on_parent,
            None => base += on_parent,
        }
        couple_ancestors(model, data, o + i, model.joints[i].parent, f);
    }
    for i in (0..n).rev() {
        let xm = transform_matrix(&data.x_up[i]);
        let add = xm.transpose() * data.ic[i] * xm;
        match model.joints[i].parent {
            Some(p) => data.ic[p] += add,
            None => base += add,
        }
        let f = data.ic[i] * model.subspace(i);
        data.mass_matrix[(o + i, o + i)] += model.subspace(i).dot(&f);
        let up = data.x_up[i].apply_force_transpose(&f);
        couple_ancestors(model, data, o + i, model.joints[i].parent, up);
    }
    base
}

/// Adds column `col`'s coupling with the joints from `body` up to the root
/// (`f`: the column's force in `body`'s frame, or the base's when `body`
/// is `None`), and with a free flyer's base rows, symmetrically.
fn couple_ancestors(
    model: &Model,
    data: &mut Data,
    col: usize,
    body: Option<usize>,
    mut f: Vector6<f64>,
) {
    let o = model.root_nv();
    let mut at = body;
    while let Some(j) = at {
        let h = model.subspace(j).dot(&f);
        data.mass_matrix[(col, o + j)] += h;
        data.mass_matrix[(o + j, col)] += h;
        f = data.x_up[j].apply_force_transpose(&f);
        at = model.joints[j].parent;
    }
    if model.is_floating() {
        for (r, h) in super::spatial::force_first(&f).into_iter().enumerate() {
            data.mass_matrix[(col, r)] += h;
            data.mass_matrix[(r, col)] += h;
        }
    }
}

/// Forward dynamics `q̈ = M(q)⁻¹ (τ − C(q, q̇) q̇ − g(q))`. Overwrites the
/// buffers of [`crba`] and [`rnea`](super::rnea).
pub fn forward_dynamics(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
) -> Result<DVector<f64>, DynamicsError> {
    let nv = model.nv();
    check_len("q", q, model.nq())?;
    check_len("qd", qd, nv)?;
    check_len("tau", tau, nv)?;
    let zeros = vec![0.0; nv];
    let bias = super::rnea(model, data, q, qd, &zeros)?.clone();
    crba(model, data, q)?;
    let chol = data
        .mass_matrix
        .clone()
        .cholesky()
        .ok_or(DynamicsError::SingularMassMatrix)?;
    Ok(chol.solve(&(DVector::from_column_slice(tau) - bias)))
}

/// Kinetic and potential energy `(T, U)` in J (U = 0 at the world origin,
/// the fixed base's), links, rotors and a free flyer's base; `qd` of
/// length [`Model::nv`]; overwrites the buffers of [`crba`].
pub fn energy(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
) -> Result<(f64, f64), DynamicsError> {
    let n = model.dof();
    check_len("qd", qd, model.nv())?;
    crba(model, data, q)?;
    let v = DVector::from_column_slice(qd);
    let t = 0.5 * (v.transpose() * &data.mass_matrix * &v)[(0, 0)];
    // world poses: X_world→body
    let mut world = vec![Transform::identity(); n];
    let g = model.gravity;
    let pot = |x: &Transform, p: &crate::moments::InertialParams| {
        let et: Matrix3<f64> = x.e.transpose();
        -g.dot(&(x.r * p.mass() + et * p.h()))
    };
    let (mut u, root) = match model.base() {
        None => (0.0, None),
        Some(b) => {
            let (p, r) = model.base_pose(q)?;
            let x = Model::pose_transform(&p, &r);
            (pot(&x, &b.inertia), Some(x))
        }
    };
    for i in 0..n {
        world[i] = match (model.joints[i].parent, &root) {
            (Some(p), _) => data.x_up[i].compose(&world[p]),
            (None, Some(x)) => data.x_up[i].compose(x),
            (None, None) => data.x_up[i],
        };
        u += pot(&world[i], &model.joints[i].inertia);
    }
    for (k, r) in model.rotors.iter().enumerate() {
        let xw = match (model.joints[r.joint].parent, &root) {
            (Some(p), _) => data.x_rotor[k].compose(&world[p]),
            (None, Some(x)) => data.x_rotor[k].compose(x),
            (None, None) => data.x_rotor[k],
        };
        u += pot(&xw, &r.inertia);
    }
    Ok((t, u))
}
