//! The joint-torque regressor `τ = Y(q, q̇, q̈) π + Σ_t c_t φ_t(q̇)`.
//!
//! Column layout of `data.regressor` (n rows):
//! `[π of link 1 … link n | π of rotor 1 … | term 1, joints 1..n | term 2, …]`,
//! 10 columns per body in the paper's order, then one column per joint for
//! each term of the friction law the model has ([`Model::friction_terms`],
//! by default viscous, then Coulomb); term t's column of joint i holds
//! its basis φ_t in row i ([`super::friction`]); the `load` term's needs
//! the joint's load, [`Data::load`], which the caller sets (an error when
//! it is not finite).

use super::data::{BodyRegressor, Data};
use super::error::DynamicsError;
use super::model::Model;
use super::rnea::{Root, check_len, forward_pass_from};
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

/// Fills `data.regressor` (see the module docs for the layout) at one state.
pub fn regressor<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> Result<&'a nalgebra::DMatrix<f64>, DynamicsError> {
    let n = model.dof();
    check_len("q", q, n)?;
    check_len("qd", qd, n)?;
    check_len("qdd", qdd, n)?;
    check_load(model, data)?;
    regressor_unchecked(model, data, q, qd, qdd);
    Ok(&data.regressor)
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

pub(crate) fn regressor_unchecked(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) {
    let mut y = std::mem::take(&mut data.regressor);
    y.as_mut_slice().fill(0.0);
    let root = Root::fixed(model, true);
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
/// joint by joint.
pub fn regressor_blocks(
    model: &Model,
    data: &mut Data,
    [q, qd, qdd]: [&[f64]; 3],
    put: impl FnMut(usize, usize, &[f64]),
) -> Result<(), DynamicsError> {
    let n = model.dof();
    check_len("q", q, n)?;
    check_len("qd", qd, n)?;
    check_len("qdd", qdd, n)?;
    check_load(model, data)?;
    regressor_blocks_from(model, data, [q, qd, qdd], &Root::fixed(model, true), put);
    Ok(())
}

/// [`regressor_blocks`] unchecked, from a moving root (the joint rows
/// only: what the root's own rows hold is the caller's).
pub(crate) fn regressor_blocks_from(
    model: &Model,
    data: &mut Data,
    [q, qd, qdd]: [&[f64]; 3],
    root: &Root,
    mut put: impl FnMut(usize, usize, &[f64]),
) {
    // τⱼ = Σ_k (X_{k←j} Sⱼ)ᵀ A_k π_k over the bodies k that joint j moves:
    // instead of carrying each 6×10 block A_k up the tree, carry the joint
    // axes down to every body (6-vectors are cheap to transform).
    let n = model.dof();
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
            put(j, 10 * i, &project(&s, &a));
        }
    }
    for (k, r) in model.rotors.iter().enumerate() {
        let a = body_regressor(&data.v_rotor[k], &data.a_rotor[k]);
        let col0 = 10 * (n + k);
        let sr = Vector6::new(r.axis.x, r.axis.y, r.axis.z, 0.0, 0.0, 0.0) * r.gear_ratio;
        put(r.joint, col0, &project(&sr, &a));
        if let Some(p) = model.joints[r.joint].parent {
            for idx in 0..data.axes[p].len() {
                let (j, s) = data.axes[p][idx];
                let sk = data.x_rotor[k].apply_motion(&s);
                put(j, col0, &project(&sk, &a));
            }
        }
    }
    let (nb, vs) = (model.num_bodies(), model.stribeck_velocity());
    for (t, term) in model.friction_terms().iter().enumerate() {
        for i in 0..n {
            put(
                i,
                10 * nb + t * n + i,
                &[term.basis(qd[i], data.load[i], vs)],
            );
        }
    }
}

/// Per joint j, the regressor columns its row can be non-zero in, in
/// increasing order: the links j moves (j and its descendants), the rotors
/// it carries or drives, and its own friction terms; every other column of
/// row j is zero at every state (the structure of [`regressor`]).
pub fn regressor_row_columns(model: &Model) -> Vec<Vec<usize>> {
    let n = model.dof();
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
    (0..n)
        .map(|j| {
            let links = (0..n).filter(|&i| moves[j][i]);
            let rotors = model.rotors.iter().enumerate().filter(|(_, r)| {
                r.joint == j || model.joints[r.joint].parent.is_some_and(|p| moves[j][p])
            });
            let bodies = links.chain(rotors.map(|(k, _)| n + k));
            let mut cols: Vec<usize> = bodies.flat_map(|b| 10 * b..10 * b + 10).collect();
            cols.extend((0..model.friction_terms().len()).map(|t| 10 * nb + t * n + j));
            cols
        })
        .collect()
}

/// Regressor rows for many samples, stacked sample by sample into a
/// `(samples · n) ×` [`Model::regressor_columns`] row-major buffer, in parallel over
/// chunks of samples (rayon). Each state slice holds `samples · n` numbers,
/// sample-major.
pub fn regressor_batch(
    model: &Model,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> Result<Vec<f64>, DynamicsError> {
    use rayon::prelude::*;
    let n = model.dof();
    // (no loads here: a load term's columns would be NaN)
    check_load(model, &Data::new(model))?;
    if n == 0 || q.len() % n != 0 || qd.len() != q.len() || qdd.len() != q.len() {
        return Err(DynamicsError::Dimension {
            what: "batch state arrays".into(),
            expected: q.len(),
            found: qd.len().min(qdd.len()),
        });
    }
    let cols = model.regressor_columns();
    let samples = q.len() / n;
    let mut out = vec![0.0; samples * n * cols];
    const CHUNK: usize = 256;
    out.par_chunks_mut(CHUNK * n * cols)
        .enumerate()
        .for_each(|(c, buf)| {
            let mut data = Data::new(model);
            let s0 = c * CHUNK;
            for (local, rows) in buf.chunks_mut(n * cols).enumerate() {
                let s = s0 + local;
                let r = s * n..(s + 1) * n;
                regressor_unchecked(model, &mut data, &q[r.clone()], &qd[r.clone()], &qdd[r]);
                for i in 0..n {
                    for j in 0..cols {
                        rows[i * cols + j] = data.regressor[(i, j)];
                    }
                }
            }
        });
    Ok(out)
}
