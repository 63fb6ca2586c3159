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

use super::choose_weight::{Folds, MIN_FOLD_SAMPLES, MIN_GAIN, TIME_FOLDS, held_out, within_noise};
use super::error::IdentifyError;
use super::warning::IdentifyWarning;
use crate::data::Dataset;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{
    Data, Friction, FrictionTerm, Model, regressor_blocks, regressor_row_columns,
};
use crate::moments::InertialParams;
use nalgebra::{DMatrix, DVector, Matrix4, SMatrix};
use rayon::prelude::*;
use serde::Serialize;

/// The Stribeck velocities (rad/s) tried: a drive's breakaway region is a
/// few hundredths to a few tenths of a rad/s wide.
pub const STRIBECK_VELOCITIES: [f64; 4] = [0.02, 0.05, 0.1, 0.2];
/// The prior weights tried with each law when the weight is chosen too
/// (`--weight auto`): half-decades from 1e-6 to 1 (N²·m², the
/// regulariser's units).
pub const WEIGHTS: [f64; 13] = [
    1e-6, 3.16e-6, 1e-5, 3.16e-5, 1e-4, 3.16e-4, 1e-3, 3.16e-3, 1e-2, 3.16e-2, 1e-1, 3.16e-1, 1.0,
];
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
    /// The prior's weight it was fitted with (N²·m², the regulariser's).
    pub weight: f64,
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

    /// `model` with the chosen law's terms and Stribeck velocity.
    pub fn apply(&self, model: Model) -> Result<Model, crate::dynamics::DynamicsError> {
        let model = model.with_friction_terms(&self.terms());
        match self.stribeck_velocity() {
            Some(v) => model.with_stribeck_velocity(v),
            None => Ok(model),
        }
    }

    /// The prior's weight chosen with the law.
    pub fn weight(&self) -> f64 {
        self.laws[self.chosen].weight
    }

    /// Whether more than one weight was tried.
    pub fn weight_chosen(&self) -> bool {
        self.laws.iter().any(|l| l.weight != self.laws[0].weight)
    }
}

impl super::Identification<'_> {
    /// [`choose_friction`] for this identification's model, prior,
    /// regulariser and weight (the prior's when one is set, else none).
    pub fn choose_friction(&self, train: &Dataset) -> Result<FrictionChoice, IdentifyError> {
        self.choose_model(train, &[self.weight])
    }

    /// The weights [`Self::choose_model`] should try: [`WEIGHTS`] when the
    /// weight is to be chosen (`weight_auto`) and the prior is Euclidean
    /// (the Gram solves are its objective exactly), else none (this
    /// identification's own; an entropic prior's weight is chosen by the
    /// fits, [`Self::choose_weight`]).
    pub fn model_weights(&self, weight_auto: bool) -> &'static [f64] {
        match weight_auto && self.regularizer == super::Regularizer::Euclidean {
            true => &WEIGHTS,
            false => &[],
        }
    }

    /// [`choose_friction`] with the prior's weight chosen with the law from
    /// `weights` (each > 0): the fewest terms first, then the strongest
    /// prior, within the noise of the best (module doc). Without a prior
    /// the weight is moot and only this identification's is tried.
    pub fn choose_model(
        &self,
        train: &Dataset,
        weights: &[f64],
    ) -> Result<FrictionChoice, IdentifyError> {
        self.fixed_base("Identification::choose_model")?;
        if let Some(&w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
            return Err(IdentifyError::WeightGrid {
                what: format!("{w:e} is not positive and finite"),
            });
        }
        let own = [self.weight];
        let weights = match self.prior.is_empty() || weights.is_empty() {
            true => &own[..],
            false => weights,
        };
        let metric = match self.regularizer {
            super::Regularizer::Entropic if !self.prior.is_empty() => {
                entropic_metric(&self.prior, &self.layout.bodies)?
            }
            _ => vec![SMatrix::<f64, 10, 10>::identity(); self.prior.len() / 10],
        };
        let prior = PriorTerm {
            values: &self.prior,
            metric,
            mass_weight: self.mass_weight(),
        };
        choose_friction(self.model, train, &prior, weights)
    }

    /// [`choose_model`](Self::choose_model) as a default that may stand
    /// down: training data too short for the folds
    /// ([`IdentifyError::FoldTooSmall`]) keep the model's own law at this
    /// identification's weight, with the warning that says so, where an
    /// explicit choice would be an error.
    pub fn choose_model_or_keep(
        &self,
        train: &Dataset,
        weights: &[f64],
    ) -> Result<LawChoice, IdentifyError> {
        match self.choose_model(train, weights) {
            Ok(c) => Ok(LawChoice::Chosen(c)),
            Err(e @ IdentifyError::FoldTooSmall { .. }) => {
                let terms = self.model.friction_terms().iter();
                Ok(LawChoice::Kept(IdentifyWarning::LawNotChosen {
                    reason: e.to_string(),
                    terms: terms.map(|t| t.name().to_string()).collect(),
                    weight: self.weight,
                }))
            }
            Err(e) => Err(e),
        }
    }
}

/// The law [`choose_model_or_keep`](super::Identification::choose_model_or_keep) chose, or why the
/// model's own was kept.
#[derive(Clone, Debug, PartialEq)]
pub enum LawChoice {
    /// Chosen from the data.
    Chosen(FrictionChoice),
    /// The model's own law kept at the identification's weight
    /// ([`IdentifyWarning::LawNotChosen`]).
    Kept(IdentifyWarning),
}

/// The prior's term of the objective as the Gram solves see it:
/// `w Σ_b (π_b − π̂_b)ᵀ M_b (π_b − π̂_b) + w_m Σ_b (m_b − m̂_b)²`, `M_b = I`
/// (Euclidean) or the entropic divergence's second-order term at the
/// prior (entropic; [`entropic_metric`]).
pub struct PriorTerm<'a> {
    /// 10 per body, or empty (no prior).
    pub values: &'a [f64],
    /// `M_b` per body.
    pub metric: Vec<SMatrix<f64, 10, 10>>,
    /// The masses' extra weight.
    pub mass_weight: f64,
}

/// Per body, `M = ½ H` with `H_kl = tr(Ĵ⁻¹ J(e_k) Ĵ⁻¹ J(e_l))`: the
/// log-det divergence `d(J ‖ Ĵ) = ½ tr(Ĵ⁻¹ΔJ Ĵ⁻¹ΔJ) + O(ΔJ³)` near the
/// prior. Each prior body must be strictly consistent.
fn entropic_metric(
    prior: &[f64],
    bodies: &[String],
) -> Result<Vec<SMatrix<f64, 10, 10>>, IdentifyError> {
    let basis: Vec<Matrix4<f64>> = (0..10)
        .map(|k| {
            let mut e = [0.0; 10];
            e[k] = 1.0;
            InertialParams(e).pseudo_inertia()
        })
        .collect();
    (prior.chunks(10).enumerate())
        .map(|(b, p)| {
            let j = InertialParams(p.try_into().expect("chunks of 10")).pseudo_inertia();
            let ji = (j.cholesky())
                .ok_or_else(|| IdentifyError::PriorNotConsistent {
                    body: bodies.get(b).cloned().unwrap_or_default(),
                    min_eig: j.symmetric_eigenvalues().min(),
                })?
                .inverse();
            let a: Vec<Matrix4<f64>> = basis.iter().map(|e| ji * e).collect();
            Ok(SMatrix::from_fn(|k, l| 0.5 * (a[k] * a[l]).trace()))
        })
        .collect()
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
/// the joint's compact rows (its links' columns, then every basis);
/// `g`, `b` and `c` are set by [`Sums::finish`].
struct Sums {
    g: DMatrix<f64>,
    b: DVector<f64>,
    c: f64,
    rows: usize,
    /// The lower triangle of `[y τ]ᵀ[y τ]` so far.
    acc: faer::Mat<f64>,
    /// Rows `[y τ]` not yet added, row-major.
    buf: Vec<f64>,
}

impl Sums {
    fn new(w: usize) -> Self {
        Self {
            g: DMatrix::zeros(w, w),
            b: DVector::zeros(w),
            c: 0.0,
            rows: 0,
            acc: faer::Mat::zeros(w + 1, w + 1),
            buf: vec![],
        }
    }

    fn push(&mut self, row: &[f64], tau: f64) {
        self.buf.extend_from_slice(row);
        self.buf.push(tau);
        if self.buf.len() == CHUNK * self.acc.ncols() {
            self.flush();
        }
    }

    /// Adds the rows gathered (faer's triangular product, as the
    /// reduction's Gram matrices are).
    fn flush(&mut self) {
        let m = self.buf.len() / self.acc.ncols();
        if m > 0 {
            super::gram::add_products(&mut self.acc, &self.buf, m);
            self.rows += m;
        }
        self.buf.clear();
    }

    /// The last rows added, and `g`, `b`, `c` set from the sums.
    fn finish(&mut self) {
        self.flush();
        let w = self.g.nrows();
        let at = |i: usize, j: usize| self.acc[(i.max(j), i.min(j))];
        self.g = DMatrix::from_fn(w, w, at);
        self.b = DVector::from_fn(w, |i, _| at(w, i));
        self.c = at(w, w);
    }
}

/// Chooses the friction law for `model`'s links and rotors (its own
/// friction terms ignored) on `train` (module doc), with the
/// identification's `prior` and each of `weights` (one law per weight).
pub fn choose_friction(
    model: &Model,
    train: &Dataset,
    prior: &PriorTerm,
    weights: &[f64],
) -> Result<FrictionChoice, IdentifyError> {
    let links = model.clone().with_friction_terms(&[]);
    let (kind, ranges) = held_out(train, TIME_FOLDS);
    let joints: Vec<&str> = train.joints.iter().map(String::as_str).collect();
    let held: Vec<Dataset> = (ranges.iter())
        .map(|parts| {
            let mut h = Dataset::empty(&joints);
            for r in parts.iter().filter(|r| !r.is_empty()) {
                h.append_segment(train.slice(r.clone()));
            }
            h
        })
        .collect();
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
    // the folds' sums, then the laws, in parallel
    let sums = (held.par_iter())
        .map(|h| fold_sums(&links, h, &cols))
        .collect::<Result<Vec<_>, _>>()?;
    let pb = 10 * links.num_bodies();
    let scored = (laws().par_iter())
        .map(|l| score(l, &sums, &cols, (pb, prior, weights)))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(conclude(
        kind,
        held.len(),
        scored.into_iter().flatten().collect(),
    ))
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
    sums.iter_mut().for_each(Sums::finish);
    Ok(sums)
}

/// Joint j's compact index → global unknown, for `law`'s columns (the
/// links' `pb` parameters first, then the law's, term-major).
fn unknowns(law: &[usize], cols: &[Vec<usize>], pb: usize) -> Vec<Vec<(usize, usize)>> {
    let n = cols.len();
    (0..n)
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
        .collect()
}

/// The normal equations `(G, b)` of the folds but `f` (each scaled by the
/// samples, as the objective is), for the unknowns of `map`.
fn normal_equations(
    sums: &[Vec<Sums>],
    f: usize,
    map: &[Vec<(usize, usize)>],
    p: usize,
) -> (DMatrix<f64>, DVector<f64>) {
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
                (map[j].iter()).for_each(|&(e, ge)| g[(ga, ge)] += s.g[(a, e)]);
            }
        }
    }
    let scale = 1.0 / ns.max(1) as f64;
    (g * scale, b * scale)
}

/// `(G, b)` with the prior's term at `weight` added (the first `pb`
/// unknowns are the links'), and a ridge of 1e-10 of G's mean diagonal.
fn with_prior(
    (mut g, mut b): (DMatrix<f64>, DVector<f64>),
    prior: &PriorTerm,
    weight: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let p = g.nrows();
    let ridge = 1e-10 * (g.trace() / p as f64).max(f64::MIN_POSITIVE);
    (0..p).for_each(|i| g[(i, i)] += ridge);
    for (body, m) in prior.metric.iter().enumerate() {
        let o = 10 * body;
        let mut wm = m * weight;
        wm[(0, 0)] += prior.mass_weight;
        let pi = nalgebra::SVector::<f64, 10>::from_column_slice(&prior.values[o..o + 10]);
        let rhs = wm * pi;
        for k in 0..10 {
            b[o + k] += rhs[k];
            (0..10).for_each(|l| g[(o + k, o + l)] += wm[(k, l)]);
        }
    }
    (g, b)
}

/// `g⁻¹ b` by faer's Cholesky factorisation (`g` symmetric positive
/// definite; None when it is not).
fn solve_spd(g: &DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let p = g.nrows();
    let a = faer::Mat::<f64>::from_fn(p, p, |i, j| g[(i, j)]);
    let rhs = faer::Mat::<f64>::from_fn(p, 1, |i, _| b[i]);
    use faer::linalg::solvers::Solve;
    let x = a.llt(faer::Side::Lower).ok()?.solve(&rhs);
    Some(DVector::from_fn(p, |i, _| x[(i, 0)]))
}

/// Held-out sum of squares per joint of `theta` on one fold's sums.
fn heldout_sse(theta: &DVector<f64>, fold: &[Sums], map: &[Vec<(usize, usize)>]) -> Vec<f64> {
    (fold.iter().enumerate())
        .map(|(j, s)| {
            let th: Vec<(usize, f64)> = map[j].iter().map(|&(a, ga)| (a, theta[ga])).collect();
            let quad: f64 = (th.iter())
                .map(|&(a, x)| x * th.iter().map(|&(e, y)| s.g[(a, e)] * y).sum::<f64>())
                .sum();
            let lin: f64 = th.iter().map(|&(a, x)| x * s.b[a]).sum();
            (quad - 2.0 * lin + s.c).max(0.0)
        })
        .collect()
}

/// The cross-validated scores of `law` (indices of [`bases`]), one per
/// weight.
fn score(
    law: &[usize],
    sums: &[Vec<Sums>],
    cols: &[Vec<usize>],
    (pb, prior, weights): (usize, &PriorTerm, &[f64]),
) -> Result<Vec<LawScore>, IdentifyError> {
    let (n, k) = (cols.len(), sums.len());
    let p = pb + law.len() * n;
    let map = unknowns(law, cols, pb);
    let rows: Vec<usize> = sums.iter().map(|s| s[0].rows).collect();
    let mut sse = vec![vec![vec![0.0; n]; k]; weights.len()];
    for f in 0..k {
        let normal = normal_equations(sums, f, &map, p);
        for (w, &weight) in weights.iter().enumerate() {
            let (g, b) = with_prior(normal.clone(), prior, weight);
            let theta = solve_spd(&g, &b).ok_or(IdentifyError::Factorisation {
                what: "Cholesky factorisation of a friction law's Gram matrix",
            })?;
            sse[w][f] = heldout_sse(&theta, &sums[f], &map);
        }
    }
    let b = bases();
    let total: usize = rows.iter().sum();
    Ok((weights.iter().zip(&sse))
        .map(|(&weight, sse)| {
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
            LawScore {
                terms: law.iter().map(|&t| b[t].0.name().to_string()).collect(),
                stribeck_velocity: (law.iter())
                    .find(|&&t| b[t].0 == FrictionTerm::Stribeck)
                    .map(|&t| b[t].1),
                weight,
                mean_rms: heldout_rms.iter().sum::<f64>() / n as f64,
                heldout_rms,
                fold_rms,
            }
        })
        .collect())
}

/// The best law, and the one the parsimony rule chooses (module doc).
fn conclude(kind: Folds, k: usize, laws: Vec<LawScore>) -> FrictionChoice {
    let best = (0..laws.len())
        .min_by(|&a, &b| laws[a].mean_rms.total_cmp(&laws[b].mean_rms))
        .unwrap_or(0);
    let within =
        |i: usize| within_noise(&laws[i].fold_rms, &laws[best].fold_rms, laws[best].mean_rms);
    let chosen = (0..laws.len())
        .filter(|&i| i == best || within(i))
        .min_by(|&a, &b| {
            (laws[a].terms.len().cmp(&laws[b].terms.len()))
                .then(laws[b].weight.total_cmp(&laws[a].weight))
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
