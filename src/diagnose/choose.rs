//! Choosing among the candidates the rule accepts: the largest held-out
//! gain, unless a candidate with fewer parameters is indistinguishable
//! from it on this motion — their per-block gains differ by less than
//! [`TIE_Z`] standard errors — or removes at least [`PARSIMONY`] of what
//! it removes; the leanest such goes first (a torque gain before a
//! 70-parameter refit of the links that bends to it and also absorbs the
//! nominal inertias' own estimation error). The others within noise of
//! the one chosen are reported as tied with it.

use super::score::Evaluation;

/// Paired block-gain differences within this many standard errors are a
/// tie.
pub const TIE_Z: f64 = 2.0;
/// The share of the best candidate's held-out gain a leaner one must
/// reach to go first (the previous diagnosis' parsimony rule).
pub const PARSIMONY: f64 = 0.9;

/// Whether `a` and `b` explain the data equally: the mean of their
/// per-block gain differences is within [`TIE_Z`] standard errors of 0.
pub fn tied(a: &Evaluation, b: &Evaluation) -> bool {
    let d: Vec<f64> = (a.all_blocks.iter().zip(&b.all_blocks))
        .map(|(x, y)| x - y)
        .collect();
    let m = d.len() as f64;
    if m < 2.0 {
        return true;
    }
    let mean = d.iter().sum::<f64>() / m;
    let sd = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1.0)).sqrt();
    mean.abs() <= TIE_Z * sd / m.sqrt()
}

/// The chosen evaluation and the others tied with it, or `None` when the
/// rule accepts none.
pub fn choose(evals: &[Evaluation]) -> Option<(usize, Vec<usize>)> {
    let ok: Vec<usize> = (0..evals.len())
        .filter(|&j| evals[j].verdict.is_ok())
        .collect();
    let best = *ok
        .iter()
        .max_by(|&&a, &&b| evals[a].gain.total_cmp(&evals[b].gain))?;
    let near = |j: usize| {
        j == best || tied(&evals[best], &evals[j]) || evals[j].gain >= PARSIMONY * evals[best].gain
    };
    let group: Vec<usize> = ok.iter().copied().filter(|&j| near(j)).collect();
    let chosen = *group.iter().min_by(|&&a, &&b| {
        (evals[a].params.cmp(&evals[b].params)).then(evals[b].gain.total_cmp(&evals[a].gain))
    })?;
    let others = (group.into_iter())
        .filter(|&j| j != chosen && tied(&evals[chosen], &evals[j]))
        .collect();
    Some((chosen, others))
}
