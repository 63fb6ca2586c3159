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
//! The reductions made from them: [`super::load_passes`].
//!
//! [`Identification::fit`]: super::Identification::fit

use super::error::IdentifyError;
use super::gram::GramAcc;
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
    /// The load the rows' load column was made with.
    load: Samples,
}

impl std::fmt::Debug for LoadRows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LoadRows {{ {} samples }}", self.qd.len())
    }
}

impl LoadRows {
    /// The peak memory (bytes) of keeping `samples` samples' rows for
    /// `model`: twice the rows (their pieces are joined), 0 when `model`
    /// has no load term or the rows would exceed [`LOAD_ROWS_BUDGET_BYTES`]
    /// (then none are kept).
    pub(crate) fn bytes(model: &Model, samples: usize) -> usize {
        if !model.friction_terms().contains(&FrictionTerm::Load) {
            return 0;
        }
        let per_sample: usize = (regressor_row_columns(model).iter())
            .map(|c| (c.len() + 1) * std::mem::size_of::<f64>())
            .sum();
        match per_sample.saturating_mul(samples) {
            b if b > LOAD_ROWS_BUDGET_BYTES => 0,
            b => 2 * b,
        }
    }

    /// `train`'s rows for `model` (which has a load term), or `None` when
    /// they would take over [`LOAD_ROWS_BUDGET_BYTES`] or the model has
    /// no load term.
    pub(crate) fn new(model: &Model, train: &Dataset) -> Result<Option<Self>, IdentifyError> {
        let terms = model.friction_terms();
        let Some(t) = terms.iter().position(|t| *t == FrictionTerm::Load) else {
            return Ok(None);
        };
        if Self::bytes(model, train.len()) == 0 {
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
            load: train.tau.clone(),
        }))
    }

    /// Rows built elsewhere ([`super::choice_pass`]) for `model` (which
    /// has a load term: else `None`), the samples' velocities `qd`, the
    /// load column made with `load`.
    pub(crate) fn from_rows(
        model: &Model,
        rows: GramAcc,
        qd: Samples,
        load: Samples,
    ) -> Option<Self> {
        let terms = model.friction_terms();
        let t = terms.iter().position(|t| *t == FrictionTerm::Load)?;
        let (n, nb) = (model.dof(), model.num_bodies());
        Some(Self {
            rows,
            load_cols: (0..n).map(|j| 10 * nb + t * n + j).collect(),
            qd,
            load,
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

    /// The load the rows' load column was made with (N·m, n per sample):
    /// the measured torque, or the model's own rigid torque
    /// ([`super::choice_pass`]).
    pub(crate) fn load(&self) -> &Samples {
        &self.load
    }

    /// The samples kept.
    pub(crate) fn samples(&self) -> usize {
        self.qd.len()
    }

    /// The joints (each joint's rows).
    pub(crate) fn joints(&self) -> usize {
        self.load_cols.len()
    }

    /// The Gram matrices of the kept rows as they were built (the load
    /// column's load the measured torque): the full one and, when
    /// `per_joint`, each joint's (lower triangles).
    pub(crate) fn kept_grams(
        &self,
        per_joint: bool,
    ) -> Result<(faer::Mat<f64>, Vec<faer::Mat<f64>>), super::gram::NotFinite> {
        self.rows.kept_grams(per_joint)
    }

    /// Joint j's load column (global) made from `load` (N·m, n per sample),
    /// and its products with each of j's columns: (column, value).
    pub(crate) fn load_column(&self, j: usize, load: &Samples) -> (usize, Vec<(usize, f64)>) {
        let col = self.load_cols[j];
        let c: Vec<f64> = (0..self.qd.len())
            .map(|s| FrictionTerm::Load.basis(self.qd[s][j], load[s][j], 0.0))
            .collect();
        let products = self.rows.column_products(j, col, &c);
        (
            col,
            self.rows.columns(j).iter().copied().zip(products).collect(),
        )
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
