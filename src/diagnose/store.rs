//! The columns every fit of the diagnosis draws on — the nominal friction
//! law's and every candidate variant's — with their Gram matrices, their
//! products with the nominal residual and the residual's sum of squares,
//! per fold ([`super::folds::Folds`]). A fit on any union of folds then
//! adds a few small matrices: the data are gone through once per pair of
//! columns, however many rounds, folds and candidates use them.
//!
//! Columns are sample-major (`x[k·n + i]`: sample k, joint i). A column
//! whose values lie in one joint's rows (a friction term, a gain, an
//! offset per joint) is multiplied over that joint's rows only, and two
//! such columns of different joints are never multiplied.

use super::folds::Folds;
use faer::Mat;
use rayon::prelude::*;
use std::collections::HashMap;
use std::ops::Range;
use std::sync::RwLock;

/// One column: its values and the joint they lie in, if one.
pub struct Col {
    /// Sample-major values.
    pub values: Vec<f64>,
    /// The joint of every nonzero value, when there is one.
    pub joint: Option<usize>,
}

/// The columns, the residual and their products per fold.
pub struct Store {
    n: usize,
    folds: Vec<Range<usize>>,
    cols: Vec<Col>,
    r: Vec<f64>,
    /// `[fold][joint]`: Σ r² over the fold's rows of the joint.
    rr: Vec<Vec<f64>>,
    /// `[column][fold]`: Σ x r.
    xr: Vec<Vec<f64>>,
    /// `(a, b)`, a ≤ b → per fold Σ x_a x_b.
    gram: RwLock<HashMap<(usize, usize), Box<[f64]>>>,
    /// Rows every fit of its columns includes and no fold holds out.
    prior: Option<Prior>,
}

/// The normal equations of rows outside the folds — the data the nominal
/// model was identified on — over some of the store's columns: every fit
/// that includes one of those columns includes these rows, no score
/// measures them.
#[derive(Clone, Debug)]
pub struct Prior {
    /// The store's columns they are over.
    pub ids: Vec<usize>,
    /// `YᵀY` over those rows (one row and column per id).
    pub g: Mat<f64>,
    /// `Yᵀr`: r the nominal's residual there.
    pub xr: Vec<f64>,
    /// `rᵀr`.
    pub rr: f64,
}

impl Prior {
    /// The same rows with the coefficients `applied` already taken off
    /// their residual (`r − Y·applied`).
    pub fn at(&self, ids: Vec<usize>, applied: &[f64]) -> Self {
        let m = self.xr.len();
        let ga: Vec<f64> = (0..m)
            .map(|a| (0..m).map(|b| self.g[(a, b)] * applied[b]).sum())
            .collect();
        let ab: f64 = applied.iter().zip(&self.xr).map(|(x, y)| x * y).sum();
        let aga: f64 = applied.iter().zip(&ga).map(|(x, y)| x * y).sum();
        Self {
            ids,
            g: self.g.clone(),
            xr: self.xr.iter().zip(&ga).map(|(b, g)| b - g).collect(),
            rr: (self.rr - 2.0 * ab + aga).max(0.0),
        }
    }

    /// `normal` (of the columns `ids`) with these rows added where `ids`
    /// has their columns.
    pub fn add_to(
        &self,
        ids: &[usize],
        (mut g, mut xr, mut rr): (Mat<f64>, Vec<f64>, f64),
    ) -> (Mat<f64>, Vec<f64>, f64) {
        let at: Vec<Option<usize>> = (ids.iter())
            .map(|id| self.ids.iter().position(|x| x == id))
            .collect();
        if at.iter().all(Option::is_none) {
            return (g, xr, rr);
        }
        for (a, pa) in at.iter().enumerate() {
            let Some(pa) = *pa else { continue };
            xr[a] += self.xr[pa];
            for (b, pb) in at.iter().enumerate() {
                if let Some(pb) = *pb {
                    g[(a, b)] += self.g[(pa, pb)];
                }
            }
        }
        rr += self.rr;
        (g, xr, rr)
    }
}

use crate::effects::fitted::joint_of;

impl Store {
    /// A store for the residual `r` (sample-major, `n` joints) over `folds`.
    pub fn new(r: Vec<f64>, n: usize, folds: &Folds) -> Self {
        let folds = folds.ranges.clone();
        let rr = folds
            .iter()
            .map(|f| {
                (0..n)
                    .map(|i| f.clone().map(|k| r[k * n + i].powi(2)).sum())
                    .collect()
            })
            .collect();
        Self {
            n,
            folds,
            cols: vec![],
            r,
            rr,
            xr: vec![],
            gram: RwLock::new(HashMap::new()),
            prior: None,
        }
    }

    /// Rows outside the folds that every fit of their columns includes
    /// ([`Prior`]).
    pub fn set_prior(&mut self, prior: Prior) {
        self.prior = Some(prior);
    }

    /// The rows outside the folds, if any.
    pub fn prior(&self) -> Option<&Prior> {
        self.prior.as_ref()
    }

    /// `normal` of the columns `ids` with the rows outside the folds added
    /// (a fit's normal equations; unchanged without them).
    pub fn with_prior(
        &self,
        ids: &[usize],
        normal: (Mat<f64>, Vec<f64>, f64),
    ) -> (Mat<f64>, Vec<f64>, f64) {
        match &self.prior {
            Some(p) => p.add_to(ids, normal),
            None => normal,
        }
    }

    /// Joints n.
    pub fn joints(&self) -> usize {
        self.n
    }

    /// Number of folds.
    pub fn folds(&self) -> usize {
        self.folds.len()
    }

    /// The nominal residual.
    pub fn residual(&self) -> &[f64] {
        &self.r
    }

    /// Column `id`.
    pub fn col(&self, id: usize) -> &Col {
        &self.cols[id]
    }

    /// Adds a column (its products with the residual computed now); its id.
    pub fn add(&mut self, values: Vec<f64>) -> usize {
        let joint = joint_of(&values, self.n);
        self.add_in(values, joint)
    }

    /// Adds a column whose values lie in the rows of `joint` (`None`:
    /// several); its id.
    pub fn add_in(&mut self, values: Vec<f64>, joint: Option<usize>) -> usize {
        debug_assert!(joint.is_none_or(|j| {
            (values.iter().enumerate()).all(|(r, x)| *x == 0.0 || r % self.n == j)
        }));
        let col = Col { values, joint };
        let xr = (self.folds.iter())
            .map(|f| self.dot_r(&col, f.clone()))
            .collect();
        self.cols.push(col);
        self.xr.push(xr);
        self.cols.len() - 1
    }

    /// Adds every column of `cols`; their ids.
    #[cfg(test)]
    pub fn add_all(&mut self, cols: Vec<Vec<f64>>) -> Vec<usize> {
        cols.into_iter().map(|c| self.add(c)).collect()
    }

    fn rows(&self, a: &Col, b: Option<&Col>) -> RowSet {
        match (a.joint, b.and_then(|b| b.joint)) {
            (Some(i), Some(j)) if i != j => RowSet::None,
            (Some(i), _) | (_, Some(i)) => RowSet::Joint(i),
            _ => RowSet::All,
        }
    }

    fn dot_r(&self, a: &Col, f: Range<usize>) -> f64 {
        let n = self.n;
        match self.rows(a, None) {
            RowSet::None => 0.0,
            RowSet::Joint(i) => f.map(|k| a.values[k * n + i] * self.r[k * n + i]).sum(),
            RowSet::All => dot(
                &a.values[f.start * n..f.end * n],
                &self.r[f.start * n..f.end * n],
            ),
        }
    }

    fn dot(&self, a: &Col, b: &Col, f: Range<usize>) -> f64 {
        let n = self.n;
        match self.rows(a, Some(b)) {
            RowSet::None => 0.0,
            RowSet::Joint(i) => f.map(|k| a.values[k * n + i] * b.values[k * n + i]).sum(),
            RowSet::All => dot(
                &a.values[f.start * n..f.end * n],
                &b.values[f.start * n..f.end * n],
            ),
        }
    }

    /// Computes (in parallel) the per-fold products of every pair in
    /// `pairs` not yet kept.
    pub fn prepare(&self, pairs: impl IntoIterator<Item = (usize, usize)>) {
        let missing: Vec<(usize, usize)> = {
            let kept = self.gram.read().unwrap_or_else(|e| e.into_inner());
            let mut m: Vec<(usize, usize)> = pairs
                .into_iter()
                .map(|(a, b)| (a.min(b), a.max(b)))
                .filter(|p| !kept.contains_key(p))
                .collect();
            m.sort_unstable();
            m.dedup();
            m
        };
        let done: Vec<((usize, usize), Box<[f64]>)> = missing
            .into_par_iter()
            .map(|(a, b)| ((a, b), self.compute(a, b)))
            .collect();
        let mut kept = self.gram.write().unwrap_or_else(|e| e.into_inner());
        kept.extend(done);
    }

    fn compute(&self, a: usize, b: usize) -> Box<[f64]> {
        let (x, y) = (&self.cols[a], &self.cols[b]);
        (self.folds.iter())
            .map(|f| self.dot(x, y, f.clone()))
            .collect()
    }

    /// Σ x_a x_b over the folds `on` (kept, or computed now).
    fn pair(&self, a: usize, b: usize, on: &[bool]) -> f64 {
        let key = (a.min(b), a.max(b));
        let sum = |v: &[f64]| {
            (v.iter().zip(on))
                .filter(|(_, o)| **o)
                .map(|(x, _)| x)
                .sum()
        };
        if let Some(v) = self
            .gram
            .read()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
        {
            return sum(v);
        }
        sum(&self.compute(a, b))
    }

    /// The normal equations of `ids` over the folds `on`: `XᵀX`, `Xᵀr`
    /// and `rᵀr`.
    pub fn normal(&self, ids: &[usize], on: &[bool]) -> (Mat<f64>, Vec<f64>, f64) {
        let m = ids.len();
        let mut g = Mat::<f64>::zeros(m, m);
        for a in 0..m {
            for b in a..m {
                let v = self.pair(ids[a], ids[b], on);
                g[(a, b)] = v;
                g[(b, a)] = v;
            }
        }
        let sum = |v: &[f64]| {
            (v.iter().zip(on))
                .filter(|(_, o)| **o)
                .map(|(x, _)| x)
                .sum()
        };
        let xr = ids.iter().map(|&a| sum(&self.xr[a])).collect();
        let rr = (self.rr.iter().zip(on))
            .filter(|(_, o)| **o)
            .map(|(r, _)| r.iter().sum::<f64>())
            .sum();
        (g, xr, rr)
    }

    /// The normal equations of `ids` over the samples `range`, computed
    /// afresh (not kept): `XᵀX`, `Xᵀr` and `rᵀr`.
    pub fn normal_over(&self, ids: &[usize], range: Range<usize>) -> (Mat<f64>, Vec<f64>, f64) {
        let m = ids.len();
        let mut g = Mat::<f64>::zeros(m, m);
        for a in 0..m {
            for b in a..m {
                let v = self.dot(&self.cols[ids[a]], &self.cols[ids[b]], range.clone());
                g[(a, b)] = v;
                g[(b, a)] = v;
            }
        }
        let xr = ids
            .iter()
            .map(|&a| self.dot_r(&self.cols[a], range.clone()))
            .collect();
        let n = self.n;
        let rr = dot(
            &self.r[range.start * n..range.end * n],
            &self.r[range.start * n..range.end * n],
        );
        (g, xr, rr)
    }

    /// `r − Σ βⱼ x_{ids[j]}` over the samples `range` (sample-major rows).
    pub fn residual_on(&self, ids: &[usize], beta: &[f64], range: Range<usize>) -> Vec<f64> {
        let n = self.n;
        let mut out = self.r[range.start * n..range.end * n].to_vec();
        for (&id, &b) in ids.iter().zip(beta) {
            if b == 0.0 {
                continue;
            }
            let c = &self.cols[id];
            match c.joint {
                Some(i) => {
                    for k in range.clone() {
                        out[(k - range.start) * n + i] -= b * c.values[k * n + i];
                    }
                }
                None => {
                    let src = &c.values[range.start * n..range.end * n];
                    out.iter_mut().zip(src).for_each(|(o, x)| *o -= b * x);
                }
            }
        }
        out
    }
}

enum RowSet {
    None,
    Joint(usize),
    All,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::Store;
    use crate::diagnose::folds::Folds;
    use std::ops::Range;

    fn folds(n: usize, k: usize) -> Folds {
        Folds {
            ranges: (0..k)
                .map(|j| j * n / k..(j + 1) * n / k)
                .collect::<Vec<Range<usize>>>(),
            fit: k - 1,
            by_file: false,
        }
    }

    /// The kept products equal the sums over the rows, per fold, for
    /// joint-local and dense columns alike, and the residual after a fit
    /// is `r − Xβ`.
    #[test]
    fn products_per_fold_are_the_sums_over_their_rows() {
        let (samples, n) = (40, 2);
        let r: Vec<f64> = (0..samples * n).map(|i| (i as f64 * 0.37).sin()).collect();
        let f = folds(samples, 4);
        let mut s = Store::new(r.clone(), n, &f);
        let local: Vec<f64> = (0..samples * n)
            .map(|i| if i % n == 1 { (i as f64).cos() } else { 0.0 })
            .collect();
        let other: Vec<f64> = (0..samples * n)
            .map(|i| if i % n == 0 { 1.0 } else { 0.0 })
            .collect();
        let dense: Vec<f64> = (0..samples * n).map(|i| (i as f64 * 0.1).exp()).collect();
        let ids = s.add_all(vec![local.clone(), other.clone(), dense.clone()]);
        assert_eq!((s.col(ids[0]).joint, s.col(ids[2]).joint), (Some(1), None));
        s.prepare([(ids[0], ids[2]), (ids[0], ids[1])]);
        let on = [true, false, true, true];
        let (g, xr, rr) = s.normal(&ids, &on);
        let rows = |k: usize| on[k * 4 / samples];
        let sum = |a: &[f64], b: &[f64]| -> f64 {
            (0..samples * n)
                .filter(|i| rows(i / n))
                .map(|i| a[i] * b[i])
                .sum()
        };
        let cols = [&local, &other, &dense];
        for a in 0..3 {
            assert!((xr[a] - sum(cols[a], &r)).abs() < 1e-12);
            for b in 0..3 {
                assert!((g[(a, b)] - sum(cols[a], cols[b])).abs() < 1e-9 * (1.0 + g[(a, b)].abs()));
            }
        }
        assert!((rr - sum(&r, &r)).abs() < 1e-12);
        assert_eq!(g[(0, 1)], 0.0);
        let beta = [0.5, -2.0, 0.25];
        let after = s.residual_on(&ids, &beta, 10..20);
        for (q, v) in after.iter().enumerate() {
            let i = 10 * n + q;
            let want = r[i] - 0.5 * local[i] + 2.0 * other[i] - 0.25 * dense[i];
            assert!((v - want).abs() < 1e-12);
        }
    }

    /// Rows outside the folds: a fit of their columns on some folds is the
    /// least squares over those folds' rows and the outside rows together
    /// (two columns, only the first has outside rows); the same rows with
    /// coefficients applied (`Prior::at`) are those of `r − Y·applied`.
    #[test]
    fn rows_outside_the_folds_join_every_fit_of_their_columns() {
        use super::Prior;
        use crate::diagnose::refit::{Group, fit};
        let samples = 60;
        let x0: Vec<f64> = (0..samples).map(|k| (k as f64 * 0.3).sin()).collect();
        let x1: Vec<f64> = (0..samples).map(|k| (k as f64 * 0.05).cos()).collect();
        let r: Vec<f64> = (0..samples)
            .map(|k| 2.0 * x0[k] - x1[k] + (k as f64).sin())
            .collect();
        let mut s = Store::new(r.clone(), 1, &folds(samples, 3));
        let ids = s.add_all(vec![x0.clone(), x1.clone()]);
        // outside rows over x0 only: y and their residual e
        let y: Vec<f64> = (0..25).map(|k| 1.0 + (k as f64 * 0.7).cos()).collect();
        let e: Vec<f64> = (0..25)
            .map(|k| 0.3 * y[k] + 0.1 * (k as f64).cos())
            .collect();
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
        let prior = Prior {
            ids: vec![ids[0]],
            g: faer::Mat::from_fn(1, 1, |_, _| dot(&y, &y)),
            xr: vec![dot(&y, &e)],
            rr: dot(&e, &e),
        };
        s.set_prior(prior.clone());
        let on = [true, true, false];
        let beta = fit(&s, &[&Group::plain(ids.clone())], &on, &[true])
            .unwrap()
            .beta;
        // the same least squares written out: rows of folds 1–2, then the outside rows
        let rows: Vec<usize> = (0..40).collect();
        let col = |c: &[f64], out: &[f64]| -> Vec<f64> {
            rows.iter()
                .map(|&k| c[k])
                .chain(out.iter().copied())
                .collect()
        };
        let (a0, a1) = (col(&x0, &y), col(&x1, &[0.0; 25]));
        let b = col(&r, &e);
        let (g00, g01, g11) = (dot(&a0, &a0), dot(&a0, &a1), dot(&a1, &a1));
        let (b0, b1) = (dot(&a0, &b), dot(&a1, &b));
        let det = g00 * g11 - g01 * g01;
        let want = [(g11 * b0 - g01 * b1) / det, (g00 * b1 - g01 * b0) / det];
        for (got, w) in beta.iter().zip(want) {
            assert!(
                (got - w).abs() < 1e-7 * (1.0 + w.abs()),
                "{beta:?} vs {want:?}"
            );
        }
        // without the outside rows' column the fit is that of the folds alone
        let only1 = fit(&s, &[&Group::plain(vec![ids[1]])], &on, &[true])
            .unwrap()
            .beta;
        let rows40: Vec<f64> = rows.iter().map(|&k| x1[k]).collect();
        let r40: Vec<f64> = rows.iter().map(|&k| r[k]).collect();
        assert!((only1[0] - dot(&rows40, &r40) / dot(&rows40, &rows40)).abs() < 1e-9);
        // applied coefficients taken off the outside residual
        let moved = prior.at(vec![7], &[0.25]);
        let e2: Vec<f64> = e.iter().zip(&y).map(|(a, b)| a - 0.25 * b).collect();
        assert_eq!(moved.ids, vec![7]);
        assert!((moved.xr[0] - dot(&y, &e2)).abs() < 1e-12);
        assert!((moved.rr - dot(&e2, &e2)).abs() < 1e-12);
    }
}
