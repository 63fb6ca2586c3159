//! Candidates that are one hypothesis: two effects whose columns span the
//! same space on the training rows (an offset and direction-dependent
//! friction, `1` and `|sign q̇|`, differ only where the joint stands still)
//! explain every residual equally, so they are offered once — under the
//! first one's name in the library's order, the others listed as its
//! aliases.

use super::candidate::Candidate;
use nalgebra::{DMatrix, DVector};
use std::ops::Range;

/// Each column of one candidate is within this share of its squared norm
/// of the other's span (the joints stand still on fewer than ~1 % of the
/// training samples).
const SAME_SPAN: f64 = 1e-2;

/// `cands` with every candidate whose single variant spans the same
/// columns as an earlier one's (both ways, over `train`) merged into it
/// (its name appended to the earlier one's `aliases`).
pub fn merge_aliases(cands: Vec<Candidate>, train: &Range<usize>) -> Vec<Candidate> {
    let mut out: Vec<Candidate> = vec![];
    for c in cands {
        match out.iter_mut().find(|a| same_span(a, &c, train)) {
            Some(a) => a.aliases.push(c.name()),
            None => out.push(c),
        }
    }
    out
}

/// Whether `a` and `b` are single plain linear variants with the same span
/// (their Gram matrices over `rows` are the ones the selection keeps).
fn same_span(a: &Candidate, b: &Candidate, rows: &Range<usize>) -> bool {
    let plain = |c: &Candidate| {
        c.variants.len() == 1
            && c.variants[0].columns.bodies.is_empty()
            && !c.variants[0].columns.nonneg
    };
    if !plain(a) || !plain(b) {
        return false;
    }
    let (va, vb) = (&a.variants[0], &b.variants[0]);
    let (x, y) = (&va.columns.cols, &vb.columns.cols);
    if x.len() != y.len() {
        return false;
    }
    let dot = |u: &[f64], v: &[f64]| rows.clone().map(|i| u[i] * v[i]).sum::<f64>();
    let cross = DMatrix::from_fn(x.len(), y.len(), |i, j| dot(&x[i], &y[j]));
    let (ga, gb) = (va.gram(rows), vb.gram(rows));
    within_span(&ga, &gb, &cross) && within_span(&gb, &ga, &cross.transpose())
}

/// Whether every column of Y lies within [`SAME_SPAN`] of the span of X's
/// columns: `gx = XᵀX`, `gy = YᵀY` (row-major), `cross = XᵀY` (least
/// squares through XᵀX; a singular one is not a span to compare).
fn within_span(gx: &[f64], gy: &[f64], cross: &DMatrix<f64>) -> bool {
    let (kx, ky) = cross.shape();
    let g = DMatrix::from_row_slice(kx, kx, gx);
    let Some(chol) = g.cholesky() else {
        return false;
    };
    (0..ky).all(|j| {
        let norm = gy[j * ky + j];
        let b: DVector<f64> = cross.column(j).into_owned();
        let explained = b.dot(&chol.solve(&b));
        norm > 0.0 && norm - explained <= SAME_SPAN * norm
    })
}

#[cfg(test)]
mod tests {
    use super::merge_aliases;
    use crate::diagnose::candidate::Candidate;
    use crate::effects::{Hypothesis, Library};

    fn candidate(name: &str, cols: Vec<Vec<f64>>) -> Candidate {
        let lib = Library::builtin();
        Candidate::new(lib.get(name).unwrap().clone(), Hypothesis::linear(cols)).unwrap()
    }

    /// `1` and `|sign q̇|` with the joint still on 3 of 400 samples are one
    /// hypothesis; with it still on a quarter of them they are two, and so
    /// are columns of another shape (a velocity).
    #[test]
    fn columns_with_one_span_are_offered_once() {
        let qd = |still: usize| -> Vec<f64> {
            (0..400)
                .map(|k| {
                    if k < still {
                        0.0
                    } else {
                        (k as f64 * 0.1).sin() + 1.5
                    }
                })
                .collect()
        };
        let abs_sign = |v: &[f64]| {
            v.iter()
                .map(|x| if *x == 0.0 { 0.0 } else { 1.0 })
                .collect()
        };
        let one = vec![vec![1.0; 400]];
        let merged = merge_aliases(
            vec![
                candidate("offset", one.clone()),
                candidate("asymmetric_friction", vec![abs_sign(&qd(3))]),
                candidate("viscous", vec![qd(0)]),
            ],
            &(0..400),
        );
        let names: Vec<_> = merged
            .iter()
            .map(|c| (c.name(), c.aliases.clone()))
            .collect();
        assert_eq!(
            names,
            [("offset", vec!["asymmetric_friction"]), ("viscous", vec![])]
        );
        let apart = merge_aliases(
            vec![
                candidate("offset", one),
                candidate("asymmetric_friction", vec![abs_sign(&qd(100))]),
            ],
            &(0..400),
        );
        assert_eq!(apart.len(), 2);
        assert!(apart.iter().all(|c| c.aliases.is_empty()));
    }
}
