//! What a diagnosis reports without stopping: a candidate left out or
//! skipped, a fit solved only approximately, an accepted effect whose fit
//! is doubtful. Each warning prints as a sentence (`Display`) and carries a
//! stable `kind` in the JSON, with its values and that sentence
//! (`message`).

use serde::Serialize;
use std::fmt;

/// A warning of the diagnosis.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum DiagnoseWarning {
    /// Candidates left out by the memory plan.
    NotConsidered {
        /// The effects left out.
        effects: Vec<String>,
        /// What they need (GiB).
        needed_gib: f64,
        /// The limit (GiB).
        limit_gib: f64,
    },
    /// A candidate that cannot apply to the model.
    NotProposed {
        /// The effect.
        effect: String,
        /// Why.
        reason: String,
    },
    /// A candidate whose hypothesis could not be built.
    NotBuilt {
        /// The effect.
        effect: String,
        /// Why.
        reason: String,
    },
    /// A variant of a candidate whose fit failed (skipped in that round).
    FitFailed {
        /// The selection round (1-based).
        round: usize,
        /// The effect.
        effect: String,
        /// The variant (its nonlinear parameter; empty for a linear one).
        variant: String,
        /// Why.
        reason: String,
    },
    /// A constrained fit solved only to the solver's reduced tolerances.
    Inaccurate {
        /// The selection round (1-based).
        round: usize,
        /// The effect.
        effect: String,
        /// The variant.
        variant: String,
    },
    /// The final model's constrained fit failed: least squares without the
    /// constraints stands in (a corrected body may not be physically
    /// consistent, a friction coefficient may be negative).
    Unconstrained {
        /// Why the constrained fit failed.
        why: String,
    },
    /// The final model's refinement (its effects' columns built again on
    /// it) stopped before its last pass: the coefficients before the
    /// failed step are kept.
    RefinementStopped {
        /// Why.
        why: String,
    },
    /// An effect accepted although its fit is physically doubtful.
    AcceptedDoubtful {
        /// The selection round (1-based).
        round: usize,
        /// The effect.
        effect: String,
        /// Why it is doubtful.
        why: String,
    },
}

impl fmt::Display for DiagnoseWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sp = |v: &str| {
            if v.is_empty() {
                String::new()
            } else {
                format!(" {v}")
            }
        };
        match self {
            DiagnoseWarning::NotConsidered {
                effects,
                needed_gib,
                limit_gib,
            } => write!(
                f,
                "{}: not considered: it needs {needed_gib:.2} GiB beyond the {limit_gib:.2} GiB limit (fewer samples or joints, or a higher limit)",
                effects.join(", ")
            ),
            DiagnoseWarning::NotProposed { effect, reason }
            | DiagnoseWarning::NotBuilt { effect, reason } => {
                write!(f, "{effect}: {reason}")
            }
            DiagnoseWarning::FitFailed {
                round,
                effect,
                variant,
                reason,
            } => write!(
                f,
                "round {round}: candidate '{effect}'{} skipped: {reason}",
                sp(variant)
            ),
            DiagnoseWarning::Unconstrained { why } => write!(
                f,
                "the final model's constrained fit failed ({why}); its least-squares fit without the constraints is used, so a corrected body may not be physically consistent"
            ),
            DiagnoseWarning::RefinementStopped { why } => write!(
                f,
                "the final model's refinement stopped ({why}); its coefficients before that step are kept"
            ),
            DiagnoseWarning::Inaccurate {
                round,
                effect,
                variant,
            } => write!(
                f,
                "round {round}: candidate '{effect}'{}: the constrained fit was solved only to reduced tolerances",
                sp(variant)
            ),
            DiagnoseWarning::AcceptedDoubtful { round, effect, why } => {
                write!(f, "round {round}: accepted '{effect}' although {why}")
            }
        }
    }
}
