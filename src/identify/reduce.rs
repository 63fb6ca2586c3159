//! Reduction of stacked regressor data to a (p + 1) × (p + 1) factor.
//!
//! `‖A θ − b‖²` over n_s · n rows equals `‖F [θ; −1]‖²` for any F with
//! `FᵀF = G = [A b]ᵀ[A b]`. G is accumulated over chunks of samples in
//! parallel (each chunk's rows are built, multiplied into its own Gram
//! matrix and dropped), so memory is O(p²) whatever the number of samples;
//! F comes from a Cholesky factorisation of G with diagonal pivoting after
//! scaling its columns to unit diagonal (it stops at G's numerical rank, so
//! it also works when the data do not excite every parameter). Forming G
//! squares the condition number of the column-scaled regressor; with the
//! unit-diagonal scaling that costs about `ε·κ` relative accuracy in the
//! fitted torques, far below any noise.

use super::error::{GramProblem, IdentifyError};
use super::gram::{GramAcc, NotFinite};
use crate::dynamics::{Model, Samples};
use faer::Mat;
use rayon::prelude::*;

/// The reduced least-squares data.
#[derive(Clone, Debug)]
pub struct Reduced {
    /// Gram matrix `[A b]ᵀ[A b]`, (p + 1) × (p + 1), symmetric.
    pub gram: Mat<f64>,
    /// Number of samples reduced.
    pub samples: usize,
    /// Number of regressor columns p.
    pub p: usize,
    /// Per joint, the Gram matrix of its rows alone (they sum to `gram`),
    /// whence each joint's residual without predicting again
    /// ([`Reduced::joint_rss`]); empty when not kept (a robot whose
    /// n·(p + 1)² values exceed [`JOINT_GRAMS_BUDGET_BYTES`], or a Gram
    /// matrix given whole).
    pub joint_grams: Vec<Mat<f64>>,
    /// Wall-clock seconds the reduction took (0 for a Gram matrix given
    /// whole or accumulated by the caller's stream).
    pub reduce_time_s: f64,
    /// The rows of each sample reduced (`0..n` for a fixed base; a
    /// free-flyer's [`Rows`](super::Rows)): a solve whose layout fits other
    /// rows is refused. `None`: not recorded.
    pub row_range: Option<std::ops::Range<usize>>,
    /// The regressor rows, kept when the model has a load friction term
    /// (its passes replace one column: [`super::load_rows`]).
    pub(crate) load_rows: Option<std::sync::Arc<super::load_rows::LoadRows>>,
}

/// The most memory the per-joint Gram matrices kept in [`Reduced`] may take.
pub const JOINT_GRAMS_BUDGET_BYTES: usize = 8 << 20;

impl Reduced {
    /// Reduced data from a Gram matrix `[A b]ᵀ[A b]` ((p + 1) × (p + 1):
    /// square, symmetric, finite) of `samples` (≥ 1) samples, for callers
    /// with their own data path.
    pub fn from_gram(gram: Mat<f64>, samples: usize) -> Result<Self, IdentifyError> {
        let bad = IdentifyError::Gram;
        let (r, c) = (gram.nrows(), gram.ncols());
        if r != c || r < 2 {
            return Err(bad(GramProblem::Shape { rows: r, cols: c }));
        }
        if samples == 0 {
            return Err(bad(GramProblem::NoSamples));
        }
        for j in 0..c {
            for i in 0..r {
                let (a, b) = (gram[(i, j)], gram[(j, i)]);
                if !a.is_finite() {
                    return Err(bad(GramProblem::NotFinite(i, j)));
                }
                if (a - b).abs() > 1e-12 * (a.abs() + b.abs()).max(f64::MIN_POSITIVE) {
                    return Err(bad(GramProblem::NotSymmetric(i, j)));
                }
            }
        }
        Ok(Self {
            gram,
            samples,
            p: r - 1,
            joint_grams: vec![],
            reduce_time_s: 0.0,
            row_range: None,
            load_rows: None,
        })
    }

    /// A fixed base's reduction of `samples` samples of `n` joints from its
    /// Gram matrices `grams` (the full one and each joint's, lower
    /// triangles), checked finite and made symmetric; `t0` when the
    /// reduction began, `load_rows` the rows kept for a load term.
    pub(crate) fn assembled(
        (mut gram, mut joint_grams): (Mat<f64>, Vec<Mat<f64>>),
        (samples, n): (usize, usize),
        t0: std::time::Instant,
        load_rows: Option<std::sync::Arc<super::load_rows::LoadRows>>,
    ) -> Result<Self, IdentifyError> {
        finite_gram(&gram)?;
        symmetrize(&mut gram);
        joint_grams.iter_mut().for_each(symmetrize);
        Ok(Self {
            p: gram.nrows() - 1,
            gram,
            samples,
            joint_grams,
            reduce_time_s: t0.elapsed().as_secs_f64(),
            row_range: Some(0..n),
            load_rows,
        })
    }

    /// A factor F with `FᵀF = G` (r × (p + 1), r ≤ p + 1 the numerical rank
    /// of G): pivoted Cholesky of G with its columns scaled to unit diagonal
    /// (directions below `(p + 1)·ε` of that scale, unexcited by the data,
    /// are dropped), the scale put back; an error if G is not finite.
    pub fn factor(&self) -> Result<Mat<f64>, IdentifyError> {
        let p1 = self.p + 1;
        let s: Vec<f64> = (0..p1).map(|i| self.gram[(i, i)].max(0.0).sqrt()).collect();
        let inv: Vec<f64> = s
            .iter()
            .map(|&v| if v > 0.0 { 1.0 / v } else { 0.0 })
            .collect();
        let mut gs: Vec<f64> = (0..p1 * p1)
            .map(|ij| {
                let (i, j) = (ij / p1, ij % p1);
                self.gram[(i, j)] * inv[i] * inv[j]
            })
            .collect();
        let tol = p1 as f64 * f64::EPSILON;
        let (f, rank) = crate::linalg::pivoted_cholesky(&mut gs, p1, tol).ok_or(
            IdentifyError::Factorisation {
                what: "Cholesky factorisation of the reduced regressor's Gram matrix",
            },
        )?;
        Ok(Mat::<f64>::from_fn(rank, p1, |k, j| f[k * p1 + j] * s[j]))
    }

    /// Per joint, the residual sum of squares `Σ (yᵢ θ − τᵢ)²` over the
    /// samples, from its Gram matrix (`[θ; −1]ᵀ Gᵢ [θ; −1]`, at least 0);
    /// `None` when the per-joint matrices were not kept.
    pub fn joint_rss(&self, theta: &[f64]) -> Option<Vec<f64>> {
        if self.joint_grams.is_empty() || theta.len() != self.p {
            return None;
        }
        let x = |k: usize| if k < self.p { theta[k] } else { -1.0 };
        let quad = |g: &Mat<f64>| {
            let mut sum = 0.0;
            for j in 0..=self.p {
                let col: f64 = (0..=self.p).map(|i| g[(i, j)] * x(i)).sum();
                sum += x(j) * col;
            }
            sum.max(0.0)
        };
        Some(self.joint_grams.iter().map(quad).collect())
    }

    /// `(R, d)`: R = F[:, 0..p] (r × p) and d = F[:, p] (r), F the
    /// [`factor`](Self::factor).
    pub fn r_d(&self) -> Result<(Mat<f64>, Vec<f64>), IdentifyError> {
        let f = self.factor()?;
        let r = f.as_ref().submatrix(0, 0, f.nrows(), self.p).to_owned();
        let d = (0..f.nrows()).map(|i| f[(i, self.p)]).collect();
        Ok((r, d))
    }
}

/// Copies the lower triangle of `g` to its upper triangle.
fn symmetrize(g: &mut Mat<f64>) {
    for j in 0..g.ncols() {
        for i in j + 1..g.nrows() {
            g[(j, i)] = g[(i, j)];
        }
    }
}

/// A sample's regressor row and torque must be finite: an overflow (a huge
/// velocity squared, say) is named where it happens, not left to turn the
/// Gram matrix into NaN; `first` is the chunk's first sample.
pub(crate) fn not_finite(first: usize, e: NotFinite) -> IdentifyError {
    IdentifyError::NonFinite {
        sample: first + e.sample,
        what: if e.torque {
            "its torque is not finite"
        } else {
            "its regressor overflowed (q, q̇ or q̈ too large)"
        },
    }
}

/// The Gram matrix must be finite after the sums.
pub(crate) fn finite_gram(g: &Mat<f64>) -> Result<(), IdentifyError> {
    let ok = (0..g.ncols()).all(|j| (j..g.nrows()).all(|i| g[(i, j)].is_finite()));
    if ok {
        Ok(())
    } else {
        Err(IdentifyError::Overflow {
            what: "the Gram matrix of the regressor (the data are too large)",
        })
    }
}

/// Checks that q, q̇, q̈, τ have as many samples, of n values each.
fn check_lengths(
    n: usize,
    q: &Samples,
    qd: &Samples,
    qdd: &Samples,
    tau: &Samples,
) -> Result<(), IdentifyError> {
    for (what, v) in [("q", q), ("qd", qd), ("qdd", qdd), ("tau", tau)] {
        if v.len() != q.len() {
            return Err(IdentifyError::SampleCount {
                what,
                expected: q.len(),
                found: v.len(),
            });
        }
        if v.width() != n && !v.is_empty() {
            return Err(IdentifyError::SampleLength {
                sample: 0,
                what,
                expected: n,
                found: v.width(),
            });
        }
    }
    Ok(())
}

/// What identifying `samples` samples of a model needs, estimated before
/// anything is allocated ([`cost`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cost {
    /// Peak memory (bytes): the Gram accumulators and row chunks of the
    /// reduction and the SDP's dense quadratic term and KKT factor.
    pub bytes: u64,
    /// Floating-point operations of the reduction (≈ samples · n · (p+1)² / 3).
    pub flops: f64,
}

/// The memory an identification may plan for by default (8 GiB).
pub const DEFAULT_MAX_MEMORY_BYTES: u64 = 8 << 30;

/// The [`Cost`] of identifying `samples` samples of `model`.
pub fn cost(model: &Model, samples: usize) -> Cost {
    let n = model.dof() as u64;
    let p1 = model.regressor_columns() as u64 + 1;
    let threads = rayon::current_num_threads() as u64;
    let gram = 8 * p1 * p1 * (threads + 2);
    let rows = ROWS_BUDGET_BYTES as u64 * threads;
    let sdp = 4 * 16 * p1 * p1;
    Cost {
        bytes: gram + rows + sdp,
        flops: samples as f64 * n as f64 * (p1 * p1) as f64 / 3.0,
    }
}

/// Whether the per-joint Gram matrices fit [`JOINT_GRAMS_BUDGET_BYTES`].
pub(crate) fn keep_joint_grams(n: usize, p1: usize) -> bool {
    n * p1 * p1 * std::mem::size_of::<f64>() <= JOINT_GRAMS_BUDGET_BYTES
}

/// Regressor rows one task may hold at once (bytes): the chunk of samples
/// shrinks for robots with many joints, so memory does not grow as
/// chunk × n × p.
pub const ROWS_BUDGET_BYTES: usize = 32 << 20;

/// At most `chunk` samples, and no more than [`ROWS_BUDGET_BYTES`] of rows.
fn chunk_for(chunk: usize, n: usize, p1: usize) -> usize {
    let per_sample = (n * p1 * std::mem::size_of::<f64>()).max(1);
    chunk.min(ROWS_BUDGET_BYTES / per_sample).max(1)
}

/// One thread's work space: its Gram sums, a chunk of rows and the
/// dynamics' scratch, made once per thread, not once per chunk.
struct Acc {
    gram: GramAcc,
    data: crate::dynamics::Data,
}

impl Acc {
    fn new(model: &Model, chunk: usize) -> Self {
        Self {
            gram: GramAcc::new(model, chunk),
            data: crate::dynamics::Data::new(model),
        }
    }

    /// Another thread's sums added to these.
    fn merge(self, other: Self) -> Self {
        Self {
            gram: self.gram.merge(other.gram),
            data: self.data,
        }
    }

    /// Adds the Gram matrix of samples `start..end` (rows built,
    /// multiplied, dropped).
    fn add(
        &mut self,
        model: &Model,
        samples: [&Samples; 5],
        range: std::ops::Range<usize>,
    ) -> Result<(), IdentifyError> {
        let [q, qd, qdd, tau, load] = samples;
        let first = range.start;
        for s in range {
            let state = [&q[s], &qd[s], &qdd[s]];
            (self.gram)
                .push_state(model, &mut self.data, state, [&tau[s], &load[s]])
                .map_err(|source| IdentifyError::Regressor { sample: s, source })?;
        }
        self.gram.flush().map_err(|e| not_finite(first, e))
    }
}

/// Reduces samples `q, q̇, q̈` with targets τ (columns: links, rotors,
/// friction terms, see [`crate::dynamics::regressor`]), `chunk` samples
/// per parallel task; the load friction column's load is τ. A sample the
/// regressor cannot evaluate is an error naming it.
pub fn reduce_samples(
    model: &Model,
    q: &Samples,
    qd: &Samples,
    qdd: &Samples,
    tau: &Samples,
    chunk: usize,
) -> Result<Reduced, IdentifyError> {
    reduce_with_load(model, [q, qd, qdd, tau], tau, chunk)
}

/// [`reduce_samples`] with the load friction column's load (N·m, a row of
/// n per sample) given apart from the targets τ.
pub(crate) fn reduce_with_load(
    model: &Model,
    [q, qd, qdd, tau]: [&Samples; 4],
    load: &Samples,
    chunk: usize,
) -> Result<Reduced, IdentifyError> {
    let t0 = std::time::Instant::now();
    let n = model.dof();
    check_lengths(n, q, qd, qdd, tau)?;
    check_lengths(n, q, qd, qdd, load)?;
    let p = model.regressor_columns();
    let chunk = chunk_for(chunk, n, p + 1);
    let starts: Vec<usize> = (0..q.len()).step_by(chunk).collect();
    // one Gram accumulator per thread, not one per chunk
    // rounded down: a count that does not divide evenly must still split
    // (rounded up, 39 chunks on 2 threads would need halves of 20 and stay whole)
    let per_thread = (starts.len() / rayon::current_num_threads()).max(1);
    let acc = starts
        .par_iter()
        .with_min_len(per_thread)
        .try_fold(
            || Acc::new(model, chunk),
            |mut acc, &start| {
                let end = (start + chunk).min(q.len());
                acc.add(model, [q, qd, qdd, tau, load], start..end)
                    .map(|()| acc)
            },
        )
        .try_reduce(|| Acc::new(model, 1), |a, b| Ok(a.merge(b)))?;
    let grams = (acc.gram)
        .finish(keep_joint_grams(n, p + 1))
        .map_err(|e| not_finite(0, e))?; // every chunk was flushed: nothing is left to fail
    Reduced::assembled(grams, (q.len(), n), t0, None)
}

/// A streaming reducer: push samples one at a time (e.g. while reading a
/// file or simulating); memory is one chunk of rows plus the Gram matrix,
/// whatever the number of samples.
pub struct StreamReducer<'m> {
    model: &'m Model,
    data: crate::dynamics::Data,
    gram: GramAcc,
    chunk: usize,
    samples: usize,
    /// The index of the first sample pushed (for errors).
    first: usize,
}

impl<'m> StreamReducer<'m> {
    /// A reducer for `model`, multiplying out every `chunk` samples.
    pub fn new(model: &'m Model, chunk: usize) -> Self {
        Self::starting_at(model, chunk, 0)
    }

    /// [`new`](Self::new), for samples whose first is sample `first` of
    /// the whole (errors name samples by that count): one of several
    /// reducers of parts of the data, [`merge`](Self::merge)d at the end.
    pub fn starting_at(model: &'m Model, chunk: usize, first: usize) -> Self {
        let n = model.dof();
        let p = model.regressor_columns();
        let chunk = chunk_for(chunk, n, p + 1);
        Self {
            model,
            data: crate::dynamics::Data::new(model),
            gram: GramAcc::new(model, chunk),
            chunk,
            samples: 0,
            first,
        }
    }

    /// The samples pushed.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Multiplies out the samples pushed and frees the room for the next
    /// chunk (kept: the sums), for a reducer kept only to be
    /// [`merge`](Self::merge)d; an error if a value overflowed.
    pub fn compact(mut self) -> Result<Self, IdentifyError> {
        let first = self.first + self.samples - self.gram.samples;
        self.gram.compact().map_err(|e| not_finite(first, e))?;
        Ok(self)
    }

    /// The sums of `other` (of the same model) added to these; a chunk
    /// not yet multiplied out is first (an error if its values overflow).
    pub fn merge(mut self, mut other: Self) -> Result<Self, IdentifyError> {
        for r in [&mut self, &mut other] {
            let first = r.first + r.samples - r.gram.samples;
            r.gram.flush().map_err(|e| not_finite(first, e))?;
        }
        self.gram = self.gram.merge(other.gram);
        self.samples += other.samples;
        Ok(self)
    }

    /// Adds one sample.
    pub fn push(
        &mut self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        tau: &[f64],
    ) -> Result<(), IdentifyError> {
        let n = self.model.dof();
        let sample = self.first + self.samples;
        if tau.len() != n {
            return Err(IdentifyError::SampleLength {
                sample,
                what: "tau",
                expected: n,
                found: tau.len(),
            });
        }
        (self.gram)
            .push_state(self.model, &mut self.data, [q, qd, qdd], [tau, tau])
            .map_err(|source| IdentifyError::Regressor { sample, source })?;
        self.samples += 1;
        if self.gram.samples == self.chunk {
            let first = self.first + self.samples - self.chunk;
            self.gram.flush().map_err(|e| not_finite(first, e))?;
        }
        Ok(())
    }

    /// The reduced data (with each joint's Gram matrix, as
    /// [`reduce_samples`] keeps them); an error if the sums overflowed.
    pub fn finish(self) -> Result<Reduced, IdentifyError> {
        let first = self.first + self.samples - self.gram.samples;
        let (n, p) = (self.model.dof(), self.model.regressor_columns());
        let grams = (self.gram)
            .finish(keep_joint_grams(n, p + 1))
            .map_err(|e| not_finite(first, e))?;
        let red = Reduced::assembled(grams, (self.samples, n), std::time::Instant::now(), None)?;
        // (the caller's stream timed the reduction)
        Ok(Reduced {
            reduce_time_s: 0.0,
            ..red
        })
    }
}

/// Test helper: every entry of the full and the joints' Gram matrices of
/// `x` and `y` agree to `rel` of `y`'s largest diagonal entry.
#[cfg(test)]
pub(crate) fn assert_same(x: &Reduced, y: &Reduced, rel: f64) {
    let scale = (0..y.gram.nrows())
        .map(|i| y.gram[(i, i)])
        .fold(0.0, f64::max);
    assert_eq!((x.samples, x.p), (y.samples, y.p));
    assert_eq!(x.joint_grams.len(), y.joint_grams.len());
    let pairs = std::iter::once((&x.gram, &y.gram)).chain(x.joint_grams.iter().zip(&y.joint_grams));
    for (a, b) in pairs {
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                assert!((a[(i, j)] - b[(i, j)]).abs() <= rel * scale, "({i}, {j})");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::symmetrize;
    use crate::identify::gram::GramAcc;

    /// The grouped, structure-exploiting Gram equals the dense `XᵀX`.
    #[test]
    fn grouped_gram_equals_the_dense_product() {
        let (samples, n, p) = (37, 3, 10);
        // joint i's rows are zero in columns 3i..3i+3 and in column 9 - i
        let x = |s: usize, i: usize, c: usize| {
            if (3 * i..3 * i + 3).contains(&c) || c == 9 - i {
                0.0
            } else {
                ((s * 31 + i * 7 + c * 13) % 17) as f64 - 8.0
            }
        };
        // the columns each joint's rows may be non-zero in (τ added by GramAcc)
        let cols = (0..n)
            .map(|i| {
                (0..p)
                    .filter(|&c| x(0, i, c) != 0.0 || x(1, i, c) != 0.0)
                    .collect()
            })
            .collect();
        let mut rows = GramAcc::with_columns(p + 1, cols, 8);
        for s in 0..samples {
            // column-major n × p regressor, then the torques (column p)
            let y: Vec<f64> = (0..p)
                .flat_map(|c| (0..n).map(move |i| x(s, i, c)))
                .collect();
            let tau: Vec<f64> = (0..n).map(|i| x(s, i, p)).collect();
            rows.push(&y, &tau);
            if s % 8 == 7 {
                rows.flush().unwrap(); // several chunks add up
            }
        }
        let (mut g, mut joints) = rows.finish(true).unwrap();
        symmetrize(&mut g);
        joints.iter_mut().for_each(symmetrize);
        // each joint's residual from its own Gram matrix, for some θ
        let theta: Vec<f64> = (0..p).map(|c| 0.1 * c as f64 - 0.3).collect();
        let red = super::Reduced {
            gram: g.clone(),
            samples,
            p,
            joint_grams: joints,
            reduce_time_s: 0.0,
            row_range: None,
            load_rows: None,
        };
        let rss = red.joint_rss(&theta).unwrap();
        for (i, got) in rss.iter().enumerate() {
            let want: f64 = (0..samples)
                .map(|s| ((0..p).map(|c| x(s, i, c) * theta[c]).sum::<f64>() - x(s, i, p)).powi(2))
                .sum();
            assert!(
                (got - want).abs() < 1e-9 * want,
                "joint {i}: {got} vs {want}"
            );
        }
        for a in 0..=p {
            for b in 0..=p {
                let want: f64 = (0..samples)
                    .flat_map(|s| (0..n).map(move |i| (s, i)))
                    .map(|(s, i)| x(s, i, a) * x(s, i, b))
                    .sum();
                assert!(
                    (g[(a, b)] - want).abs() < 1e-9 * (1.0 + want.abs()),
                    "{a} {b}"
                );
            }
        }
    }

    /// The regressor's rows written straight into each joint's block
    /// (`push_state`) give the Gram matrices of the dense regressor's rows,
    /// on the leg (rotors carried and driven by other joints) at states
    /// spread over its range.
    #[test]
    fn rows_written_by_blocks_equal_the_dense_regressors() {
        let model = crate::dynamics::cheetah3::model();
        let mut data = crate::dynamics::Data::new(&model);
        let n = model.dof();
        let (mut dense, mut direct) = (GramAcc::new(&model, 64), GramAcc::new(&model, 64));
        for s in 0..50 {
            let v = |k: usize| (0.37 * (s * n + k) as f64).sin() * (1.0 + k as f64);
            let (q, qd, qdd): (Vec<f64>, Vec<f64>, Vec<f64>) =
                (0..n).map(|i| (v(i), v(i + 7), v(i + 13))).collect();
            let tau: Vec<f64> = (0..n).map(|i| v(i + 19)).collect();
            let y = crate::dynamics::regressor(&model, &mut data, &q, &qd, &qdd).unwrap();
            dense.push(y.as_slice(), &tau);
            direct
                .push_state(&model, &mut data, [&q, &qd, &qdd], [&tau, &tau])
                .unwrap();
        }
        let (a, ja) = dense.finish(true).unwrap();
        let (b, jb) = direct.finish(true).unwrap();
        let scale = (0..a.nrows()).map(|i| a[(i, i)]).fold(0.0, f64::max);
        for (x, y) in std::iter::once((&a, &b)).chain(ja.iter().zip(&jb)) {
            for j in 0..x.ncols() {
                for i in 0..x.nrows() {
                    assert!((x[(i, j)] - y[(i, j)]).abs() <= 1e-12 * scale, "({i}, {j})");
                }
            }
        }
        // a state of the wrong length is refused and the sample not kept
        let mut one = GramAcc::new(&model, 4);
        let (ok, short) = ([0.1; 3], [0.0; 1]);
        one.push_state(&model, &mut data, [&ok, &ok, &ok], [&ok, &ok])
            .unwrap();
        assert!(
            one.push_state(&model, &mut data, [&ok, &short, &ok], [&ok, &ok])
                .is_err()
        );
        assert_eq!(one.samples, 1);
        let (g, _) = one.finish(false).unwrap();
        let y = crate::dynamics::regressor(&model, &mut data, &ok, &ok, &ok).unwrap();
        let squares = y.iter().map(|v| v * v).sum::<f64>() + 3.0 * 0.1 * 0.1; // and τ's
        let trace = (0..g.nrows()).map(|i| g[(i, i)]).sum::<f64>();
        assert!(squares > 0.0 && (trace - squares).abs() <= 1e-12 * squares);
    }

    /// A value that is not finite is named by its sample, a regressor
    /// value before a torque of the same sample.
    #[test]
    fn the_first_value_that_is_not_finite_is_named() {
        let (n, p) = (2, 3);
        let run = |nan_torque_at: usize| {
            let mut rows = GramAcc::with_columns(p + 1, vec![vec![0, 1, 2], vec![1, 2]], 8);
            for s in 0..6 {
                let mut y = vec![1.0; n * p];
                let mut tau = vec![0.5; n];
                if s == nan_torque_at {
                    tau[1] = f64::NAN;
                }
                if s == 4 {
                    y[2 * n + 1] = f64::INFINITY; // joint 1, column 2
                    tau[0] = f64::NAN;
                }
                rows.push(&y, &tau);
            }
            rows.flush().unwrap_err()
        };
        let e = run(3);
        assert_eq!((e.sample, e.torque), (3, true));
        assert!(super::not_finite(100, e).to_string().contains("sample 103"));
        let e = run(5);
        assert_eq!((e.sample, e.torque), (4, false));
    }
}
