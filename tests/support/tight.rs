//! Tight solver tolerances for tests against closed forms (shared with
//! `#[path = "support/tight.rs"] mod tight;`).

use momentlmi::conic::Settings;

/// Gap and feasibility tolerances 1e-10.
pub fn tight() -> Settings {
    Settings::default()
        .tol_gap_abs(1e-10)
        .tol_gap_rel(1e-10)
        .tol_feas(1e-10)
}
