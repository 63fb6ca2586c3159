//! A candidate of the diagnosis: one effect of the library with its
//! hypothesis' variants, each a [`Group`] of columns in the [`Store`] with
//! the constraints its fit keeps (an inertial correction's LMIs, a
//! payload's own pseudo-inertia).

use super::refit::Group;
use super::store::Store;
use crate::effects::{Columns, Effect, Hypothesis};
use std::sync::Arc;

/// One variant: what the effect says of it, and its columns.
pub struct Variant {
    /// Its description (its columns' values moved to the store).
    pub columns: Columns,
    /// Its columns and constraints.
    pub group: Group,
    /// The joint each column lies in, if one.
    pub col_joints: Vec<Option<usize>>,
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
    /// The candidate of `effect`'s hypothesis, its columns moved into
    /// `store`; `None` when it proposes nothing.
    pub fn new(effect: Arc<dyn Effect>, h: Hypothesis, store: &mut Store) -> Option<Self> {
        if h.variants.is_empty() {
            return None;
        }
        let variants = (h.variants.into_iter())
            .map(|mut columns| {
                let cols = std::mem::take(&mut columns.cols);
                let stated = columns.joints.len() == cols.len();
                let ids: Vec<usize> = (cols.into_iter().enumerate())
                    .map(|(a, c)| match stated {
                        true => store.add_in(c, columns.joints[a]),
                        false => store.add(c),
                    })
                    .collect();
                let col_joints = ids.iter().map(|&id| store.col(id).joint).collect();
                let group = Group {
                    ids,
                    bodies: columns.bodies.clone(),
                    nonneg: columns.nonneg,
                    ..Group::default()
                };
                Variant {
                    columns,
                    group,
                    col_joints,
                }
            })
            .collect();
        Some(Self {
            effect,
            variants,
            open_low: h.open_low,
            open_high: h.open_high,
            aliases: vec![],
        })
    }

    /// The effect's name.
    pub fn name(&self) -> &'static str {
        self.effect.name()
    }

    /// Whether its fit separates by joint: every variant unconstrained
    /// with every column in one joint's rows.
    pub fn per_joint(&self) -> bool {
        self.variants
            .iter()
            .all(|v| !v.group.constrained() && v.col_joints.iter().all(Option::is_some))
    }

    /// Each variant's group with only the columns of `joints`.
    pub fn restricted(&self, joints: &[usize]) -> Vec<Group> {
        (self.variants.iter())
            .map(|v| {
                let keep: Vec<usize> = (0..v.col_joints.len())
                    .filter(|&a| v.col_joints[a].is_some_and(|j| joints.contains(&j)))
                    .collect();
                v.group.only(&keep)
            })
            .collect()
    }

    /// Its variants' groups.
    pub fn groups(&self) -> Vec<Group> {
        self.variants.iter().map(|v| v.group.clone()).collect()
    }
}
