//! Recursive Newton–Euler inverse dynamics with geared rotors, from a fixed
//! or a free-flying root.

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

/// The motion of the body the tree hangs from, in its own frame: a fixed
/// base has `v = 0` and `a = (0, −g)` (gravity as a fictitious upward
/// acceleration); a free-flyer's is its twist and its acceleration minus
/// gravity, both in base coordinates.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RootMotion {
    pub v: Vector6<f64>,
    pub a: Vector6<f64>,
}

impl RootMotion {
    /// The fixed base, with or without gravity.
    pub fn fixed(model: &Model, with_gravity: bool) -> Self {
        let g = if with_gravity {
            model.gravity
        } else {
            nalgebra::Vector3::zeros()
        };
        RootMotion {
            v: Vector6::zeros(),
            a: Vector6::new(0.0, 0.0, 0.0, -g.x, -g.y, -g.z),
        }
    }
}

/// Forward pass shared by RNEA and the regressor: fills `x_up`, `v`, `a`
/// for links and rotors from the root's motion (a fixed base's carries −g).
pub(crate) fn forward_pass_from(
    model: &Model,
    data: &mut Data,
    state: [&[f64]; 3],
    root: &RootMotion,
) {
    let [q, qd, qdd] = state;
    let (v0, a0) = (root.v, root.a);
    for i in 0..model.dof() {
        let x = model.joint_transform(i, q[i]);
        let s = model.subspace(i);
        let (vp, ap) = match model.joints[i].parent {
            Some(p) => (data.v[p], data.a[p]),
            None => (v0, a0),
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
/// Inputs of length [`Model::nq`], [`Model::nv`], [`Model::nv`] (rad,
/// rad/s, rad/s²; m for prismatic joints; a free flyer's conventions in
/// [`super::free_flyer`]); writes `data.tau` (N·m or N; a free flyer's
/// base wrench first) and the kinematic buffers, and returns `&data.tau`.
pub fn rnea<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> Result<&'a DVector<f64>, DynamicsError> {
    check_state(model, q, qd, qdd)?;
    if model.is_floating() {
        let s = model.base_state(q, qd, qdd)?;
        let j = model.root_nv();
        model.free_flyer_inverse_dynamics(data, &s, [&q[7..], &qd[j..], &qdd[j..]], true);
    } else {
        rnea_unchecked(model, data, q, qd, qdd, true);
    }
    Ok(&data.tau)
}

/// A state's lengths: `q` [`Model::nq`], `qd` and `qdd` [`Model::nv`].
pub(crate) fn check_state(
    model: &Model,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> Result<(), DynamicsError> {
    check_len("q", q, model.nq())?;
    check_len("qd", qd, model.nv())?;
    check_len("qdd", qdd, model.nv())
}

pub(crate) fn rnea_unchecked(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    gravity: bool,
) {
    debug_assert!(!model.is_floating(), "rnea_unchecked is the fixed base's");
    rnea_from(
        model,
        data,
        [q, qd, qdd],
        &RootMotion::fixed(model, gravity),
    );
}

/// RNEA from a moving root: writes the joint rows of `data.tau` (after the
/// root's [`Model::root_nv`]) and returns the force the
/// tree exerts on its root (root coordinates, `[moment; force]`), what the
/// fixed base absorbs and a free-flyer's base must balance.
pub(crate) fn rnea_from(
    model: &Model,
    data: &mut Data,
    state: [&[f64]; 3],
    root: &RootMotion,
) -> Vector6<f64> {
    forward_pass_from(model, data, state, root);
    let o = model.root_nv();
    let mut f_root = Vector6::zeros();
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
            let fr = data.x_rotor[k].apply_force_transpose(&data.f_rotor[k]);
            match model.joints[i].parent {
                Some(pp) => data.f[pp] += fr,
                None => f_root += fr,
            }
        }
        data.tau[o + i] = t;
        let fp = data.x_up[i].apply_force_transpose(&data.f[i]);
        match model.joints[i].parent {
            Some(pp) => data.f[pp] += fp,
            None => f_root += fp,
        }
    }
    f_root
}
