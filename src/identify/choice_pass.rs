//! The friction law's choice's one pass over the training data, and the
//! chosen law's reduction made from it without a second pass.
//!
//! Each sample's regressor row is built once, per joint over its links'
//! columns ([`regressor_row_columns`]), then every candidate friction basis
//! ([`bases`](super::friction_choice)), then τ; each fold's and joint's Gram
//! sums ([`Sums`]) are the products of those rows. The samples are taken in
//! pieces of one fold each, in parallel. When the rows fit in
//! [`LOAD_ROWS_BUDGET_BYTES`] they are kept, in the training data's order,
//! so that a chosen law with a load term gets its passes' rows
//! ([`LoadRows`]) without building them again.
//!
//! The chosen law's reduction ([`ChoicePass::reduced`]) is the folds' sums
//! added, its columns picked and put in the identification's places: the
//! Gram matrix a reduction of the same samples would give, except that a
//! load column's load is the model's own bodies' rigid torque (as the
//! choice scored it) where a reduction takes the measured torque — the
//! load passes then iterate it to the fit's, as from either.

use super::error::IdentifyError;
use super::gram::{GramAcc, add_products};
use super::load_rows::{LOAD_ROWS_BUDGET_BYTES, LoadRows};
use super::reduce::{Reduced, keep_joint_grams};
use crate::data::Dataset;
use crate::dynamics::{Data, FrictionTerm, Model, regressor_blocks};
use faer::Mat;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::ops::Range;

/// The most samples a piece of the pass holds.
const PIECE: usize = 1024;
/// Pieces computed at once (their products held until added).
const WAVE: usize = 64;

/// One fold's and joint's sums: `G = Σ yᵀy`, `b = Σ yᵀτ`, `c = Σ τ²` over
/// the joint's rows (its links' columns, then every basis), and the lower
/// triangle of `[y τ]ᵀ[y τ]` they come from.
pub(crate) struct Sums {
    pub(crate) g: DMatrix<f64>,
    pub(crate) b: DVector<f64>,
    pub(crate) c: f64,
    pub(crate) rows: usize,
    lower: Mat<f64>,
}

impl Sums {
    fn new(lower: Mat<f64>, rows: usize) -> Self {
        let w = lower.nrows() - 1;
        let at = |i: usize, j: usize| lower[(i.max(j), i.min(j))];
        Self {
            g: DMatrix::from_fn(w, w, at),
            b: DVector::from_fn(w, |i, _| at(w, i)),
            c: at(w, w),
            rows,
            lower,
        }
    }
}

/// A piece of the pass: its samples (one fold's), its fold, each joint's
/// rows (row-major, its columns and τ) and their products.
struct Piece {
    range: Range<usize>,
    fold: usize,
    rows: Vec<Vec<f64>>,
    lower: Vec<Mat<f64>>,
    /// The load basis' load: the rigid torque of the model's own bodies.
    rigid: crate::dynamics::Samples,
}

/// The choice's pass over a training set: per fold and joint its sums, and
/// the rows when kept (module doc).
pub(crate) struct ChoicePass {
    /// Per fold, per joint.
    pub(crate) sums: Vec<Vec<Sums>>,
    /// Per joint, its links' columns.
    cols: Vec<Vec<usize>>,
    /// The candidate bases, in their columns' order.
    bases: Vec<(FrictionTerm, f64)>,
    /// The rows, piece by piece in the training order, when kept.
    pieces: Option<Vec<Piece>>,
    /// The training velocities (a load column's sign).
    qd: crate::dynamics::Samples,
    /// The samples of the pass.
    samples: usize,
    /// The fingerprint of the data and links it was made from.
    data: u64,
}

/// A fingerprint of `train`'s values and `links`' parameters (every bit
/// of each), to tell a pass from one of other data.
fn fingerprint(links: &Model, train: &Dataset) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    let series = [&train.q, &train.qd, &train.qdd, &train.tau];
    let params = links.params();
    let values = (train.t.iter())
        .chain(series.into_iter().flat_map(|s| s.as_flat().iter()))
        .chain(params.iter());
    values.for_each(|v| v.to_bits().hash(&mut h));
    train.segments.hash(&mut h);
    h.finish()
}

impl std::fmt::Debug for ChoicePass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ChoicePass {{ {} samples }}", self.qd.len())
    }
}

/// `folds[f]`'s ranges (one per segment) cut into pieces of at most
/// [`PIECE`] samples, in the training order.
fn pieces_of(folds: &[Vec<Range<usize>>]) -> Vec<(Range<usize>, usize)> {
    let mut out: Vec<(Range<usize>, usize)> = (folds.iter().enumerate())
        .flat_map(|(f, parts)| parts.iter().map(move |r| (r.clone(), f)))
        .flat_map(|(r, f)| (r.clone().step_by(PIECE)).map(move |s| (s..(s + PIECE).min(r.end), f)))
        .collect();
    out.sort_by_key(|(r, _)| r.start);
    out
}

impl ChoicePass {
    /// The pass over `train` for `links` (no friction terms; each joint's
    /// columns `cols`), its samples split as `folds` (each sample in one),
    /// the load basis the rigid torque of `links`' own bodies.
    pub(crate) fn new(
        links: &Model,
        train: &Dataset,
        folds: &[Vec<Range<usize>>],
        (cols, bases): (&[Vec<usize>], Vec<(FrictionTerm, f64)>),
    ) -> Result<Self, IdentifyError> {
        let widths: Vec<usize> = cols.iter().map(|c| c.len() + bases.len() + 1).collect();
        let bytes =
            (widths.iter().sum::<usize>() * std::mem::size_of::<f64>()).saturating_mul(train.len());
        let keep = bytes <= LOAD_ROWS_BUDGET_BYTES;
        let mut sums: Vec<Vec<(Mat<f64>, usize)>> = (0..folds.len())
            .map(|_| widths.iter().map(|&w| (Mat::zeros(w, w), 0)).collect())
            .collect();
        // a wave of pieces at a time, their products added as they come (a
        // piece's products are dropped once added; its rows kept or not)
        let mut kept = vec![];
        for wave in pieces_of(folds).chunks(WAVE) {
            let done = (wave.par_iter())
                .map(|(range, fold)| {
                    piece(links, train, (range.clone(), *fold), (cols, &bases), keep)
                })
                .collect::<Result<Vec<_>, _>>()?;
            for mut p in done {
                for (s, l) in sums[p.fold].iter_mut().zip(std::mem::take(&mut p.lower)) {
                    s.0 += l;
                    s.1 += p.range.len();
                }
                if keep {
                    kept.push(p);
                }
            }
        }
        let sums = (sums.into_iter())
            .map(|f| f.into_iter().map(|(l, r)| Sums::new(l, r)).collect())
            .collect();
        Ok(Self {
            sums,
            cols: cols.to_vec(),
            bases,
            pieces: keep.then_some(kept),
            qd: train.qd.clone(),
            samples: train.len(),
            data: fingerprint(links, train),
        })
    }

    /// Whether `train` and `links` are the ones the pass was made from (by
    /// their values' fingerprint).
    pub(crate) fn made_from(&self, links: &Model, train: &Dataset) -> bool {
        self.samples == train.len() && self.data == fingerprint(links, train)
    }

    /// The samples of the pass.
    pub(crate) fn samples(&self) -> usize {
        self.samples
    }
}

/// The piece `range` of `train` (in `fold`): its rows and their products.
fn piece(
    links: &Model,
    train: &Dataset,
    (range, fold): (Range<usize>, usize),
    (cols, bases): (&[Vec<usize>], &[(FrictionTerm, f64)]),
    keep: bool,
) -> Result<Piece, IdentifyError> {
    let (n, p) = (links.dof(), links.regressor_columns());
    let d = train.slice(range.clone());
    // the bodies' own parameters: a row's products with them is the rigid
    // torque (the regressor's columns are the bodies', 10 each)
    let own = links.params();
    let mut at = vec![vec![usize::MAX; p]; n];
    (cols.iter().enumerate())
        .for_each(|(j, cs)| cs.iter().enumerate().for_each(|(a, &c)| at[j][c] = a));
    let widths: Vec<usize> = cols.iter().map(|c| c.len() + bases.len() + 1).collect();
    // zeros written, not a zeroed allocation: a zeroed page read by `+=`
    // before it is written is copied on the write (a second fault, and a
    // flush of every core's TLB)
    let mut rows: Vec<Vec<f64>> = (widths.iter())
        .map(|w| {
            let mut r = Vec::with_capacity(w * d.len());
            r.resize(w * d.len(), 0.0);
            r
        })
        .collect();
    let mut data = Data::new(links);
    let mut rigid = crate::dynamics::Samples::zeros(0, n);
    for k in 0..d.len() {
        regressor_blocks(
            links,
            &mut data,
            [&d.q[k], &d.qd[k], &d.qdd[k]],
            |j, c0, v| {
                let row = &mut rows[j][k * widths[j]..];
                (v.iter().enumerate()).for_each(|(a, x)| row[at[j][c0 + a]] += x)
            },
        )
        .map_err(|source| IdentifyError::Regressor {
            sample: range.start + k,
            source,
        })?;
        let mut load = vec![0.0; n];
        for j in 0..n {
            let row = &mut rows[j][k * widths[j]..(k + 1) * widths[j]];
            let l = cols[j].len();
            load[j] = (cols[j].iter().zip(&row[..l]))
                .map(|(&c, y)| own[c] * y)
                .sum();
            for (t, (term, vs)) in bases.iter().enumerate() {
                row[l + t] = term.basis(d.qd[k][j], load[j], *vs);
            }
            row[widths[j] - 1] = d.tau[k][j];
        }
        rigid.push(&load);
    }
    let lower = (rows.iter().zip(&widths))
        .map(|(r, &w)| {
            let mut g = Mat::zeros(w, w);
            add_products(&mut g, r, d.len());
            g
        })
        .collect();
    if !keep {
        (rows, rigid) = (vec![], crate::dynamics::Samples::zeros(0, n));
    }
    Ok(Piece {
        range,
        fold,
        rows,
        lower,
        rigid,
    })
}

impl ChoicePass {
    /// The reduction of the pass's samples for `model`, whose friction
    /// terms and Stribeck velocity are those of `law` (indices of the
    /// pass's bases) — `None` when they are not (or when the law has a
    /// load term and the rows were not kept: a reduction then builds its
    /// own). The load passes' rows come with it for a load term.
    pub(crate) fn reduced(
        &self,
        model: &Model,
        law: &[usize],
    ) -> Result<Option<Reduced>, IdentifyError> {
        let t0 = std::time::Instant::now();
        let Some(places) = self.places(model, law) else {
            return Ok(None);
        };
        let (n, p1) = (model.dof(), model.regressor_columns() + 1);
        let has_load = law.iter().any(|&t| self.bases[t].0 == FrictionTerm::Load);
        if has_load && self.pieces.is_none() {
            return Ok(None);
        }
        // per joint: (its compact index, global column), in global order
        let picks: Vec<Vec<(usize, usize)>> = (0..n)
            .map(|j| {
                let w = self.cols[j].len() + self.bases.len();
                let mut m: Vec<(usize, usize)> = self.cols[j].iter().copied().enumerate().collect();
                m.extend(
                    law.iter()
                        .map(|&t| (self.cols[j].len() + t, places[&t] + j)),
                );
                m.push((w, p1 - 1));
                m.sort_by_key(|&(_, g)| g);
                m
            })
            .collect();
        let grams: Vec<Mat<f64>> = (0..n)
            .map(|j| {
                let total = (self.sums.iter()).fold(None::<Mat<f64>>, |acc, f| match acc {
                    None => Some(f[j].lower.clone()),
                    Some(a) => Some(a + &f[j].lower),
                });
                let total = total.expect("a fold at least");
                let at = |a: usize, b: usize| total[(a.max(b), a.min(b))];
                let pk = &picks[j];
                Mat::from_fn(pk.len(), pk.len(), |r, c| at(pk[r].0, pk[c].0))
            })
            .collect();
        let cols: Vec<Vec<usize>> = picks
            .iter()
            .map(|m| m.iter().map(|x| x.1).collect())
            .collect();
        let load_rows = match has_load {
            true => match self.load_rows(model, &picks, &cols) {
                Some(rows) => Some(std::sync::Arc::new(rows)),
                None => return Ok(None),
            },
            false => None,
        };
        let scattered = super::gram::scattered(p1, &cols, &grams, keep_joint_grams(n, p1));
        Reduced::assembled(scattered, (self.samples(), n), t0, load_rows).map(Some)
    }

    /// Per basis of `law`, the global column of its joint 0 (joint j's is
    /// that + j) in `model`'s regressor; `None` when `model`'s friction
    /// law is not `law`.
    fn places(
        &self,
        model: &Model,
        law: &[usize],
    ) -> Option<std::collections::HashMap<usize, usize>> {
        let (n, terms) = (model.dof(), model.friction_terms());
        let pb = 10 * model.num_bodies();
        let same = terms.len() == law.len()
            && model.regressor_columns() == pb + n * law.len()
            && (law.iter()).all(|&t| {
                let (term, vs) = self.bases[t];
                terms.contains(&term)
                    && (term != FrictionTerm::Stribeck || vs == model.stribeck_velocity())
            });
        if !same || n != self.cols.len() {
            return None;
        }
        let place = |t: usize| terms.iter().position(|x| *x == self.bases[t].0);
        law.iter().map(|&t| Some((t, pb + n * place(t)?))).collect()
    }

    /// The kept rows with `picks`' columns (`cols`, global), for the load
    /// term's passes.
    fn load_rows(
        &self,
        model: &Model,
        picks: &[Vec<(usize, usize)>],
        cols: &[Vec<usize>],
    ) -> Option<LoadRows> {
        let pieces = self.pieces.as_ref()?;
        let widths: Vec<usize> = (self.cols.iter())
            .map(|c| c.len() + self.bases.len() + 1)
            .collect();
        let blocks: Vec<Vec<f64>> = (0..cols.len())
            .into_par_iter()
            .map(|j| {
                let mut b = Vec::with_capacity(self.samples() * picks[j].len());
                for p in pieces {
                    for row in p.rows[j].chunks_exact(widths[j]) {
                        b.extend(picks[j].iter().map(|&(a, _)| row[a]));
                    }
                }
                b
            })
            .collect();
        let p1 = model.regressor_columns() + 1;
        let rows = GramAcc::from_rows(p1, cols.to_vec(), blocks, self.samples());
        let mut load = crate::dynamics::Samples::zeros(0, cols.len());
        for p in pieces {
            (0..p.rigid.len()).for_each(|k| load.push(&p.rigid[k]));
        }
        LoadRows::from_rows(model, rows, self.qd.clone(), load)
    }
}

#[cfg(test)]
mod tests {
    use super::ChoicePass;
    use crate::data::Dataset;
    use crate::dynamics::predict::predict_torques;
    use crate::dynamics::{Friction, FrictionTerm, Samples, random_states, regressor_row_columns};
    use crate::identify::choose_weight::held_out;
    use crate::identify::reduce::{Reduced, reduce_samples, reduce_with_load};

    /// 3000 random states of the leg (two segments: two folds), a torque
    /// wave as the measured torque.
    fn leg_data() -> Dataset {
        let model = crate::dynamics::cheetah3::model();
        let (n, m) = (model.dof(), 3000);
        let [q, qd, qdd] = random_states(&model, m, 3).map(|v| Samples::from_flat(n, v).unwrap());
        let wave = (0..m * n).map(|i| 4.0 * (0.37 * i as f64).sin()).collect();
        Dataset {
            joints: model.joint_names().iter().map(|j| j.to_string()).collect(),
            t: (0..m).map(|s| s as f64 * 1e-3).collect(),
            q,
            qd,
            qdd,
            tau: Samples::from_flat(n, wave).unwrap(),
            segments: vec![0, 1300],
            base: None,
            contacts: vec![],
        }
    }

    fn same(x: &Reduced, y: &Reduced) {
        crate::identify::reduce::assert_same(x, y, 1e-10);
    }

    /// The chosen law's reduction made from the pass equals a reduction of
    /// the same samples: without a load term exactly, with one (its load
    /// the model's own rigid torque) that of the load reduction, and its
    /// kept rows carry that load and give the dynamics' rigid torques.
    #[test]
    fn the_chosen_law_reduced_from_the_pass_equals_a_reduction() {
        use FrictionTerm::*;
        let links = crate::dynamics::cheetah3::model().with_friction_terms(&[]);
        let train = leg_data();
        let (_, folds) = held_out(&train, 5);
        assert_eq!(folds.len(), 2, "a fold per segment");
        let cols = regressor_row_columns(&links);
        let bases = super::super::friction_choice::bases();
        let pass = ChoicePass::new(&links, &train, &folds, (&cols, bases.clone())).unwrap();
        assert_eq!(pass.samples(), train.len());
        // the pass knows its data: one torque changed, or other bodies, is
        // other data
        assert!(pass.made_from(&links, &train));
        let mut other = train.clone();
        other.tau[1700][1] += 1e-9;
        assert!(!pass.made_from(&links, &other));
        let mut heavier = links.clone();
        let mut params = heavier.params();
        params[0] *= 1.01;
        heavier.set_params(&params).unwrap();
        assert!(!pass.made_from(&heavier, &train));
        assert_eq!(pass.sums[0][0].rows + pass.sums[1][0].rows, train.len());
        let at = |t: FrictionTerm, v: f64| bases.iter().position(|b| *b == (t, v)).unwrap();
        // viscous + Coulomb + Stribeck at 0.05: no load term
        let law = [at(Viscous, 0.0), at(Coulomb, 0.0), at(Stribeck, 0.05)];
        let model = (links
            .clone()
            .with_friction_terms(&[Viscous, Coulomb, Stribeck]))
        .with_stribeck_velocity(0.05)
        .unwrap();
        let got = pass
            .reduced(&model, &law)
            .unwrap()
            .expect("the model has the law");
        let (q, qd, qdd, tau) = (&train.q, &train.qd, &train.qdd, &train.tau);
        same(&got, &reduce_samples(&model, q, qd, qdd, tau, 64).unwrap());
        assert!(got.load_rows.is_none());
        // a model whose Stribeck velocity is not the law's: no reduction
        let other = model.clone().with_stribeck_velocity(0.1).unwrap();
        assert!(pass.reduced(&other, &law).unwrap().is_none());
        // viscous + Coulomb + offset + load
        let law = [
            at(Viscous, 0.0),
            at(Coulomb, 0.0),
            at(Offset, 0.0),
            at(Load, 0.0),
        ];
        let model = links
            .clone()
            .with_friction_terms(&[Viscous, Coulomb, Offset, Load]);
        let got = pass.reduced(&model, &law).unwrap().expect("rows kept");
        let n = model.dof();
        let rigid = predict_torques(&links, &Friction::zeros(n), q, qd, qdd).unwrap();
        same(
            &got,
            &reduce_with_load(&model, [q, qd, qdd, tau], &rigid, 64).unwrap(),
        );
        let rows = got.load_rows.as_ref().expect("the load passes' rows");
        let big = rigid.as_flat().iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (a, b) in rows.load().as_flat().iter().zip(rigid.as_flat()) {
            assert!((a - b).abs() <= 1e-10 * big, "{a} vs {b}");
        }
        let theta = model.params();
        let again = rows.rigid_torques(&theta, theta.len());
        for (a, b) in again.as_flat().iter().zip(rigid.as_flat()) {
            assert!((a - b).abs() <= 1e-10 * big, "{a} vs {b}");
        }
    }
}
