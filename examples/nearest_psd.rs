//! The nearest positive semidefinite matrix to a symmetric C in the
//! Frobenius norm: `min ‖X − C‖²_F s.t. X ⪰ 0`. The answer is known in
//! closed form (clip C's negative eigenvalues), which checks the SDP.
//!
//! Run: `cargo run --release --example nearest_psd`
//!
//! The same in CVXPY (4 lines of model, as here):
//! ```text
//! X = cp.Variable((n, n), symmetric=True)
//! prob = cp.Problem(cp.Minimize(cp.sum_squares(X - C)), [X >> 0])
//! prob.solve()
//! X.value
//! ```

use momentlmi::conic::{MatExpr, Problem, Settings};
use nalgebra::DMatrix;

/// The nearest PSD matrix to `c`.
pub fn run(c: &DMatrix<f64>) -> Result<DMatrix<f64>, Box<dyn std::error::Error>> {
    let mut p = Problem::new();
    let x = p.symmetric("X", c.nrows());
    p.add_psd(&x)?;
    p.add_frobenius(1.0, x.expr() - MatExpr::constant(c));
    let sol = p.solve(&Settings::default().tol_gap_rel(1e-10))?.solved()?;
    Ok(sol.sym_value(&x)?)
}

/// The closed form: `V max(Λ, 0) Vᵀ`.
pub fn clipped(c: &DMatrix<f64>) -> DMatrix<f64> {
    let e = c.clone().symmetric_eigen();
    let l = DMatrix::from_diagonal(&e.eigenvalues.map(|v| v.max(0.0)));
    &e.eigenvectors * l * e.eigenvectors.transpose()
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let c = DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 0.0, 2.0, 1.0, 0.5, 0.0, 0.5, -0.5]);
    let x = run(&c)?;
    println!("nearest PSD matrix:{x:.6}");
    println!(
        "distance to the closed form: {:.2e}",
        (&x - clipped(&c)).abs().max()
    );
    Ok(())
}
