//! Recursive Newton–Euler inverse dynamics with geared rotors.

use super::data::Data;
use super::error::DynamicsError;
use super::model::Model;
use super::spatial::{cross_force, cross_motion, inertia_times};
use nalgebra::{DVector, Vector6};

pub(crate) fn check_len(what: &str, v: &[f64], n: usize) -> Result<(), DynamicsError> {
    if v.len() != n {
        return Err(DynamicsError::Dimension {
            what: what.into(),
            expected: n,
            found: v.len(),
        });
    }
    Ok(())
}

/// Forward pass shared by RNEA and the regressor: fills `x_up`, `v`, `a`
/// (with −g at the base) for links and rotors. `with_gravity = false` drops it.
pub(crate) fn forward_pass(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    with_gravity: bool,
) {
    let g = if with_gravity {
        model.gravity
    } else {
        nalgebra::Vector3::zeros()
    };
    let a0 = Vector6::new(0.0, 0.0, 0.0, -g.x, -g.y, -g.z);
    let zero = Vector6::zeros();
    for i in 0..model.dof() {
        let x = model.joint_transform(i, q[i]);
        let s = model.subspace(i);
        let (vp, ap) = match model.joints[i].parent {
            Some(p) => (data.v[p], data.a[p]),
            None => (zero, a0),
        };
        let vj = s * qd[i];
        let v = x.apply_motion(&vp) + vj;
        data.a[i] = x.apply_motion(&ap) + s * qdd[i] + cross_motion(&v, &vj);
        data.v[i] = v;
        data.x_up[i] = x;
        if let Some(k) = model.rotor_of[i] {
            let r = &model.rotors[k];
            let xr = model.rotor_transform(k, q[i]);
            let sr = Vector6::new(r.axis.x, r.axis.y, r.axis.z, 0.0, 0.0, 0.0) * r.gear_ratio;
            let vr_j = sr * qd[i];
            let vr = xr.apply_motion(&vp) + vr_j;
            data.a_rotor[k] = xr.apply_motion(&ap) + sr * qdd[i] + cross_motion(&vr, &vr_j);
            data.v_rotor[k] = vr;
            data.x_rotor[k] = xr;
        }
    }
}

/// Inverse dynamics `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)` including rotors
/// (their spin about `N q̇`, reflected inertia and gyroscopic coupling).
/// Inputs of length n (rad, rad/s, rad/s²; m for prismatic joints); writes
/// `data.tau` (N·m or N) and the kinematic buffers, and returns `&data.tau`.
pub fn rnea<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> Result<&'a DVector<f64>, DynamicsError> {
    let n = model.dof();
    check_len("q", q, n)?;
    check_len("qd", qd, n)?;
    check_len("qdd", qdd, n)?;
    rnea_unchecked(model, data, q, qd, qdd, true);
    Ok(&data.tau)
}

pub(crate) fn rnea_unchecked(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    gravity: bool,
) {
    forward_pass(model, data, q, qd, qdd, gravity);
    for i in 0..model.dof() {
        let p = &model.joints[i].inertia.0;
        data.f[i] =
            inertia_times(p, &data.a[i]) + cross_force(&data.v[i], &inertia_times(p, &data.v[i]));
    }
    for (k, r) in model.rotors.iter().enumerate() {
        let p = &r.inertia.0;
        data.f_rotor[k] = inertia_times(p, &data.a_rotor[k])
            + cross_force(&data.v_rotor[k], &inertia_times(p, &data.v_rotor[k]));
    }
    for i in (0..model.dof()).rev() {
        let mut t = model.subspace(i).dot(&data.f[i]);
        if let Some(k) = model.rotor_of[i] {
            let r = &model.rotors[k];
            let sr = Vector6::new(r.axis.x, r.axis.y, r.axis.z, 0.0, 0.0, 0.0) * r.gear_ratio;
            t += sr.dot(&data.f_rotor[k]);
            if let Some(pp) = model.joints[i].parent {
                let fr = data.x_rotor[k].apply_force_transpose(&data.f_rotor[k]);
                data.f[pp] += fr;
            }
        }
        data.tau[i] = t;
        if let Some(pp) = model.joints[i].parent {
            let fp = data.x_up[i].apply_force_transpose(&data.f[i]);
            data.f[pp] += fp;
        }
    }
}
