//! The joint-torque regressor `τ = Y(q, q̇, q̈) π + Σ_t c_t φ_t(q̇)`.
//!
//! Column layout of `data.regressor` ([`Model::nv`] rows: a free flyer's 6
//! base rows first, then one per joint):
//! `[π of the base | π of link 1 … link n | π of rotor 1 … | term 1, joints 1..n | term 2, …]`
//! (the base's 10 columns only with a free-flying root),
//! 10 columns per body in the paper's order, then one column per joint for
//! each term of the friction law the model has ([`Model::friction_terms`],
//! by default viscous, then Coulomb); term t's column of joint i holds
//! its basis φ_t in row i ([`super::friction`]); the `load` term's needs
//! the joint's load, [`Data::load`], which the caller sets (an error when
//! it is not finite).

use super::data::{BodyRegressor, Data};
use super::error::DynamicsError;

use super::model::Model;
use super::rnea::{RootMotion, check_state, forward_pass_from};
use super::spatial::{Transform, force_first};
use crate::moments::skew;
use nalgebra::{Matrix3, SMatrix, Vector3, Vector6};

/// `A(v, a)` with `I(π) a + v ×* I(π) v = A(v, a) π` (6 × 10).
pub fn body_regressor(v: &Vector6<f64>, a: &Vector6<f64>) -> BodyRegressor {
    let w = Vector3::new(v[0], v[1], v[2]);
    let vl = Vector3::new(v[3], v[4], v[5]);
    let al_ = Vector3::new(a[0], a[1], a[2]);
    let al = Vector3::new(a[3], a[4], a[5]);
    let acc = al + w.cross(&vl);
    let l = |x: &Vector3<f64>| {
        SMatrix::<f64, 3, 6>::from_row_slice(&[
            x.x, x.y, x.z, 0.0, 0.0, 0.0, //
            0.0, x.x, 0.0, x.y, x.z, 0.0, //
            0.0, 0.0, x.x, 0.0, x.y, x.z,
        ])
    };
    let sw: Matrix3<f64> = skew(&w);
    let ang_i = l(&al_) + sw * l(&w);
    let ang_h = -skew(&acc);
    let lin_h = skew(&al_) + sw * sw;
    let mut y = BodyRegressor::zeros();
    for r in 0..3 {
        y[(3 + r, 0)] = acc[r];
        for c in 0..3 {
            y[(r, 1 + c)] = ang_h[(r, c)];
            y[(3 + r, 1 + c)] = lin_h[(r, c)];
        }
        for c in 0..6 {
            y[(r, 4 + c)] = ang_i[(r, c)];
        }
    }
    y
}

/// `sᵀ B` (a row of 10), B column-major.
#[inline(always)]
fn project(s: &Vector6<f64>, b: &BodyRegressor) -> [f64; 10] {
    // fixed sizes: no bounds checks, the ten dot products side by side
    let d: &[f64; 60] = b.as_slice().try_into().expect("6 × 10");
    let s: &[f64; 6] = s.as_slice().try_into().expect("6");
    let mut out = [0.0; 10];
    for (c, o) in out.iter_mut().enumerate() {
        let col = &d[6 * c..6 * c + 6];
        *o = s[0] * col[0]
            + s[1] * col[1]
            + s[2] * col[2]
            + s[3] * col[3]
            + s[4] * col[4]
            + s[5] * col[5];
    }
    out
}

/// Adds a piece of a row into the regressor at (row, col0..col0 + len).
#[inline]
fn add_row(y: &mut nalgebra::DMatrix<f64>, row: usize, col0: usize, r: &[f64]) {
    let n = y.nrows();
    let data = &mut y.as_mut_slice()[col0 * n..(col0 + r.len()) * n];
    for (c, v) in r.iter().enumerate() {
        data[c * n + row] += v;
    }
}

/// Fills `data.regressor` (see the module docs for the layout) at one
/// state (lengths [`Model::nq`], [`Model::nv`], [`Model::nv`]).
pub fn regressor<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> Result<&'a nalgebra::DMatrix<f64>, DynamicsError> {
    check_state(model, q, qd, qdd)?;
    check_load(model, data)?;
    let root = root_of(model, [q, qd, qdd])?;
    let mut y = std::mem::take(&mut data.regressor);
    y.as_mut_slice().fill(0.0);
    all_blocks(model, data, [q, qd, qdd], &root, |row, col0, values| {
        add_row(&mut y, row, col0, values)
    });
    data.regressor = y;
    Ok(&data.regressor)
}

/// The root's motion at a state: the fixed base's (gravity) or the free
/// flyer's (its quaternion checked).
fn root_of(model: &Model, [q, qd, qdd]: [&[f64]; 3]) -> Result<RootMotion, DynamicsError> {
    if !model.is_floating() {
        return Ok(RootMotion::fixed(model, true));
    }
    Ok(model.root_motion(&model.base_state(q, qd, qdd)?, true))
}

/// Every block of the regressor: the joint rows, then a free flyer's base
/// rows (the joint parts of the state after the base's).
fn all_blocks(
    model: &Model,
    data: &mut Data,
    [q, qd, qdd]: [&[f64]; 3],
    root: &RootMotion,
    mut put: impl FnMut(usize, usize, &[f64]),
) {
    let (jq, jv) = (model.nq() - model.dof(), model.root_nv());
    let joints = [&q[jq..], &qd[jv..], &qdd[jv..]];
    regressor_blocks_from(model, data, joints, root, &mut put);
    if model.is_floating() {
        base_row_blocks(model, data, root, put);
    }
}

/// A free flyer's base rows (0..6): every body's `X_{body←base}ᵀ A(v, a)`,
/// the base's own with the identity, as `put(row, col0, 10 values)`.
fn base_row_blocks(
    model: &Model,
    data: &mut Data,
    root: &RootMotion,
    mut put: impl FnMut(usize, usize, &[f64]),
) {
    model.chain_to_base(data);
    let n = model.dof();
    let mut body = |col0: usize, a: &BodyRegressor, x: &Transform| {
        let mut rows = [[0.0; 10]; 6];
        for c in 0..10 {
            let f = force_first(&x.apply_force_transpose(&a.column(c).into_owned()));
            for (r, v) in f.iter().enumerate() {
                rows[r][c] = *v;
            }
        }
        for (r, row) in rows.iter().enumerate() {
            put(r, col0, row);
        }
    };
    body(0, &body_regressor(&root.v, &root.a), &Transform::identity());
    for i in 0..n {
        let a = body_regressor(&data.v[i], &data.a[i]);
        body(10 + 10 * i, &a, &data.x_base[i]);
    }
    for (k, r) in model.rotors.iter().enumerate() {
        let x = match model.joints[r.joint].parent {
            Some(p) => data.x_rotor[k].compose(&data.x_base[p]),
            None => data.x_rotor[k],
        };
        let a = body_regressor(&data.v_rotor[k], &data.a_rotor[k]);
        body(10 + 10 * (n + k), &a, &x);
    }
}

/// With a load friction term, every joint's [`Data::load`] must be finite
/// (set by the caller).
pub(crate) fn check_load(model: &Model, data: &Data) -> Result<(), DynamicsError> {
    let has_load = model.friction_terms().contains(&super::FrictionTerm::Load);
    match data.load.iter().position(|l| !l.is_finite()) {
        Some(i) if has_load => Err(DynamicsError::NonFinite {
            sample: 0,
            what: format!(
                "the load of joint '{}' (Data::load, which a model with the load friction term needs set)",
                model.joints[i].name
            ),
        }),
        _ => Ok(()),
    }
}

/// [`regressor`] of a fixed base, unchecked.
pub(crate) fn regressor_unchecked(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) {
    debug_assert!(
        !model.is_floating(),
        "regressor_unchecked is the fixed base's"
    );
    let mut y = std::mem::take(&mut data.regressor);
    y.as_mut_slice().fill(0.0);
    let root = RootMotion::fixed(model, true);
    regressor_blocks_from(model, data, [q, qd, qdd], &root, |row, col0, values| {
        add_row(&mut y, row, col0, values)
    });
    data.regressor = y;
}

/// The regressor's non-zero entries at one state, without the zeros:
/// `put(row, col0, values)` is called once for each body (10 values, its
/// columns `col0..col0 + 10`) in each row the body enters, and once for
/// each friction column of each row (1 value); the columns a row gets are
/// exactly [`regressor_row_columns`]'s, each once. The checked form of
/// what [`regressor`] writes densely, for callers that gather the rows
/// joint by joint. A free flyer's base rows (0..6) get each body's 10
/// values once per row.
pub fn regressor_blocks(
    model: &Model,
    data: &mut Data,
    [q, qd, qdd]: [&[f64]; 3],
    put: impl FnMut(usize, usize, &[f64]),
) -> Result<(), DynamicsError> {
    check_state(model, q, qd, qdd)?;
    check_load(model, data)?;
    let root = root_of(model, [q, qd, qdd])?;
    all_blocks(model, data, [q, qd, qdd], &root, put);
    Ok(())
}

/// [`regressor_blocks`] unchecked, from a moving root: the joint rows only
/// (rows and columns numbered as in the whole regressor), from the joint
/// parts of the state (n each).
pub(crate) fn regressor_blocks_from(
    model: &Model,
    data: &mut Data,
    [q, qd, qdd]: [&[f64]; 3],
    root: &RootMotion,
    mut put: impl FnMut(usize, usize, &[f64]),
) {
    // τⱼ = Σ_k (X_{k←j} Sⱼ)ᵀ A_k π_k over the bodies k that joint j moves:
    // instead of carrying each 6×10 block A_k up the tree, carry the joint
    // axes down to every body (6-vectors are cheap to transform).
    let (n, o, b0) = (model.dof(), model.root_nv(), model.first_link_body());
    forward_pass_from(model, data, [q, qd, qdd], root);
    for i in 0..n {
        let (done, rest) = data.axes.split_at_mut(i);
        let mine = &mut rest[0];
        mine.clear();
        if let Some(p) = model.joints[i].parent {
            for &(j, s) in &done[p] {
                mine.push((j, data.x_up[i].apply_motion(&s)));
            }
        }
        mine.push((i, model.subspace(i)));
        let a = body_regressor(&data.v[i], &data.a[i]);
        for &(j, s) in mine.iter() {
            put(o + j, 10 * (b0 + i), &project(&s, &a));
        }
    }
    for (k, r) in model.rotors.iter().enumerate() {
        let a = body_regressor(&data.v_rotor[k], &data.a_rotor[k]);
        let col0 = 10 * (b0 + n + k);
        let sr = Vector6::new(r.axis.x, r.axis.y, r.axis.z, 0.0, 0.0, 0.0) * r.gear_ratio;
        put(o + r.joint, col0, &project(&sr, &a));
        if let Some(p) = model.joints[r.joint].parent {
            for idx in 0..data.axes[p].len() {
                let (j, s) = data.axes[p][idx];
                let sk = data.x_rotor[k].apply_motion(&s);
                put(o + j, col0, &project(&sk, &a));
            }
        }
    }
    let (nb, vs) = (model.num_bodies(), model.stribeck_velocity());
    for (t, term) in model.friction_terms().iter().enumerate() {
        for i in 0..n {
            put(
                o + i,
                10 * nb + t * n + i,
                &[term.basis(qd[i], data.load[i], vs)],
            );
        }
    }
}

/// Per row (a free flyer's 6 base rows, then one per joint j), the
/// regressor columns it can be non-zero in, in increasing order: a base
/// row every body's; joint j's the links j moves (j and its descendants),
/// the rotors it carries or drives, and its own friction terms; every other
/// column of the row is zero at every state (the structure of
/// [`regressor`]).
pub fn regressor_row_columns(model: &Model) -> Vec<Vec<usize>> {
    let (n, b0) = (model.dof(), model.first_link_body());
    // moves[j][i]: joint j is joint i or one of its ancestors
    let mut moves = vec![vec![false; n]; n];
    for i in 0..n {
        let mut a = Some(i);
        while let Some(j) = a {
            moves[j][i] = true;
            a = model.joints[j].parent;
        }
    }
    let nb = model.num_bodies();
    let base_rows = (0..model.root_nv()).map(|_| (0..10 * nb).collect());
    let joint_rows = (0..n).map(|j| {
        let links = (0..n).filter(|&i| moves[j][i]);
        let rotors = model.rotors.iter().enumerate().filter(|(_, r)| {
            r.joint == j || model.joints[r.joint].parent.is_some_and(|p| moves[j][p])
        });
        let bodies = links.chain(rotors.map(|(k, _)| n + k)).map(|b| b0 + b);
        let mut cols: Vec<usize> = bodies.flat_map(|b| 10 * b..10 * b + 10).collect();
        cols.extend((0..model.friction_terms().len()).map(|t| 10 * nb + t * n + j));
        cols
    });
    base_rows.chain(joint_rows).collect()
}

/// Regressor rows for many samples, stacked sample by sample into a
/// `(samples · nv) ×` [`Model::regressor_columns`] row-major buffer, in
/// parallel over chunks of samples (rayon). `q` holds `samples ·`
/// [`Model::nq`] numbers, `qd` and `qdd` `samples ·` [`Model::nv`],
/// sample-major.
pub fn regressor_batch(
    model: &Model,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> Result<Vec<f64>, DynamicsError> {
    use rayon::prelude::*;
    let (nq, nv) = (model.nq(), model.nv());
    // (no loads here: a load term's columns would be NaN)
    check_load(model, &Data::new(model))?;
    let samples = q.len() / nq.max(1);
    if nq == 0 || q.len() % nq != 0 || qd.len() != samples * nv || qdd.len() != samples * nv {
        return Err(DynamicsError::Dimension {
            what: "batch state arrays".into(),
            expected: samples * nv,
            found: qd.len().min(qdd.len()),
        });
    }
    let cols = model.regressor_columns();
    let mut out = vec![0.0; samples * nv * cols];
    const CHUNK: usize = 256;
    out.par_chunks_mut(CHUNK * nv * cols)
        .enumerate()
        .try_for_each(|(c, buf)| {
            let mut data = Data::new(model);
            let s0 = c * CHUNK;
            for (local, rows) in buf.chunks_mut(nv * cols).enumerate() {
                let s = s0 + local;
                let (x, v) = (&q[s * nq..(s + 1) * nq], s * nv..(s + 1) * nv);
                if model.is_floating() {
                    regressor(model, &mut data, x, &qd[v.clone()], &qdd[v])?;
                } else {
                    regressor_unchecked(model, &mut data, x, &qd[v.clone()], &qdd[v]);
                }
                for i in 0..nv {
                    for j in 0..cols {
                        rows[i * cols + j] = data.regressor[(i, j)];
                    }
                }
            }
            Ok::<(), DynamicsError>(())
        })?;
    Ok(out)
}
