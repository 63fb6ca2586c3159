//! A load friction term's passes without reducing the samples again.
//!
//! The load term's column is `|load| sign(q̇)`, its load the rigid model's
//! torque at the previous pass's solution ([`Identification::fit`]'s
//! passes). Only that column changes from pass to pass, and it is non-zero
//! in its own joint's rows alone: so the Gram matrix of a pass is the first
//! reduction's with, per joint, one row and column replaced — the products
//! of the new column with that joint's rows. The rows are built once and
//! kept (joint by joint, only their non-zero columns: ~2.6 kB a sample for
//! a 7-joint arm with five friction terms), so a pass costs
//! `samples × Σ_j columns(j)` multiply-adds instead of a reduction; past
//! [`LOAD_ROWS_BUDGET_BYTES`] the passes reduce again instead (the rows
//! are built in parallel pieces and joined: at most twice that at once).
//!
//! [`Identification::fit`]: super::Identification::fit

use super::error::IdentifyError;
use super::gram::GramAcc;
use super::reduce::Reduced;
use crate::data::Dataset;
use crate::dynamics::{Data, FrictionTerm, Model, Samples, regressor_row_columns};
use rayon::prelude::*;

/// The most memory the kept rows may take (bytes).
pub const LOAD_ROWS_BUDGET_BYTES: usize = 128 << 20;

/// A training set's regressor rows, kept for the load term's passes.
pub(crate) struct LoadRows {
    rows: GramAcc,
    /// Per joint, its load column (global).
    load_cols: Vec<usize>,
    /// The samples' velocities (the load column's sign).
    qd: Samples,
}

impl std::fmt::Debug for LoadRows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LoadRows {{ {} samples }}", self.qd.len())
    }
}

impl LoadRows {
    /// `train`'s rows for `model` (which has a load term), or `None` when
    /// they would take over [`LOAD_ROWS_BUDGET_BYTES`] or the model has
    /// no load term.
    pub(crate) fn new(model: &Model, train: &Dataset) -> Result<Option<Self>, IdentifyError> {
        let terms = model.friction_terms();
        let Some(t) = terms.iter().position(|t| *t == FrictionTerm::Load) else {
            return Ok(None);
        };
        let per_sample: usize = (regressor_row_columns(model).iter())
            .map(|c| (c.len() + 1) * std::mem::size_of::<f64>())
            .sum();
        if per_sample.saturating_mul(train.len()) > LOAD_ROWS_BUDGET_BYTES {
            return Ok(None);
        }
        // built in pieces in parallel, then joined in order
        let piece = train.len().div_ceil(rayon::current_num_threads()).max(1);
        let starts: Vec<usize> = (0..train.len()).step_by(piece).collect();
        let pieces = (starts.par_iter())
            .map(|&start| rows_of(model, train, start..(start + piece).min(train.len())))
            .collect::<Result<Vec<_>, _>>()?;
        let mut pieces = pieces.into_iter();
        let Some(mut rows) = pieces.next() else {
            return Ok(None);
        };
        pieces.for_each(|p| rows.append(p));
        let (n, nb) = (model.dof(), model.num_bodies());
        Ok(Some(Self {
            rows,
            load_cols: (0..n).map(|j| 10 * nb + t * n + j).collect(),
            qd: train.qd.clone(),
        }))
    }

    /// The reduction of the kept rows, the load column's load the measured
    /// torque (as [`reduce_samples`](super::reduce::reduce_samples) makes
    /// it), with these rows in it for the passes.
    pub(crate) fn into_reduced(self, p: usize) -> Result<Reduced, IdentifyError> {
        let t0 = std::time::Instant::now();
        let per_joint = super::reduce::keep_joint_grams(self.load_cols.len(), p + 1);
        let (mut gram, mut joint_grams) =
            (self.rows.kept_grams(per_joint)).map_err(|e| super::reduce::not_finite(0, e))?;
        super::reduce::finite_gram(&gram)?;
        super::reduce::symmetrize(&mut gram);
        joint_grams.iter_mut().for_each(super::reduce::symmetrize);
        Ok(Reduced {
            gram,
            samples: self.qd.len(),
            p,
            joint_grams,
            reduce_time_s: t0.elapsed().as_secs_f64(),
            row_range: Some(0..self.load_cols.len()),
            load_rows: Some(std::sync::Arc::new(self)),
        })
    }

    /// The rigid model's torques (links and rotors at `theta`'s first
    /// `bodies_end` entries, no friction) at every sample, from the kept
    /// rows: what `predict_torques` gives without friction, without the
    /// dynamics again.
    pub(crate) fn rigid_torques(&self, theta: &[f64], bodies_end: usize) -> Samples {
        let n = self.load_cols.len();
        let mut out = Samples::zeros(self.qd.len(), n);
        for j in 0..n {
            let cols = self.rows.columns(j);
            let body = |c: &&usize| **c < bodies_end;
            let w: Vec<f64> = cols.iter().take_while(body).map(|&c| theta[c]).collect();
            for (s, v) in self.rows.row_products(j, &w).into_iter().enumerate() {
                out[s][j] = v;
            }
        }
        out
    }

    /// `base` (the reduction of the same samples, any load) with every
    /// joint's load column made from `load` (N·m, n per sample).
    pub(crate) fn reduce(&self, base: &Reduced, load: &Samples) -> Result<Reduced, IdentifyError> {
        if base.samples != self.qd.len() || load.len() != self.qd.len() {
            return Err(IdentifyError::SampleCount {
                what: "the load term's reduction",
                expected: self.qd.len(),
                found: base.samples.min(load.len()),
            });
        }
        let mut red = base.clone();
        for (j, &col) in self.load_cols.iter().enumerate() {
            let c: Vec<f64> = (0..self.qd.len())
                .map(|s| FrictionTerm::Load.basis(self.qd[s][j], load[s][j], 0.0))
                .collect();
            let products = self.rows.column_products(j, col, &c);
            for (&g, &x) in self.rows.columns(j).iter().zip(&products) {
                for m in std::iter::once(&mut red.gram).chain(red.joint_grams.get_mut(j)) {
                    m[(col, g)] = x;
                    m[(g, col)] = x;
                }
            }
        }
        super::reduce::finite_gram(&red.gram)?;
        Ok(red)
    }
}

/// The rows of `train`'s samples `range`, kept (not flushed).
fn rows_of(
    model: &Model,
    train: &Dataset,
    range: std::ops::Range<usize>,
) -> Result<GramAcc, IdentifyError> {
    let mut rows = GramAcc::new(model, range.len());
    let mut data = Data::new(model);
    for s in range {
        let state = [&train.q[s], &train.qd[s], &train.qdd[s]];
        (rows.push_state(model, &mut data, state, [&train.tau[s], &train.tau[s]]))
            .map_err(|source| IdentifyError::Regressor { sample: s, source })?;
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::{LoadRows, Reduced};
    use crate::data::Dataset;
    use crate::dynamics::{FrictionTerm, Samples, random_states};
    use crate::identify::reduce::{reduce_samples, reduce_with_load};

    /// A pass's Gram matrices from the kept rows equal a reduction made
    /// again with the new load (the full matrix and each joint's), on the
    /// leg with offset and load terms.
    #[test]
    fn a_pass_from_kept_rows_equals_a_new_reduction() {
        use FrictionTerm::*;
        let model = crate::dynamics::cheetah3::model()
            .with_friction_terms(&[Viscous, Coulomb, Load, Offset]);
        let n = model.dof();
        let [q, qd, qdd] = random_states(&model, 80, 7).map(|v| Samples::from_flat(n, v).unwrap());
        let wave = |k: usize, a: f64| {
            (0..80 * n)
                .map(|i| a * (0.3 * (i + k) as f64).sin())
                .collect()
        };
        let tau = Samples::from_flat(n, wave(1, 5.0)).unwrap();
        let load = Samples::from_flat(n, wave(5, 3.0)).unwrap();
        let joints: Vec<String> = model.joint_names().iter().map(|j| j.to_string()).collect();
        let t = (0..80).map(|s| s as f64 * 1e-3).collect();
        let train = Dataset {
            joints,
            t,
            q,
            qd,
            qdd,
            tau,
            segments: vec![],
        };
        let base = reduce_samples(&model, &train.q, &train.qd, &train.qdd, &train.tau, 16).unwrap();
        let rows = LoadRows::new(&model, &train)
            .unwrap()
            .expect("within the budget");
        let got = rows.reduce(&base, &load).unwrap();
        let states = [&train.q, &train.qd, &train.qdd, &train.tau];
        let want = reduce_with_load(&model, states, &load, 16).unwrap();
        let scale = (0..want.gram.nrows())
            .map(|i| want.gram[(i, i)])
            .fold(0.0, f64::max);
        // every entry of the full and the joints' Gram matrices
        let same = |x: &Reduced, y: &Reduced| {
            assert_eq!(x.joint_grams.len(), y.joint_grams.len());
            let pairs =
                std::iter::once((&x.gram, &y.gram)).chain(x.joint_grams.iter().zip(&y.joint_grams));
            for (a, b) in pairs {
                for j in 0..a.ncols() {
                    for i in 0..a.nrows() {
                        assert!((a[(i, j)] - b[(i, j)]).abs() <= 1e-11 * scale, "({i}, {j})");
                    }
                }
            }
        };
        assert_eq!(got.joint_grams.len(), n);
        same(&got, &want);
        // the reduction made from the kept rows is the reduction's own
        let own = LoadRows::new(&model, &train).unwrap().unwrap();
        let own = own.into_reduced(model.regressor_columns()).unwrap();
        assert!(own.load_rows.is_some() && own.samples == base.samples);
        same(&own, &base);
        // the load changed the Gram matrix: the test compares something
        let moved = (0..base.gram.nrows())
            .any(|i| (base.gram[(i, i)] - got.gram[(i, i)]).abs() > 1e-6 * scale);
        assert!(moved);
        // the rigid torques from the kept rows are the dynamics' own
        let theta: Vec<f64> = (0..model.regressor_columns())
            .map(|k| 0.1 + 0.01 * k as f64)
            .collect();
        let nb = 10 * model.num_bodies();
        let got = rows.rigid_torques(&theta, nb);
        let mut rigid = model.clone();
        rigid.set_params(&theta[..nb]).unwrap();
        let none = crate::dynamics::Friction::zeros(n);
        let want = crate::dynamics::predict::predict_torques(
            &rigid, &none, &train.q, &train.qd, &train.qdd,
        )
        .unwrap();
        let big = want.as_flat().iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (a, b) in got.as_flat().iter().zip(want.as_flat()) {
            assert!((a - b).abs() <= 1e-10 * big, "{a} vs {b}");
        }
        // a model without the load term keeps no rows
        let plain = crate::dynamics::cheetah3::model();
        assert!(LoadRows::new(&plain, &train).unwrap().is_none());
    }
}
