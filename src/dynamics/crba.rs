//! Composite-rigid-body algorithm for the joint-space mass matrix, with
//! rotors, and forward dynamics on top of it.

use super::data::Data;
use super::error::DynamicsError;
use super::model::Model;
use super::rnea::{check_len, rnea_unchecked};
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

/// The mass matrix `M(q)` (n × n, kg·m² for revolute joints) into
/// `data.mass_matrix`; also overwrites `data.x_up`, `data.x_rotor`, `data.ic`.
pub fn crba<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
) -> Result<&'a DMatrix<f64>, DynamicsError> {
    let n = model.dof();
    check_len("q", q, n)?;
    for i in 0..n {
        data.x_up[i] = model.joint_transform(i, q[i]);
        data.ic[i] = model.joints[i].inertia.spatial();
    }
    for (k, r) in model.rotors.iter().enumerate() {
        data.x_rotor[k] = model.rotor_transform(k, q[r.joint]);
    }
    data.mass_matrix.fill(0.0);
    // rotors: their inertia rides on the parent body, their spin couples joint i
    for (k, r) in model.rotors.iter().enumerate() {
        let i = r.joint;
        let ir = r.inertia.spatial();
        let sr = spin_subspace(&r.axis, r.gear_ratio);
        let fr = ir * sr;
        data.mass_matrix[(i, i)] += sr.dot(&fr);
        if let Some(p) = model.joints[i].parent {
            let xm = transform_matrix(&data.x_rotor[k]);
            data.ic[p] += xm.transpose() * ir * xm;
            let mut f = data.x_rotor[k].apply_force_transpose(&fr);
            let mut j = p;
            loop {
                let h = model.subspace(j).dot(&f);
                data.mass_matrix[(i, j)] += h;
                data.mass_matrix[(j, i)] += h;
                match model.joints[j].parent {
                    Some(pp) => {
                        f = data.x_up[j].apply_force_transpose(&f);
                        j = pp;
                    }
                    None => break,
                }
            }
        }
    }
    for i in (0..n).rev() {
        if let Some(p) = model.joints[i].parent {
            let xm = transform_matrix(&data.x_up[i]);
            let add = xm.transpose() * data.ic[i] * xm;
            data.ic[p] += add;
        }
        let mut f = data.ic[i] * model.subspace(i);
        data.mass_matrix[(i, i)] += model.subspace(i).dot(&f);
        let mut j = i;
        while let Some(p) = model.joints[j].parent {
            f = data.x_up[j].apply_force_transpose(&f);
            j = p;
            let h = model.subspace(j).dot(&f);
            data.mass_matrix[(i, j)] += h;
            data.mass_matrix[(j, i)] += h;
        }
    }
    Ok(&data.mass_matrix)
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
    let n = model.dof();
    check_len("q", q, n)?;
    check_len("qd", qd, n)?;
    check_len("tau", tau, n)?;
    let zeros = vec![0.0; n];
    rnea_unchecked(model, data, q, qd, &zeros, true);
    let bias = data.tau.clone();
    crba(model, data, q)?;
    let chol = data
        .mass_matrix
        .clone()
        .cholesky()
        .ok_or(DynamicsError::SingularMassMatrix)?;
    Ok(chol.solve(&(DVector::from_column_slice(tau) - bias)))
}

/// Kinetic and potential energy `(T, U)` in J (U = 0 at the base origin),
/// links and rotors; overwrites the buffers of [`crba`].
pub fn energy(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
) -> Result<(f64, f64), DynamicsError> {
    let n = model.dof();
    check_len("qd", qd, n)?;
    crba(model, data, q)?;
    let v = DVector::from_column_slice(qd);
    let t = 0.5 * (v.transpose() * &data.mass_matrix * &v)[(0, 0)];
    // world poses: X_world→body
    let mut world = vec![Transform::identity(); n];
    let mut u = 0.0;
    let g = model.gravity;
    let pot = |x: &Transform, p: &crate::moments::InertialParams| {
        let et: Matrix3<f64> = x.e.transpose();
        -g.dot(&(x.r * p.mass() + et * p.h()))
    };
    for i in 0..n {
        world[i] = match model.joints[i].parent {
            Some(p) => data.x_up[i].compose(&world[p]),
            None => data.x_up[i],
        };
        u += pot(&world[i], &model.joints[i].inertia);
    }
    for (k, r) in model.rotors.iter().enumerate() {
        let xw = match model.joints[r.joint].parent {
            Some(p) => data.x_rotor[k].compose(&world[p]),
            None => data.x_rotor[k],
        };
        u += pot(&xw, &r.inertia);
    }
    Ok((t, u))
}
