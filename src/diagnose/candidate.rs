//! A candidate of the diagnosis: one effect of the library with its
//! hypothesis' variants, each keeping its Gram matrix `XᵀX` over the rows
//! first asked for (the selection fits every round on the training rows;
//! only the residual changes).

use crate::effects::{Columns, Effect, Hypothesis};
use std::borrow::Cow;
use std::ops::Range;
use std::sync::{Arc, OnceLock};

/// One variant's columns and their kept Gram matrix.
pub struct Variant {
    /// The columns.
    pub columns: Columns,
    gram: OnceLock<(Range<usize>, Vec<f64>)>,
}

impl Variant {
    /// A variant with no Gram matrix yet.
    pub fn new(columns: Columns) -> Self {
        Self {
            columns,
            gram: OnceLock::new(),
        }
    }

    /// `XᵀX` of the columns over `rows` (k × k, row-major): kept from the
    /// first call, computed afresh for other rows.
    pub fn gram(&self, rows: &Range<usize>) -> Cow<'_, [f64]> {
        let (at, g) = self
            .gram
            .get_or_init(|| (rows.clone(), gram_of(&self.columns.cols, rows)));
        if at == rows {
            Cow::Borrowed(g)
        } else {
            Cow::Owned(gram_of(&self.columns.cols, rows))
        }
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
