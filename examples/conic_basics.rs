//! The conic layer on its own: the largest eigenvalue of a matrix as an SDP,
//! with the dual matrix (the top eigenvector's projector) read back.
//!
//! Run: `cargo run --release --example conic_basics`

use momentlmi::conic::{MatExpr, Problem, Settings, check_optimality};
use nalgebra::DMatrix;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = DMatrix::from_row_slice(3, 3, &[2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0]);
    let mut p = Problem::new();
    let t = p.scalar("t");
    // t·I − A ⪰ 0
    let lmi = p.add_psd(&MatExpr::scaled_identity(3, t).try_sub(&MatExpr::constant(&a))?)?;
    p.minimize(t);
    let sol = p.solve(&Settings::default())?;
    println!(
        "status {}, λmax = {:.9} (exact 2 + √2 = {:.9})",
        sol.status,
        sol.value(t)?,
        2.0 + 2f64.sqrt()
    );
    let z = sol.dual_matrix(lmi)?;
    println!("dual Z (trace {:.6}):{z:.6}", z.trace());
    println!("optimality residuals: {:?}", check_optimality(&p, &sol));
    Ok(())
}
