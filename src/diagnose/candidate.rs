//! A candidate of the diagnosis: one effect of the library with its
//! hypothesis' variants, each keeping its Gram matrix `XᵀX` over the rows
//! first asked for (the selection fits every round on the training rows;
//! only the residual changes).

use crate::effects::{Columns, Effect, Hypothesis};
use std::borrow::Cow;
use std::ops::Range;
use std::sync::{Arc, OnceLock};

/// One variant's columns, their kept Gram matrices and the joint each
/// column lies in.
pub struct Variant {
    /// The columns.
    pub columns: Columns,
    /// Gram matrices of the first two row ranges asked for (the training
    /// rows, and the first part of them the joints are screened on).
    gram: [OnceLock<(Range<usize>, Vec<f64>)>; 2],
    joints: OnceLock<Option<Vec<usize>>>,
}

impl Variant {
    /// A variant with no Gram matrix yet.
    pub fn new(columns: Columns) -> Self {
        Self {
            columns,
            gram: [OnceLock::new(), OnceLock::new()],
            joints: OnceLock::new(),
        }
    }

    /// `XᵀX` of the columns over `rows` (k × k, row-major): kept for the
    /// first two row ranges asked for, computed afresh for others.
    pub fn gram(&self, rows: &Range<usize>) -> Cow<'_, [f64]> {
        for slot in &self.gram {
            let (at, g) = slot.get_or_init(|| (rows.clone(), gram_of(&self.columns.cols, rows)));
            if at == rows {
                return Cow::Borrowed(g);
            }
        }
        Cow::Owned(gram_of(&self.columns.cols, rows))
    }

    /// The joint each column lies in (every nonzero value in that joint's
    /// rows, `n` joints, sample-major), or `None` when a column spans
    /// several joints (or none).
    pub fn column_joints(&self, n: usize) -> Option<&[usize]> {
        self.joints
            .get_or_init(|| {
                let one = |c: &Vec<f64>| {
                    let mut rows = c.iter().enumerate().filter(|(_, x)| **x != 0.0);
                    let j = rows.next()?.0 % n;
                    rows.all(|(i, _)| i % n == j).then_some(j)
                };
                self.columns.cols.iter().map(one).collect()
            })
            .as_deref()
    }
}

/// `XᵀX` of `cols` over `rows`, row-major.
fn gram_of(cols: &[Vec<f64>], rows: &Range<usize>) -> Vec<f64> {
    let k = cols.len();
    let mut g = vec![0.0; k * k];
    for a in 0..k {
        for c in a..k {
            let v: f64 = rows.clone().map(|i| cols[a][i] * cols[c][i]).sum();
            g[a * k + c] = v;
            g[c * k + a] = v;
        }
    }
    g
}

/// An effect and its variants.
pub struct Candidate {
    /// The effect.
    pub effect: Arc<dyn Effect>,
    /// Its hypothesis' variants (never empty).
    pub variants: Vec<Variant>,
    /// A fit at the grid's first variant can hide a smaller value.
    pub open_low: bool,
    /// A fit at the grid's last variant can hide a larger value.
    pub open_high: bool,
    /// Effects whose hypotheses span the same columns on these data,
    /// offered under this one's name ([`super::alias`]).
    pub aliases: Vec<&'static str>,
}

impl Candidate {
    /// The candidate of `effect`'s hypothesis; `None` when it proposes
    /// nothing.
    pub fn new(effect: Arc<dyn Effect>, h: Hypothesis) -> Option<Self> {
        (!h.variants.is_empty()).then(|| Self {
            effect,
            variants: h.variants.into_iter().map(Variant::new).collect(),
            open_low: h.open_low,
            open_high: h.open_high,
            aliases: vec![],
        })
    }

    /// The effect's name.
    pub fn name(&self) -> &'static str {
        self.effect.name()
    }

    /// Computes and keeps every variant's Gram matrix over `rows`.
    pub fn warm_gram(&self, rows: &Range<usize>) {
        for v in &self.variants {
            v.gram(rows);
        }
    }
}
