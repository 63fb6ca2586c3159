//! A floating-base robot's data reduced for identification: the chosen rows
//! ([`Rows`]) of `Y(q, v, a) π = [0; τ] + Σ_c J_cᵀ w_c` stacked over the
//! samples of a [`Dataset`] and reduced to their Gram matrix (as
//! [`reduce`](super::reduce) does for a fixed base), for
//! [`Identification::for_free_flyer`](super::Identification::for_free_flyer).
//!
//! The base rows need no joint torque: the contact wrenches alone balance
//! them (Ayusawa et al.), so they identify a robot with no torque sensing.

use super::error::IdentifyError;
use super::reduce::Reduced;
use crate::data::Dataset;
use crate::dynamics::{Data, Model};
use faer::Mat;
use rayon::prelude::*;

/// Which rows of the floating-base dynamics the identification fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Rows {
    /// The six base rows: the contact wrenches balance the whole robot's
    /// Newton–Euler equations (no joint torque needed).
    Base,
    /// The joint rows: joint torques plus the contacts' share.
    Joints,
    /// Every row (the base rows in N and N·m, the joints' in N·m; unweighted
    /// here, weighted by group in
    /// [`fit_floating`](super::floating_fit::fit_floating)).
    All,
}

impl Rows {
    /// The rows of the generalized force (6 + n) these are.
    pub fn range(self, joints: usize) -> std::ops::Range<usize> {
        match self {
            Rows::Base => 0..6,
            Rows::Joints => 6..6 + joints,
            Rows::All => 0..6 + joints,
        }
    }

    /// The name (`base`, `joints`, `all`).
    pub fn as_str(self) -> &'static str {
        match self {
            Rows::Base => "base",
            Rows::Joints => "joints",
            Rows::All => "all",
        }
    }

    /// The rows `asked`, else every row when each log has joint torques,
    /// else the base rows; with the default, the words saying which and
    /// why. Rows with joints asked of a log without torques are an error.
    pub fn for_logs(
        asked: Option<Rows>,
        logs: &[Dataset],
    ) -> Result<(Rows, Option<&'static str>), IdentifyError> {
        let torques = logs.iter().all(Dataset::has_torques);
        match asked {
            Some(r) if r != Rows::Base && !torques => {
                Err(IdentifyError::NoTorquesForRows { rows: r.as_str() })
            }
            Some(r) => Ok((r, None)),
            None if torques => Ok((Rows::All, Some("every row (the logs have joint torques)"))),
            None => Ok((
                Rows::Base,
                Some("the base rows (the logs have no joint torques)"),
            )),
        }
    }
}

/// Samples per chunk of the reduction.
const CHUNK: usize = 256;

/// The Gram matrix `[A b]ᵀ[A b]` of the chosen rows of every sample of
/// `log` (checked against `ff` first): A the regressor
/// ([`crate::dynamics::regressor`]), b the measured generalized force.
pub fn reduce_floating(ff: &Model, log: &Dataset, rows: Rows) -> Result<Reduced, IdentifyError> {
    reduce_floating_weighted(ff, log, rows, None)
}

/// [`reduce_floating`] with each row of the generalized force (6 + n)
/// weighted by `weights` (≥ 0, finite; e.g. 1/σ² of its noise).
pub fn reduce_floating_weighted(
    ff: &Model,
    log: &Dataset,
    rows: Rows,
    weights: Option<&[f64]>,
) -> Result<Reduced, IdentifyError> {
    log.check(ff)?;
    if let Some(w) = weights {
        if w.len() != ff.nv() || w.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
            return Err(IdentifyError::RowWeights {
                found: w.len(),
                rows: ff.nv(),
            });
        }
    }
    let samples = log.len();
    if rows != Rows::Base && !log.has_torques() {
        return Err(IdentifyError::NoTrainingData {
            samples,
            torques: 0,
        });
    }
    let p1 = ff.regressor_columns() + 1;
    let chunks: Vec<usize> = (0..samples).step_by(CHUNK).collect();
    let grams = chunks
        .par_iter()
        .map(|&s0| chunk_gram(ff, (log, weights), rows, s0..(s0 + CHUNK).min(samples)))
        .collect::<Result<Vec<_>, _>>()?;
    let mut gram = Mat::<f64>::zeros(p1, p1);
    for g in grams {
        gram += g;
    }
    // XᵀX is symmetric in exact arithmetic; make it so in floating point
    let gram = Mat::from_fn(p1, p1, |i, j| 0.5 * (gram[(i, j)] + gram[(j, i)]));
    Ok(Reduced {
        row_range: Some(rows.range(ff.dof())),
        ..Reduced::from_gram(gram, samples)?
    })
}

/// One chunk's `XᵀX`, X its rows `[A b]`.
fn chunk_gram(
    ff: &Model,
    (log, weights): (&Dataset, Option<&[f64]>),
    rows: Rows,
    range: std::ops::Range<usize>,
) -> Result<Mat<f64>, IdentifyError> {
    let (n, p) = (ff.dof(), ff.regressor_columns());
    let r = rows.range(n);
    let mut x = Mat::<f64>::zeros(range.len() * r.len(), p + 1);
    let mut data = Data::new(ff);
    for (local, k) in range.enumerate() {
        let b = measured(ff, &mut data, log, k)?;
        let y = sample_regressor(ff, &mut data, log, k)?;
        for (i, row) in r.clone().enumerate() {
            let (at, s) = (local * r.len() + i, weights.map_or(1.0, |w| w[row].sqrt()));
            for c in 0..p {
                x[(at, c)] = s * y[(row, c)];
            }
            x[(at, p)] = s * b[row];
        }
    }
    Ok(x.transpose() * &x)
}

/// Sample k's regressor; call after [`measured`] (which checks the
/// sample's lengths).
pub(super) fn sample_regressor<'d>(
    ff: &Model,
    data: &'d mut Data,
    log: &Dataset,
    k: usize,
) -> Result<&'d nalgebra::DMatrix<f64>, IdentifyError> {
    // (sample k's lengths were checked by `measured`, called first)
    // without torques only the base rows are fitted, where no friction acts
    match log.tau.is_empty() {
        false => data.load.copy_from_slice(&log.tau[k]),
        true => data.load.fill(0.0),
    }
    let (q, v, a) = log.state(k);
    crate::dynamics::regressor(ff, data, &q, &v, &a)
        .map_err(|source| IdentifyError::Regressor { sample: k, source })
}

/// Sample k's measured generalized force `[0; τ] + Σ_c J_cᵀ w_c` (6 + n;
/// the joint part zero without torques).
pub fn measured(
    ff: &Model,
    data: &mut Data,
    log: &Dataset,
    k: usize,
) -> Result<nalgebra::DVector<f64>, IdentifyError> {
    let fail = |source| IdentifyError::Regressor { sample: k, source };
    let contacts = log.contacts_at(ff, k).map_err(fail)?; // (checks sample k's lengths)
    let (q, _, _) = log.state(k);
    let mut b = ff.contact_force(data, &q, &contacts).map_err(fail)?;
    if !log.tau.is_empty() {
        for (j, t) in log.tau[k].iter().enumerate() {
            b[6 + j] += t;
        }
    }
    Ok(b)
}
