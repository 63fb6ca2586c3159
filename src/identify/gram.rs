//! The Gram matrix `[Y τ]ᵀ[Y τ]` of stacked regressor rows, joint by joint.
//!
//! Joint j's regressor row is zero outside the columns of the bodies and
//! friction terms j moves ([`regressor_row_columns`]): for a 7-joint arm,
//! joint 7's row has 12 non-zero columns of 84. The rows of each joint are
//! gathered, in a chunk of samples, into a dense block of only its columns
//! (and τ), and each block's `XᵀX` is added to that joint's compact Gram
//! matrix (faer's triangular product, the lower half). The full Gram matrix
//! is the joints' compact ones scattered into place, once at the end; each
//! joint's own is kept too (its residual without a second pass).

use crate::dynamics::{Data, DynamicsError, Model, regressor_blocks, regressor_row_columns};
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::{Mat, MatRef};
use rayon::prelude::*;

/// A column that is not one of a joint's.
const ABSENT: usize = usize::MAX;

/// A value of a chunk that is not finite: its sample in the chunk, and
/// whether it is a torque (else a regressor value).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct NotFinite {
    pub(crate) sample: usize,
    pub(crate) torque: bool,
}

/// A chunk of regressor rows grouped by joint, and the per-joint sums of
/// their Gram matrices.
pub(crate) struct GramAcc {
    p1: usize,
    /// Per joint, its columns in increasing order, the last `p1 − 1` (τ).
    cols: Vec<Vec<usize>>,
    /// Per joint, each column's place in its rows ([`ABSENT`]: not one of
    /// its columns).
    place: Vec<Vec<usize>>,
    /// Per joint, the chunk's rows: `samples × cols[j].len()`, row-major.
    blocks: Vec<Vec<f64>>,
    /// Samples in the chunk.
    pub(crate) samples: usize,
    /// Per joint, the lower triangle of its compact Gram matrix.
    grams: Vec<Mat<f64>>,
}

impl GramAcc {
    /// For `model`'s regressor, room for `chunk` samples a chunk.
    pub(crate) fn new(model: &Model, chunk: usize) -> Self {
        let p = model.regressor_columns();
        Self::with_columns(p + 1, regressor_row_columns(model), chunk)
    }

    /// Rows of `p1` columns (the last τ), joint j's non-zero in `cols[j]`
    /// only (increasing, each `< p1 − 1`).
    pub(crate) fn with_columns(p1: usize, mut cols: Vec<Vec<usize>>, chunk: usize) -> Self {
        cols.iter_mut().for_each(|c| c.push(p1 - 1));
        let blocks = cols
            .iter()
            .map(|c| Vec::with_capacity(chunk * c.len()))
            .collect();
        let grams = cols.iter().map(|c| Mat::zeros(c.len(), c.len())).collect();
        let place = (cols.iter())
            .map(|c| {
                let mut at = vec![ABSENT; p1];
                c.iter().enumerate().for_each(|(k, &col)| at[col] = k);
                at
            })
            .collect();
        Self {
            p1,
            cols,
            place,
            blocks,
            samples: 0,
            grams,
        }
    }

    /// Kept rows made elsewhere: joint j's `samples` rows in `blocks[j]`
    /// (row-major) over the columns `cols[j]` (increasing, the last τ's,
    /// `p1 − 1`).
    pub(crate) fn from_rows(
        p1: usize,
        cols: Vec<Vec<usize>>,
        blocks: Vec<Vec<f64>>,
        samples: usize,
    ) -> Self {
        let place = (cols.iter())
            .map(|c| {
                let mut at = vec![ABSENT; p1];
                c.iter().enumerate().for_each(|(k, &col)| at[col] = k);
                at
            })
            .collect();
        let grams = cols.iter().map(|c| Mat::zeros(c.len(), c.len())).collect();
        debug_assert!((cols.iter().zip(&blocks)).all(|(c, b)| b.len() == samples * c.len()));
        Self {
            p1,
            cols,
            place,
            blocks,
            samples,
            grams,
        }
    }

    /// Appends one sample: `y` the dense regressor (column-major
    /// n × (p1 − 1)), `tau` its n torques (the tests' reference for
    /// [`push_state`](Self::push_state)).
    #[cfg(test)]
    pub(crate) fn push(&mut self, y: &[f64], tau: &[f64]) {
        let n = self.cols.len();
        for (j, (cols, block)) in self.cols.iter().zip(&mut self.blocks).enumerate() {
            let (last, regressor) = cols.split_last().expect("τ is a column");
            block.extend(regressor.iter().map(|&c| y[c * n + j]));
            debug_assert_eq!(*last, self.p1 - 1);
            block.push(tau[j]);
        }
        self.samples += 1;
    }

    /// Appends one sample from its state `[q, q̇, q̈]`, torques `tau` and
    /// the load friction column's `load` (n each): the regressor's non-zero
    /// entries are written straight into each joint's row
    /// ([`regressor_blocks`]), with no dense row between.
    pub(crate) fn push_state(
        &mut self,
        model: &Model,
        data: &mut Data,
        state: [&[f64]; 3],
        [tau, load]: [&[f64]; 2],
    ) -> Result<(), DynamicsError> {
        for (block, cols) in self.blocks.iter_mut().zip(&self.cols) {
            block.resize(block.len() + cols.len(), 0.0);
        }
        for (block, &t) in self.blocks.iter_mut().zip(tau) {
            *block.last_mut().expect("τ is a column") = t;
        }
        data.load.iter_mut().zip(load).for_each(|(l, t)| *l = *t);
        let (blocks, cols, place, row) = (&mut self.blocks, &self.cols, &self.place, self.samples);
        let result = regressor_blocks(model, data, state, |j, col0, values| {
            // consecutive columns of joint j's (regressor_row_columns)
            let at = place[j][col0];
            let start = row * cols[j].len() + at;
            blocks[j][start..start + values.len()].copy_from_slice(values);
        });
        if result.is_err() {
            // the sample is not kept
            for (block, cols) in self.blocks.iter_mut().zip(&self.cols) {
                block.truncate(block.len() - cols.len());
            }
        } else {
            self.samples += 1;
        }
        result
    }

    /// Adds the chunk's `XᵀX` to the per-joint sums and empties it; a
    /// value that is not finite is an error naming its sample in the chunk.
    /// (Such a value makes its column's diagonal entry, a sum of squares,
    /// not finite: the diagonals are checked, the chunk only then.)
    pub(crate) fn flush(&mut self) -> Result<(), NotFinite> {
        if self.samples == 0 {
            return Ok(());
        }
        for (block, g) in self.blocks.iter().zip(&mut self.grams) {
            add_products(g, block, self.samples);
        }
        if !self.grams.iter().all(finite_diagonal)
            && let Some(e) = self.first_not_finite()
        {
            return Err(e);
        }
        // (no bad value: the sums overflowed, which the caller's check of
        // the whole Gram matrix names)
        self.blocks.iter_mut().for_each(Vec::clear);
        self.samples = 0;
        Ok(())
    }

    /// [`flush`](Self::flush)es and frees the chunk's room (kept: the
    /// sums), for an accumulator kept only to be merged.
    pub(crate) fn compact(&mut self) -> Result<(), NotFinite> {
        self.flush()?;
        self.blocks.iter_mut().for_each(|b| *b = Vec::new());
        Ok(())
    }

    /// The chunk's first sample with a value that is not finite, if any.
    fn first_not_finite(&self) -> Option<NotFinite> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        for s in 0..self.samples {
            let (mut y_bad, mut tau_bad) = (false, false);
            for b in &self.blocks {
                let k = b.len() / self.samples;
                let (tau, y) = b[s * k..(s + 1) * k].split_last().expect("τ is a column");
                y_bad |= !finite(y);
                tau_bad |= !tau.is_finite();
            }
            if y_bad || tau_bad {
                return Some(NotFinite {
                    sample: s,
                    torque: !y_bad,
                });
            }
        }
        None
    }

    /// Another accumulator's chunk (not flushed; the same columns) appended
    /// to this one's, its samples after these.
    pub(crate) fn append(&mut self, other: GramAcc) {
        for (a, b) in self.blocks.iter_mut().zip(other.blocks) {
            a.extend_from_slice(&b);
        }
        self.samples += other.samples;
    }

    /// Joint j's columns (global, increasing; the last τ).
    pub(crate) fn columns(&self, j: usize) -> &[usize] {
        &self.cols[j]
    }

    /// The products of a new column `c` (a value per sample in the chunk,
    /// not flushed) with each of joint j's columns, its column `col`
    /// (global, one of [`columns`](Self::columns)`(j)`) taken as `c`:
    /// `Σ_s c_s x_s` in `columns(j)`'s order, `Σ_s c_s²` at `col`'s place.
    pub(crate) fn column_products(&self, j: usize, col: usize, c: &[f64]) -> Vec<f64> {
        let k = self.cols[j].len();
        debug_assert_ne!(
            self.place[j][col], ABSENT,
            "column {col} is not joint {j}'s"
        );
        let mut out = vec![0.0; k];
        let rows = self.blocks[j].chunks_exact(k).take(self.samples);
        for (row, &cs) in rows.zip(c) {
            out.iter_mut().zip(row).for_each(|(o, x)| *o += cs * x);
        }
        out[self.place[j][col]] = c.iter().take(self.samples).map(|v| v * v).sum();
        out
    }

    /// Per sample in the chunk (not flushed), the product of joint j's row
    /// with `w`, a weight per leading column of `columns(j)` (the rest
    /// weigh 0).
    pub(crate) fn row_products(&self, j: usize, w: &[f64]) -> Vec<f64> {
        let k = self.cols[j].len();
        (self.blocks[j].chunks_exact(k).take(self.samples))
            .map(|row| row.iter().zip(w).map(|(x, v)| x * v).sum())
            .collect()
    }

    /// Another accumulator's sums (flushed) added to these.
    pub(crate) fn merge(mut self, other: Self) -> Self {
        for (a, b) in self.grams.iter_mut().zip(other.grams) {
            *a += b;
        }
        self
    }

    /// The full Gram matrix (lower triangle) and, when `per_joint`, each
    /// joint's (lower triangle; empty otherwise), after a last flush.
    pub(crate) fn finish(
        mut self,
        per_joint: bool,
    ) -> Result<(Mat<f64>, Vec<Mat<f64>>), NotFinite> {
        self.flush()?;
        Ok(scattered(self.p1, &self.cols, &self.grams, per_joint))
    }

    /// What [`finish`](Self::finish) would give for the rows of the chunk
    /// alone (not flushed), the rows kept.
    pub(crate) fn kept_grams(
        &self,
        per_joint: bool,
    ) -> Result<(Mat<f64>, Vec<Mat<f64>>), NotFinite> {
        // the joints in parallel (each product on one thread)
        let grams: Vec<Mat<f64>> = (self.cols.par_iter().zip(&self.blocks))
            .map(|(c, block)| {
                let mut g = Mat::zeros(c.len(), c.len());
                add_products(&mut g, block, self.samples);
                g
            })
            .collect();
        if !grams.iter().all(finite_diagonal)
            && let Some(e) = self.first_not_finite()
        {
            return Err(e);
        }
        Ok(scattered(self.p1, &self.cols, &grams, per_joint))
    }
}

/// Adds the lower triangle of `XᵀX` to `g`, X the `samples` row-major
/// rows of `block`.
pub(crate) fn add_products(g: &mut Mat<f64>, block: &[f64], samples: usize) {
    let x = MatRef::from_row_major_slice(block, samples, g.ncols());
    triangular::matmul(
        g.as_mut(),
        BlockStructure::TriangularLower,
        faer::Accum::Add,
        x.transpose(),
        BlockStructure::Rectangular,
        x,
        BlockStructure::Rectangular,
        1.0,
        faer::Par::Seq,
    );
}

fn finite_diagonal(g: &Mat<f64>) -> bool {
    (0..g.ncols()).all(|i| g[(i, i)].is_finite())
}

/// The full Gram matrix (lower triangle) of the joints' compact ones
/// `grams` (columns `cols`, `p1` in all) and, when `per_joint`, each
/// joint's in place (lower triangle; empty otherwise).
pub(crate) fn scattered(
    p1: usize,
    cols: &[Vec<usize>],
    grams: &[Mat<f64>],
    per_joint: bool,
) -> (Mat<f64>, Vec<Mat<f64>>) {
    let mut full = Mat::<f64>::zeros(p1, p1);
    let mut joints = vec![];
    for (cols, g) in cols.iter().zip(grams) {
        scatter_lower(&mut full, cols, g);
        if per_joint {
            let mut m = Mat::<f64>::zeros(p1, p1);
            scatter_lower(&mut m, cols, g);
            joints.push(m);
        }
    }
    (full, joints)
}

/// Adds the lower triangle of the compact `g` (rows and columns `cols` of
/// the full matrix) to the lower triangle of `full`.
fn scatter_lower(full: &mut Mat<f64>, cols: &[usize], g: &Mat<f64>) {
    for (b, &cb) in cols.iter().enumerate() {
        for (a, &ca) in cols.iter().enumerate().skip(b) {
            full[(ca, cb)] += g[(a, b)];
        }
    }
}
