//! [`Status`]: how a solve ended.

use serde::Serialize;

/// How the solver ended. Every Clarabel status maps to exactly one of these.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Optimal within the tolerances.
    Solved,
    /// Optimal within Clarabel's reduced tolerances.
    SolvedInaccurately,
    /// A certificate that no x satisfies the constraints.
    PrimalInfeasible,
    /// As [`Status::PrimalInfeasible`], reduced accuracy.
    PrimalInfeasibleInaccurate,
    /// A certificate that the objective is unbounded below.
    DualInfeasible,
    /// As [`Status::DualInfeasible`], reduced accuracy.
    DualInfeasibleInaccurate,
    /// The iteration limit was reached.
    IterationLimit,
    /// The time limit was reached.
    TimeLimit,
    /// The solver hit a numerical error.
    NumericalError,
    /// The solver stopped making progress.
    InsufficientProgress,
    /// The solver did not run.
    NotSolved,
}

impl Status {
    /// Solved, accurately or not.
    pub fn is_solved(self) -> bool {
        matches!(self, Status::Solved | Status::SolvedInaccurately)
    }
    /// Primal infeasible, accurately or not.
    pub fn is_primal_infeasible(self) -> bool {
        matches!(
            self,
            Status::PrimalInfeasible | Status::PrimalInfeasibleInaccurate
        )
    }
    /// Dual infeasible (unbounded), accurately or not.
    pub fn is_dual_infeasible(self) -> bool {
        matches!(
            self,
            Status::DualInfeasible | Status::DualInfeasibleInaccurate
        )
    }
    /// A short lower-case name (`solved`, `primal_infeasible`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Solved => "solved",
            Status::SolvedInaccurately => "solved_inaccurately",
            Status::PrimalInfeasible => "primal_infeasible",
            Status::PrimalInfeasibleInaccurate => "primal_infeasible_inaccurate",
            Status::DualInfeasible => "dual_infeasible",
            Status::DualInfeasibleInaccurate => "dual_infeasible_inaccurate",
            Status::IterationLimit => "iteration_limit",
            Status::TimeLimit => "time_limit",
            Status::NumericalError => "numerical_error",
            Status::InsufficientProgress => "insufficient_progress",
            Status::NotSolved => "not_solved",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}
