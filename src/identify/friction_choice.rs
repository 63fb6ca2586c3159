//! The friction law chosen from the training data (`--friction auto`).
//!
//! Every law of viscous + Coulomb friction with or without a torque
//! offset, load-dependent friction and Stribeck friction (its velocity one
//! of [`STRIBECK_VELOCITIES`]) is scored by cross-validation on the
//! training data alone — each file (segment) held out in turn when there
//! are several, else [`TIME_FOLDS`] blocks of time — as the identification
//! would fit it without constraints: the links' parameters and the law's
//! coefficients by least squares, `(1/n_s) Σ‖Y θ − τ‖² + w ‖π − π̂‖²` with
//! the prior and weight of the identification. One pass over the data
//! builds each fold's and joint's Gram matrix over every candidate column
//! (a joint's row has its links' columns and its own friction columns);
//! each law is then a solve of the folds' sums, scored on the held-out
//! fold by its quadratic form. A law's score is the mean over joints of
//! the held-out RMS pooled over the folds.
//!
//! **Parsimony**: the law with the fewest terms whose score is within the
//! noise of the best's is chosen — within the noise when the mean over the
//! folds of its per-fold score minus the best's is at most the standard
//! error of those differences (the one-standard-error rule, applied to
//! paired differences) or [`MIN_GAIN`] of the best's score, whichever is
//! larger. The load term's basis is the size of the rigid torque of the
//! model's own bodies (the prior's, as given; the identification then
//! iterates it on its fit's): the measured torque would carry the held-out
//! fold's noise into its own prediction.

use super::choose_weight::{Folds, MIN_FOLD_SAMPLES, TIME_FOLDS, folds};
use super::error::IdentifyError;
use crate::data::Dataset;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{
    Data, Friction, FrictionTerm, Model, regressor_blocks, regressor_row_columns,
};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// The Stribeck velocities (rad/s) tried: a drive's breakaway region is a
/// few hundredths to a few tenths of a rad/s wide.
pub const STRIBECK_VELOCITIES: [f64; 4] = [0.02, 0.05, 0.1, 0.2];
/// The least share of the best's score a term must gain to be kept: a
/// gain under it is within the noise whatever the folds say (1 % of the
/// RMS, about the 2 % of the mean square the diagnosis asks of an effect:
/// the diagnosis' `MIN_SHARE`).
pub const MIN_GAIN: f64 = 0.01;
/// Rows gathered before they are multiplied into a Gram matrix.
const CHUNK: usize = 256;

/// The candidate friction columns per joint, in order.
fn bases() -> Vec<(FrictionTerm, f64)> {
    let mut b = vec![
        (FrictionTerm::Viscous, 0.0),
        (FrictionTerm::Coulomb, 0.0),
        (FrictionTerm::Offset, 0.0),
        (FrictionTerm::Load, 0.0),
    ];
    b.extend(STRIBECK_VELOCITIES.map(|v| (FrictionTerm::Stribeck, v)));
    b
}

/// One candidate law and its cross-validated error.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LawScore {
    /// Its terms.
    pub terms: Vec<String>,
    /// Its Stribeck velocity (rad/s), with a Stribeck term.
    pub stribeck_velocity: Option<f64>,
    /// Per joint, the held-out RMS pooled over the folds (N·m).
    pub heldout_rms: Vec<f64>,
    /// The mean over joints of `heldout_rms` (N·m).
    pub mean_rms: f64,
    /// Per fold, the mean over joints of that fold's held-out RMS (N·m).
    pub fold_rms: Vec<f64>,
}

/// The friction law chosen and the table it was chosen from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrictionChoice {
    /// How the training data were split.
    pub folds: Folds,
    /// Number of folds.
    pub k: usize,
    /// Every law tried.
    pub laws: Vec<LawScore>,
    /// The index of the lowest `mean_rms`.
    pub best: usize,
    /// The index of the law chosen.
    pub chosen: usize,
    /// Why, in words.
    pub rule: String,
}

impl FrictionChoice {
    /// The chosen law's terms.
    pub fn terms(&self) -> Vec<FrictionTerm> {
        (self.laws[self.chosen].terms.iter())
            .filter_map(|t| FrictionTerm::parse(t))
            .collect()
    }

    /// The chosen law's Stribeck velocity, if it has the term.
    pub fn stribeck_velocity(&self) -> Option<f64> {
        self.laws[self.chosen].stribeck_velocity
    }
}

impl super::Identification<'_> {
    /// [`choose_friction`] for this identification's model, prior and
    /// weight (the prior's when one is set, else none).
    pub fn choose_friction(&self, train: &Dataset) -> Result<FrictionChoice, IdentifyError> {
        self.fixed_base("Identification::choose_friction")?;
        choose_friction(self.model, train, &self.prior, self.weight)
    }
}

/// A law: which of [`bases`] it has.
fn laws() -> Vec<Vec<usize>> {
    let mut out = vec![];
    for offset in [false, true] {
        for load in [false, true] {
            for stribeck in [None, Some(4), Some(5), Some(6), Some(7)] {
                let mut l = vec![0, 1];
                l.extend(offset.then_some(2));
                l.extend(load.then_some(3));
                l.extend(stribeck);
                out.push(l);
            }
        }
    }
    out
}

/// One fold's and joint's sums: `G = Σ yᵀy`, `b = Σ yᵀτ`, `c = Σ τ²`, over
/// the joint's compact rows (its links' columns, then every basis).
struct Sums {
    g: DMatrix<f64>,
    b: DVector<f64>,
    c: f64,
    rows: usize,
    buf: Vec<f64>,
    tau: Vec<f64>,
}

impl Sums {
    fn new(w: usize) -> Self {
        Self {
            g: DMatrix::zeros(w, w),
            b: DVector::zeros(w),
            c: 0.0,
            rows: 0,
            buf: vec![],
            tau: vec![],
        }
    }

    fn push(&mut self, row: &[f64], tau: f64) {
        self.buf.extend_from_slice(row);
        self.tau.push(tau);
        if self.tau.len() == CHUNK {
            self.flush();
        }
    }

    fn flush(&mut self) {
        let (m, w) = (self.tau.len(), self.g.nrows());
        if m > 0 {
            let y = DMatrix::from_row_slice(m, w, &self.buf);
            let t = DVector::from_column_slice(&self.tau);
            let yt = y.transpose();
            self.g += &yt * &y;
            self.b += &yt * &t;
            self.c += t.dot(&t);
            self.rows += m;
        }
        self.buf.clear();
        self.tau.clear();
    }
}

/// Chooses the friction law for `model`'s links and rotors (its own
/// friction terms ignored) on `train` (module doc), with the
/// identification's `prior` (10 per body, or empty) and `weight`.
pub fn choose_friction(
    model: &Model,
    train: &Dataset,
    prior: &[f64],
    weight: f64,
) -> Result<FrictionChoice, IdentifyError> {
    let links = model.clone().with_friction_terms(&[]);
    let (kind, pairs) = folds(train, TIME_FOLDS);
    let held: Vec<Dataset> = pairs.into_iter().map(|(_, h)| h).collect();
    if let Some((fold, h)) = held
        .iter()
        .enumerate()
        .find(|(_, h)| h.len() < MIN_FOLD_SAMPLES)
    {
        return Err(IdentifyError::FoldTooSmall {
            fold,
            training: train.len() - h.len(),
            held_out: h.len(),
            min: MIN_FOLD_SAMPLES,
        });
    }
    let cols = regressor_row_columns(&links);
    let sums = held
        .iter()
        .map(|h| fold_sums(&links, h, &cols))
        .collect::<Result<Vec<_>, _>>()?;
    let pb = 10 * links.num_bodies();
    let laws: Vec<LawScore> = (laws().iter())
        .map(|l| score(l, &sums, &cols, (pb, prior, weight)))
        .collect::<Result<_, _>>()?;
    Ok(conclude(kind, held.len(), laws))
}

/// Each joint's sums over the samples of `d` (one fold).
fn fold_sums(links: &Model, d: &Dataset, cols: &[Vec<usize>]) -> Result<Vec<Sums>, IdentifyError> {
    let (n, p) = (links.dof(), links.regressor_columns());
    let nb = bases();
    let mut at = vec![vec![usize::MAX; p]; n];
    (cols.iter().enumerate())
        .for_each(|(j, cs)| cs.iter().enumerate().for_each(|(a, &c)| at[j][c] = a));
    let mut sums: Vec<Sums> = cols.iter().map(|c| Sums::new(c.len() + nb.len())).collect();
    let mut row: Vec<Vec<f64>> = cols.iter().map(|c| vec![0.0; c.len() + nb.len()]).collect();
    // the load term's basis: the rigid torque of the model's own bodies (the
    // measured torque would carry the held-out noise into the column)
    let rigid = predict_torques(links, &Friction::zeros(n), &d.q, &d.qd, &d.qdd)
        .map_err(|source| IdentifyError::Regressor { sample: 0, source })?;
    let mut data = Data::new(links);
    for k in 0..d.len() {
        row.iter_mut().for_each(|r| r.fill(0.0));
        regressor_blocks(
            links,
            &mut data,
            [&d.q[k], &d.qd[k], &d.qdd[k]],
            |j, c0, v| (v.iter().enumerate()).for_each(|(a, x)| row[j][at[j][c0 + a]] += x),
        )
        .map_err(|source| IdentifyError::Regressor { sample: k, source })?;
        for j in 0..n {
            let l = cols[j].len();
            for (t, (term, vs)) in nb.iter().enumerate() {
                row[j][l + t] = term.basis(d.qd[k][j], rigid[k][j], *vs);
            }
            sums[j].push(&row[j], d.tau[k][j]);
        }
    }
    sums.iter_mut().for_each(Sums::flush);
    Ok(sums)
}

/// The cross-validated score of `law` (indices of [`bases`]).
fn score(
    law: &[usize],
    sums: &[Vec<Sums>],
    cols: &[Vec<usize>],
    (pb, prior, weight): (usize, &[f64], f64),
) -> Result<LawScore, IdentifyError> {
    let n = cols.len();
    let p = pb + law.len() * n;
    // joint j's compact index → global unknown, for the law's columns
    let map: Vec<Vec<(usize, usize)>> = (0..n)
        .map(|j| {
            let l = cols[j].len();
            let mut m: Vec<(usize, usize)> =
                cols[j].iter().enumerate().map(|(a, &c)| (a, c)).collect();
            m.extend(
                law.iter()
                    .enumerate()
                    .map(|(s, &t)| (l + t, pb + s * n + j)),
            );
            m
        })
        .collect();
    let k = sums.len();
    let (mut sse, mut rows) = (vec![vec![0.0; n]; k], vec![0usize; k]);
    for f in 0..k {
        let (mut g, mut b) = (DMatrix::<f64>::zeros(p, p), DVector::<f64>::zeros(p));
        let mut ns = 0usize;
        for fold in (sums.iter().enumerate())
            .filter(|(h, _)| *h != f)
            .map(|(_, s)| s)
        {
            ns += fold[0].rows;
            for (j, s) in fold.iter().enumerate() {
                for &(a, ga) in &map[j] {
                    b[ga] += s.b[a];
                    map[j]
                        .iter()
                        .for_each(|&(e, ge)| g[(ga, ge)] += s.g[(a, e)]);
                }
            }
        }
        let scale = 1.0 / ns.max(1) as f64;
        g *= scale;
        b *= scale;
        let ridge = 1e-10 * (g.trace() / p as f64).max(f64::MIN_POSITIVE);
        for i in 0..p {
            let w = if i < pb && prior.len() == pb {
                weight
            } else {
                0.0
            };
            g[(i, i)] += w + ridge;
            b[i] += if i < pb && prior.len() == pb {
                weight * prior[i]
            } else {
                0.0
            };
        }
        let theta = (g.cholesky())
            .ok_or(IdentifyError::Factorisation {
                what: "Cholesky factorisation of a friction law's Gram matrix",
            })?
            .solve(&b);
        for (j, s) in sums[f].iter().enumerate() {
            let th: Vec<(usize, f64)> = map[j].iter().map(|&(a, ga)| (a, theta[ga])).collect();
            let quad: f64 = (th.iter())
                .map(|&(a, x)| x * th.iter().map(|&(e, y)| s.g[(a, e)] * y).sum::<f64>())
                .sum();
            let lin: f64 = th.iter().map(|&(a, x)| x * s.b[a]).sum();
            sse[f][j] = (quad - 2.0 * lin + s.c).max(0.0);
        }
        rows[f] = sums[f][0].rows;
    }
    let total: usize = rows.iter().sum();
    let heldout_rms: Vec<f64> = (0..n)
        .map(|j| (sse.iter().map(|s| s[j]).sum::<f64>() / total.max(1) as f64).sqrt())
        .collect();
    let fold_rms = (0..k)
        .map(|f| {
            (0..n)
                .map(|j| (sse[f][j] / rows[f].max(1) as f64).sqrt())
                .sum::<f64>()
                / n as f64
        })
        .collect();
    let b = bases();
    Ok(LawScore {
        terms: law.iter().map(|&t| b[t].0.name().to_string()).collect(),
        stribeck_velocity: law
            .iter()
            .find(|&&t| b[t].0 == FrictionTerm::Stribeck)
            .map(|&t| b[t].1),
        mean_rms: heldout_rms.iter().sum::<f64>() / n as f64,
        heldout_rms,
        fold_rms,
    })
}

/// The best law, and the one the parsimony rule chooses (module doc).
fn conclude(kind: Folds, k: usize, laws: Vec<LawScore>) -> FrictionChoice {
    let best = (0..laws.len())
        .min_by(|&a, &b| laws[a].mean_rms.total_cmp(&laws[b].mean_rms))
        .unwrap_or(0);
    let within = |i: usize| {
        let d: Vec<f64> = (laws[i].fold_rms.iter().zip(&laws[best].fold_rms))
            .map(|(a, b)| a - b)
            .collect();
        let mean = d.iter().sum::<f64>() / k as f64;
        let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (k.max(2) - 1) as f64;
        mean <= (var / k as f64).sqrt().max(MIN_GAIN * laws[best].mean_rms)
    };
    let chosen = (0..laws.len())
        .filter(|&i| i == best || within(i))
        .min_by(|&a, &b| {
            (laws[a].terms.len().cmp(&laws[b].terms.len()))
                .then(laws[a].mean_rms.total_cmp(&laws[b].mean_rms))
        })
        .unwrap_or(best);
    let rule = match chosen == best {
        true => format!(
            "the lowest cross-validated error ({:.4} N·m)",
            laws[best].mean_rms
        ),
        false => format!(
            "the fewest terms within the noise of the lowest (one standard error over the {k} folds, paired, or {:.0} % of it; lowest {:.4} N·m with {}): {:.4} N·m",
            100.0 * MIN_GAIN,
            laws[best].mean_rms,
            laws[best].terms.join("+"),
            laws[chosen].mean_rms
        ),
    };
    FrictionChoice {
        folds: kind,
        k,
        laws,
        best,
        chosen,
        rule,
    }
}
