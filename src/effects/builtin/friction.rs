//! What the effects of the friction law share (not an effect itself): the
//! true robot's coefficients of one term, scaled from the robot's nominal
//! ones, and one term's basis as a hypothesis.

use crate::dynamics::FrictionTerm;
use crate::effects::{Context, Hypothesis, Size, SizeContext};
use crate::sim::{SimWarning, Truth};

/// The robot's nominal coefficients of `term` times `scale`; a warning
/// naming `effect` when they are zero on every joint (it then changes
/// nothing).
pub fn scaled_nominal(truth: &mut Truth, term: FrictionTerm, scale: f64, effect: &str) -> Vec<f64> {
    let nominal = truth.robot().friction.coefficients(term);
    let c: Vec<f64> = nominal.iter().map(|c| c * scale).collect();
    if c.iter().all(|x| *x == 0.0) {
        truth.warn(SimWarning::NominalFrictionZero {
            effect: effect.into(),
        });
    }
    c
}

/// Why a fitted coefficient `beta` of `term` (an effect the nominal law
/// lacks, so the coefficient is the whole of it) is implausible: friction
/// that is not a signed term does not push the joint along.
pub fn term_implausible(term: FrictionTerm, beta: f64) -> Option<String> {
    (!term.signed() && beta < 0.0).then(|| {
        format!(
            "a negative {} friction coefficient ({beta:.3})",
            term.name()
        )
    })
}

/// One size per joint kept: the coefficient of `term` (`what`) in its unit.
pub fn term_sizes(beta: &[f64], cx: &SizeContext, term: FrictionTerm, what: &str) -> Vec<Size> {
    cx.per_joint(beta, what, term.unit(), 1.0)
}

/// One column per joint: the basis φ of `term` at q̇ᵢ (the load: the
/// measured torque τᵢ).
pub fn basis_hypothesis(cx: &Context, term: FrictionTerm) -> Hypothesis {
    let d = cx.data;
    let vs = cx.friction.stribeck_velocity();
    Hypothesis::per_joint(cx.per_joint(|k, i| term.basis(d.qd[k][i], d.tau[k][i], vs)))
}
