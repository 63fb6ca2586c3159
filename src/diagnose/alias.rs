//! Hypotheses that are one on these data. Two effects whose single
//! variant spans the same columns on the data (each column of either
//! within [`SAME_SPAN`] of its squared norm of the other's span) are one
//! hypothesis: offered once, under the first name in the library's order
//! (an offset and direction-dependent friction where the joints never
//! stand still). A hypothesis within the span of the nominal friction
//! law's columns — refit in every fit — adds nothing and is not offered.

use super::candidate::Candidate;
use super::refit::Group;
use super::store::Store;
use nalgebra::{DMatrix, DVector};

/// The share of a column's squared norm that may lie outside the other
/// span for the two to count as one.
const SAME_SPAN: f64 = 1e-2;

/// `cands` with each candidate that spans the same columns as an earlier
/// one folded into it (its name in the earlier one's `aliases`).
pub fn merge_aliases(cands: Vec<Candidate>, store: &Store) -> Vec<Candidate> {
    let mut out: Vec<Candidate> = vec![];
    for c in cands {
        match out.iter_mut().find(|a| same_span(a, &c, store)) {
            Some(a) => a.aliases.push(c.name()),
            None => out.push(c),
        }
    }
    out
}

/// A candidate's only variant, when it is a plain one.
fn plain(c: &Candidate) -> Option<&Group> {
    (c.variants.len() == 1 && !c.variants[0].group.constrained()).then(|| &c.variants[0].group)
}

fn same_span(a: &Candidate, b: &Candidate, store: &Store) -> bool {
    let (Some(x), Some(y)) = (plain(a), plain(b)) else {
        return false;
    };
    x.ids.len() == y.ids.len() && within(store, &x.ids, &y.ids) && within(store, &y.ids, &x.ids)
}

/// Whether candidate `c`'s only plain variant lies within the span of `law`.
pub fn within_law(c: &Candidate, law: &Group, store: &Store) -> bool {
    !law.ids.is_empty() && plain(c).is_some_and(|g| within(store, &law.ids, &g.ids))
}

/// Whether every column of `ys` lies within the span of `xs` (over all
/// the data), but for [`SAME_SPAN`] of its squared norm.
fn within(store: &Store, xs: &[usize], ys: &[usize]) -> bool {
    let all = vec![true; store.folds()];
    let ids: Vec<usize> = xs.iter().chain(ys).copied().collect();
    let (g, _, _) = store.normal(&ids, &all);
    let (kx, ky) = (xs.len(), ys.len());
    let gx = DMatrix::from_fn(kx, kx, |i, j| g[(i, j)]);
    let ridge = 1e-12 * (0..kx).map(|i| gx[(i, i)]).fold(0.0, f64::max);
    let Some(chol) = (gx + DMatrix::identity(kx, kx) * ridge).cholesky() else {
        return false;
    };
    (0..ky).all(|j| {
        let norm = g[(kx + j, kx + j)];
        let b = DVector::from_fn(kx, |i, _| g[(i, kx + j)]);
        norm > 0.0 && norm - b.dot(&chol.solve(&b)) <= SAME_SPAN * norm
    })
}

#[cfg(test)]
mod tests {
    use super::{merge_aliases, within_law};
    use crate::diagnose::candidate::Candidate;
    use crate::diagnose::folds::Folds;
    use crate::diagnose::refit::Group;
    use crate::diagnose::store::Store;
    use crate::effects::{Hypothesis, Library};

    fn candidate(store: &mut Store, name: &str, cols: Vec<Vec<f64>>) -> Candidate {
        let lib = Library::builtin();
        Candidate::new(
            lib.get(name).unwrap().clone(),
            Hypothesis::linear(cols),
            store,
        )
        .unwrap()
    }

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
        let folds = Folds {
            ranges: vec![0..200, 200..400],
            fit: 1,
            by_file: false,
        };
        let mut s = Store::new(vec![0.0; 400], 1, &folds);
        let one = vec![vec![1.0; 400]];
        let cands = vec![
            candidate(&mut s, "offset", one.clone()),
            candidate(&mut s, "asymmetric_friction", vec![abs_sign(&qd(3))]),
            candidate(&mut s, "viscous", vec![qd(0)]),
        ];
        let merged = merge_aliases(cands, &s);
        let names: Vec<_> = merged
            .iter()
            .map(|c| (c.name(), c.aliases.clone()))
            .collect();
        assert_eq!(
            names,
            [("offset", vec!["asymmetric_friction"]), ("viscous", vec![])]
        );
        let apart = vec![
            candidate(&mut s, "offset", one.clone()),
            candidate(&mut s, "asymmetric_friction", vec![abs_sign(&qd(100))]),
        ];
        let apart = merge_aliases(apart, &s);
        assert_eq!(apart.len(), 2);
        assert!(apart.iter().all(|c| c.aliases.is_empty()));
        // a law with an offset column has what the asymmetry adds here
        let law = Group::plain(s.add_all(one));
        let asym = candidate(&mut s, "asymmetric_friction", vec![abs_sign(&qd(3))]);
        assert!(within_law(&asym, &law, &s));
        let visc = candidate(&mut s, "viscous", vec![qd(0)]);
        assert!(!within_law(&visc, &law, &s));
    }
}
