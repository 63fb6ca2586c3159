//! Building the candidates: every effect of the library that applies to
//! the model and fits the memory plan proposes its hypothesis, built in
//! parallel (the most expensive first) and returned in the library's order.

use super::alias::merge_aliases;
use super::candidate::Candidate;
use super::warning::DiagnoseWarning;
use crate::effects::{Context, Effect, EffectError, Hypothesis, Library};
use std::ops::Range;
use std::sync::{Arc, OnceLock};

/// One effect's candidate (none if it proposes nothing), or why not.
type Built = Result<Option<Candidate>, EffectError>;

/// The candidates of `library` for the data of `cx`, leaving out the
/// effects `left_out` (by the memory plan) and, with a warning each, those
/// that do not apply to the model or whose hypothesis cannot be built.
/// Every variant's Gram matrix over `train` is computed while the cores are
/// free. Candidates with one span are merged ([`merge_aliases`]).
pub fn candidates(
    library: &Library,
    cx: &Context,
    left_out: &[&str],
    train: &Range<usize>,
    warnings: &mut Vec<DiagnoseWarning>,
) -> Vec<Candidate> {
    let mut proposed: Vec<Arc<dyn Effect>> = vec![];
    for e in library.effects() {
        if left_out.contains(&e.name()) {
            continue;
        }
        match e.inapplicable(cx.model) {
            Some(why) => warnings.push(DiagnoseWarning::NotProposed {
                effect: e.name().into(),
                reason: why.into(),
            }),
            None => proposed.push(e.clone()),
        }
    }
    // what several hypotheses share, computed with every core first
    proposed.iter().for_each(|e| e.prepare(cx));
    let build = |e: &Arc<dyn Effect>| -> Built {
        let h: Hypothesis = e.hypothesis(cx)?;
        // the Gram matrices the selection rounds reuse, while cores are free
        Ok(Candidate::new(e.clone(), h).inspect(|c| c.warm_gram(train)))
    };
    let nothing = "its hypothesis has no columns for these data";
    let built = build_all(&proposed, build);
    let mut out = vec![];
    for (e, b) in proposed.iter().zip(built) {
        match b {
            Ok(Some(c)) => out.push(c),
            Ok(None) => warnings.push(DiagnoseWarning::NotBuilt {
                effect: e.name().into(),
                reason: nothing.into(),
            }),
            Err(err) => warnings.push(DiagnoseWarning::NotBuilt {
                effect: e.name().into(),
                reason: err.to_string(),
            }),
        }
    }
    merge_aliases(out, train)
}

/// `build` of every effect, in parallel, returned in `proposed`'s order;
/// the most expensive ([`Effect::expense`]) start first, the others on
/// whichever core is free.
fn build_all(
    proposed: &[Arc<dyn Effect>],
    build: impl Fn(&Arc<dyn Effect>) -> Built + Sync,
) -> Vec<Built> {
    let mut order: Vec<usize> = (0..proposed.len()).collect();
    order.sort_by_key(|&j| std::cmp::Reverse(proposed[j].expense()));
    let slots: Vec<OnceLock<Built>> = (0..proposed.len()).map(|_| OnceLock::new()).collect();
    rayon::scope_fifo(|s| {
        for &j in &order {
            let (build, slots) = (&build, &slots);
            s.spawn_fifo(move |_| {
                let _ = slots[j].set(build(&proposed[j]));
            });
        }
    });
    // (the scope waits for every job, so each slot is set)
    slots
        .into_iter()
        .map(|s| s.into_inner().unwrap_or(Err(EffectError::SearchFailed)))
        .collect()
}
