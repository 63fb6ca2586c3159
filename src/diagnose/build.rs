//! Building the candidates: every effect of the library that applies to
//! the model, is not a term of the nominal friction law and fits the
//! memory plan proposes its hypothesis, built in parallel (the most
//! expensive first); their columns go into the store in the library's
//! order.

use super::alias::{merge_aliases, within_law};
use super::candidate::Candidate;
use super::law::Law;
use super::store::Store;
use super::warning::DiagnoseWarning;
use crate::effects::{Context, Effect, EffectError, Hypothesis, Library};
use std::sync::{Arc, OnceLock};

/// One effect's hypothesis, or why not.
type Built = Result<Hypothesis, EffectError>;

/// Why an effect that is one of the nominal law's terms is not proposed.
const IN_LAW: &str = "not proposed: the nominal model's friction law has this term, whose coefficients are refit with the law";
/// Why a correction of the nominal's bodies is not proposed when they are
/// refit with the law.
const BODIES_REFIT: &str = "not proposed: the nominal's bodies are refit with the friction law, on these data and the data it was identified on";

/// Why a hypothesis within the law's span is not proposed.
const LAW_SPAN: &str = "not proposed: on these data its columns lie within those of the nominal friction law, refit with the law";

/// The effects of `library` the diagnosis proposes for `cx`: not those
/// `left_out` (by the memory plan), and with a warning each not those that
/// do not apply to the model or are terms of `law`.
fn proposed(
    library: &Library,
    cx: &Context,
    left_out: &[&str],
    law: &Law,
    warnings: &mut Vec<DiagnoseWarning>,
) -> Vec<Arc<dyn Effect>> {
    let mut out = vec![];
    for e in library.effects() {
        if left_out.contains(&e.name()) {
            continue;
        }
        let why = match e.inapplicable(cx.model) {
            Some(why) => Some(why),
            None if law.bodies > 0 && e.changes_nominal_bodies() => Some(BODIES_REFIT),
            None => (e.law_term()).and_then(|t| law.terms.contains(&t).then_some(IN_LAW)),
        };
        match why {
            Some(why) => warnings.push(DiagnoseWarning::NotProposed {
                effect: e.name().into(),
                reason: why.into(),
            }),
            None => out.push(e.clone()),
        }
    }
    out
}

/// The candidates of `library` for the data of `cx` ([`proposed`]), their
/// columns added to `store`; with a warning each, those whose hypothesis
/// cannot be built or lies within the law's span. Candidates with one span
/// are merged ([`merge_aliases`]).
pub fn candidates(
    library: &Library,
    cx: &Context,
    (left_out, law): (&[&str], &Law),
    store: &mut Store,
    warnings: &mut Vec<DiagnoseWarning>,
) -> Vec<Candidate> {
    let proposed = proposed(library, cx, left_out, law, warnings);
    // what several hypotheses share, computed with every core first
    proposed.iter().for_each(|e| e.prepare(cx));
    let built = build_all(&proposed, |e| e.hypothesis(cx));
    let mut out = vec![];
    for (e, b) in proposed.iter().zip(built) {
        let why = match b.map(|h| Candidate::new(e.clone(), h, store)) {
            Ok(Some(c)) if within_law(&c, &law.friction_group(), store) => LAW_SPAN.to_string(),
            Ok(Some(c)) => {
                out.push(c);
                continue;
            }
            Ok(None) => "its hypothesis has no columns for these data".into(),
            Err(err) => err.to_string(),
        };
        warnings.push(DiagnoseWarning::NotBuilt {
            effect: e.name().into(),
            reason: why,
        });
    }
    merge_aliases(out, store)
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
