//! The largest eigenvalue of a symmetric matrix as an SDP, with the dual of
//! its LMI: `λmax(A) = min t s.t. t·I − A ⪰ 0`, whose dual matrix is the top
//! eigenvector's projector `v vᵀ`.
//!
//! Run: `cargo run --release --example lambda_max`
//!
//! The same in CVXPY (4 lines of model, as here):
//! ```text
//! t = cp.Variable()
//! lmi = t * np.eye(3) - A >> 0
//! cp.Problem(cp.Minimize(t), [lmi]).solve()
//! Z = lmi.dual_value
//! ```

use momentlmi::conic::{MatExpr, Problem, Settings, check_optimality};
use nalgebra::DMatrix;

/// λmax, the dual matrix Z, and the KKT residuals.
pub fn run(a: &DMatrix<f64>) -> Result<(f64, DMatrix<f64>, f64), Box<dyn std::error::Error>> {
    let mut p = Problem::new();
    let t = p.scalar("t");
    let lmi = p.add_psd(MatExpr::scaled_identity(a.nrows(), t) - MatExpr::constant(a))?;
    p.minimize(t);
    let sol = p.solve(&Settings::default())?.solved()?;
    let z = sol.dual_matrix(lmi)?;
    let kkt = check_optimality(&p, &sol);
    Ok((sol.value(t)?, z, kkt.max()))
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = DMatrix::from_row_slice(3, 3, &[2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0]);
    let (lmax, z, kkt) = run(&a)?;
    println!("λmax = {lmax:.9} (exact 2 + √2 = {:.9})", 2.0 + 2f64.sqrt());
    println!("dual Z (trace {:.6}):{z:.6}", z.trace());
    println!("largest optimality residual: {kkt:.2e}");
    Ok(())
}
