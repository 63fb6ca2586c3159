//! # `conic`: a small modelling layer for LMIs and conic programs on Clarabel
//!
//! ```text
//! minimise    cᵀx + c₀ + Σₖ wₖ (aₖᵀx + bₖ)²
//! subject to  sᵢ(x) ∈ Kᵢ,   Kᵢ ∈ {0, ℝ₊ⁿ, second-order, PSD, exponential cone}
//! ```
//!
//! Variables ([`Var`], [`SymVar`]) live in a [`Problem`]; affine scalar
//! expressions ([`AffExpr`]) and affine matrix expressions ([`MatExpr`])
//! combine them with `+`, `−`, scalar `×`, constant matrix products, blocks,
//! trace and inner products. `log`, relative entropy and `log det` are
//! atoms on the exponential cone ([`Problem::add_logdet_ge`]). Constraints return a [`ConstraintId`] whose dual
//! the [`Solution`] gives back (PSD duals as full symmetric matrices).
//! [`Problem::compile`] produces Clarabel's `(P, q, A, b, K)` once
//! ([`Compiled`]), with PSD cones as √2-scaled upper triangles.
//!
//! Dual sign convention: for a constraint `s(x) ∈ K` the dual `z ∈ K*`
//! satisfies `∇f(x) = Σ Ds(x)ᵀ z` at the optimum of the minimised objective
//! (under `maximize`, of its negation); [`Solution::sensitivity`] gives a
//! scalar constraint's shadow price in the user's sense; [`check_optimality`]
//! verifies the convention for any result.
//!
//! ```
//! use momentlmi::conic::{MatExpr, Problem, Settings};
//! use nalgebra::DMatrix;
//! // λmax(A) = min t s.t. tI − A ⪰ 0
//! let a = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
//! let mut p = Problem::new();
//! let t = p.scalar("t");
//! let lmi = p.add_psd(MatExpr::scaled_identity(2, t) - MatExpr::constant(&a))?;
//! p.minimize(t);
//! let sol = p.solve(&Settings::default())?.solved()?;
//! assert!((sol.value(t)? - 3.0).abs() < 1e-7);
//! // the dual: the projector on the top eigenvector
//! assert!((sol.dual_matrix(lmi)?.trace() - 1.0).abs() < 1e-6);
//! # Ok::<(), momentlmi::conic::ConicError>(())
//! ```
//!
//! Handles ([`Var`], [`ConstraintId`]) carry their problem's identity: using
//! one with another problem or its solution is [`ConicError::ForeignHandle`].
//! Matrix operators panic on a shape mismatch, as nalgebra's do; the `try_`
//! methods return [`ConicError::DimensionMismatch`].

mod compile;
mod error;
mod expr;
mod kkt;
mod logdet;
mod matexpr;
mod problem;
mod settings;
mod solution;
mod status;
mod verify;

pub use compile::Compiled;
pub use error::ConicError;
pub use expr::{AffExpr, Var, sum};
pub use kkt::{KktReport, check_optimality};
pub use logdet::LogDet;
pub use matexpr::MatExpr;
pub(crate) use problem::ConstraintData;
pub use problem::{ConeKind, ConstraintId, Problem, Sense, SymVar};
pub use settings::{Decomposition, KktSolver, LeastSquaresForm, Settings};
pub use solution::{DecompositionOutcome, Dual, Solution, svec_to_mat};
pub use status::Status;
