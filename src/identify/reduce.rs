//! Reduction of stacked regressor data to a (p + 1) × (p + 1) factor.
//!
//! `‖A θ − b‖²` over n_s · n rows equals `‖F [θ; −1]‖²` for any F with
//! `FᵀF = G = [A b]ᵀ[A b]`. G is accumulated over chunks of samples in
//! parallel (each chunk's rows are built, multiplied into its own Gram
//! matrix and dropped), so memory is O(p²) whatever the number of samples;
//! F comes from the eigen-decomposition of G after scaling its columns to
//! unit diagonal (a symmetric square root, which also works when the data
//! do not excite every parameter). Forming G squares the condition number
//! of the column-scaled regressor; with the unit-diagonal scaling that costs
//! about `ε·κ` relative accuracy in the fitted torques, far below any noise.

use super::error::IdentifyError;
use crate::dynamics::Model;
use faer::{Mat, MatRef};
use rayon::prelude::*;

/// The reduced least-squares data.
#[derive(Clone, Debug)]
pub struct Reduced {
    /// Gram matrix `[A b]ᵀ[A b]`, (p + 1) × (p + 1).
    pub gram: Mat<f64>,
    /// Number of samples reduced.
    pub samples: usize,
    /// Number of regressor columns p.
    pub p: usize,
}

impl Reduced {
    /// The factor F with `FᵀF = G` ((p + 1) × (p + 1)); an error if the
    /// eigen-decomposition does not converge (a non-finite Gram matrix).
    pub fn factor(&self) -> Result<Mat<f64>, IdentifyError> {
        let p1 = self.p + 1;
        let s: Vec<f64> = (0..p1).map(|i| self.gram[(i, i)].max(0.0).sqrt()).collect();
        let inv: Vec<f64> = s
            .iter()
            .map(|&v| if v > 0.0 { 1.0 / v } else { 0.0 })
            .collect();
        let gs = Mat::<f64>::from_fn(p1, p1, |i, j| self.gram[(i, j)] * inv[i] * inv[j]);
        let fail = IdentifyError::Factorisation {
            what: "eigen-decomposition of the reduced regressor's Gram matrix",
        };
        if !(0..p1).all(|j| (0..p1).all(|i| gs[(i, j)].is_finite())) {
            return Err(fail);
        }
        let evd = gs.self_adjoint_eigen(faer::Side::Lower).map_err(|_| fail)?;
        let lam = evd.S().column_vector();
        let v = evd.U();
        // F = Λ^{1/2} Vᵀ D  (rows scaled by √λ, columns by the diagonal scale)
        Ok(Mat::<f64>::from_fn(p1, p1, |k, j| {
            lam[k].max(0.0).sqrt() * v[(j, k)] * s[j]
        }))
    }

    /// `(R, d)`: R = F[:, 0..p] ((p + 1) × p) and d = F[:, p].
    pub fn r_d(&self) -> Result<(Mat<f64>, Vec<f64>), IdentifyError> {
        let f = self.factor()?;
        let r = f.as_ref().submatrix(0, 0, self.p + 1, self.p).to_owned();
        let d = (0..=self.p).map(|i| f[(i, self.p)]).collect();
        Ok((r, d))
    }
}

/// Checks that every sample has n values in each of q, q̇, q̈, τ.
fn check_lengths(
    n: usize,
    q: &[Vec<f64>],
    qd: &[Vec<f64>],
    qdd: &[Vec<f64>],
    tau: &[Vec<f64>],
) -> Result<(), IdentifyError> {
    for (what, v) in [("q", q), ("qd", qd), ("qdd", qdd), ("tau", tau)] {
        if v.len() != q.len() {
            return Err(IdentifyError::NoTrainingData {
                samples: q.len(),
                torques: tau.len(),
            });
        }
        if let Some(k) = v.iter().position(|x| x.len() != n) {
            return Err(IdentifyError::SampleLength {
                sample: k,
                what,
                expected: n,
                found: v[k].len(),
            });
        }
    }
    Ok(())
}

/// The Gram matrix of samples `start..end` (rows built, multiplied, dropped).
fn chunk_gram(
    model: &Model,
    samples: [&[Vec<f64>]; 4],
    start: usize,
    end: usize,
) -> Result<Mat<f64>, IdentifyError> {
    let [q, qd, qdd, tau] = samples;
    let n = model.dof();
    let p = 10 * model.num_bodies() + 2 * n;
    let p1 = p + 1;
    let mut data = crate::dynamics::Data::new(model);
    let mut buf = vec![0.0; (end - start) * n * p1];
    for s in start..end {
        crate::dynamics::regressor(model, &mut data, &q[s], &qd[s], &qdd[s])
            .map_err(|source| IdentifyError::Regressor { sample: s, source })?;
        let y = data.regressor.as_slice(); // column-major n × p
        for i in 0..n {
            let row = &mut buf[((s - start) * n + i) * p1..((s - start) * n + i + 1) * p1];
            for c in 0..p {
                row[c] = y[c * n + i];
            }
            row[p] = tau[s][i];
        }
    }
    let x = MatRef::from_row_major_slice(&buf, (end - start) * n, p1);
    let mut g = Mat::<f64>::zeros(p1, p1);
    faer::linalg::matmul::matmul(
        g.as_mut(),
        faer::Accum::Replace,
        x.transpose(),
        x,
        1.0,
        faer::Par::Seq,
    );
    Ok(g)
}

/// Reduces samples `q, q̇, q̈` with targets τ (columns: links, rotors,
/// viscous, Coulomb, see [`crate::dynamics::regressor`]), `chunk` samples
/// per parallel task. A sample the regressor cannot evaluate is an error
/// naming it.
pub fn reduce_samples(
    model: &Model,
    q: &[Vec<f64>],
    qd: &[Vec<f64>],
    qdd: &[Vec<f64>],
    tau: &[Vec<f64>],
    chunk: usize,
) -> Result<Reduced, IdentifyError> {
    let n = model.dof();
    check_lengths(n, q, qd, qdd, tau)?;
    let p = 10 * model.num_bodies() + 2 * n;
    let chunk = chunk.max(1);
    let starts: Vec<usize> = (0..q.len()).step_by(chunk).collect();
    let partial: Vec<Mat<f64>> = starts
        .par_iter()
        .map(|&start| {
            chunk_gram(
                model,
                [q, qd, qdd, tau],
                start,
                (start + chunk).min(q.len()),
            )
        })
        .collect::<Result<_, _>>()?;
    let mut gram = Mat::<f64>::zeros(p + 1, p + 1);
    for g in partial {
        gram += g;
    }
    Ok(Reduced {
        gram,
        samples: q.len(),
        p,
    })
}

/// A streaming reducer: push samples one at a time (e.g. while reading a
/// file or simulating); memory is one chunk of rows plus the Gram matrix,
/// whatever the number of samples.
pub struct StreamReducer<'m> {
    model: &'m Model,
    data: crate::dynamics::Data,
    buf: Vec<f64>,
    rows: usize,
    chunk_rows: usize,
    red: Reduced,
}

impl<'m> StreamReducer<'m> {
    /// A reducer for `model`, multiplying out every `chunk` samples.
    pub fn new(model: &'m Model, chunk: usize) -> Self {
        let n = model.dof();
        let p = 10 * model.num_bodies() + 2 * n;
        let chunk_rows = chunk.max(1) * n;
        Self {
            model,
            data: crate::dynamics::Data::new(model),
            buf: vec![0.0; chunk_rows * (p + 1)],
            rows: 0,
            chunk_rows,
            red: Reduced {
                gram: Mat::zeros(p + 1, p + 1),
                samples: 0,
                p,
            },
        }
    }

    /// Adds one sample.
    pub fn push(
        &mut self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        tau: &[f64],
    ) -> Result<(), crate::dynamics::DynamicsError> {
        let n = self.model.dof();
        let p = self.red.p;
        if tau.len() != n {
            return Err(crate::dynamics::DynamicsError::Dimension {
                what: "tau".into(),
                expected: n,
                found: tau.len(),
            });
        }
        crate::dynamics::regressor(self.model, &mut self.data, q, qd, qdd)?;
        let y = self.data.regressor.as_slice();
        for i in 0..n {
            let row = &mut self.buf[(self.rows + i) * (p + 1)..(self.rows + i + 1) * (p + 1)];
            for c in 0..p {
                row[c] = y[c * n + i];
            }
            row[p] = tau[i];
        }
        self.rows += n;
        self.red.samples += 1;
        if self.rows == self.chunk_rows {
            self.flush();
        }
        Ok(())
    }

    fn flush(&mut self) {
        if self.rows == 0 {
            return;
        }
        let p1 = self.red.p + 1;
        let x = MatRef::from_row_major_slice(&self.buf[..self.rows * p1], self.rows, p1);
        faer::linalg::matmul::matmul(
            self.red.gram.as_mut(),
            faer::Accum::Add,
            x.transpose(),
            x,
            1.0,
            faer::Par::Seq,
        );
        self.rows = 0;
    }

    /// The reduced data.
    pub fn finish(mut self) -> Reduced {
        self.flush();
        self.red
    }
}
