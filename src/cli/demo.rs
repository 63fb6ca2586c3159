//! `momentlmi demo`: until the identification layers exist, it solves the
//! conic layer's bundled examples and prints their known answers beside the
//! computed ones.

use crate::conic::{MatExpr, Problem, Settings};
use nalgebra::DMatrix;
use std::path::Path;

fn lovasz_theta(n: usize, edges: &[(usize, usize)]) -> Result<f64, crate::conic::ConicError> {
    // θ(G) = max ⟨J, X⟩ s.t. tr X = 1, X_ij = 0 for ij ∈ E, X ⪰ 0
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let xe = x.expr();
    p.add_eq(xe.trace()?, 1.0)?;
    for &(i, j) in edges {
        p.add_eq(xe.get(i, j)?.clone(), 0.0)?;
    }
    p.add_psd(&xe)?;
    p.maximize(xe.dot(&DMatrix::from_element(n, n, 1.0))?);
    Ok(p.solve(&Settings::default())?.primal_objective)
}

/// Runs the demo; returns the exit code.
pub fn run(_out: &Path) -> i32 {
    let c5: Vec<(usize, usize)> = (0..5).map(|i| (i, (i + 1) % 5)).collect();
    let mut petersen: Vec<(usize, usize)> = (0..5).map(|i| (i, (i + 1) % 5)).collect();
    petersen.extend((0..5).map(|i| (5 + i, 5 + (i + 2) % 5)));
    petersen.extend((0..5).map(|i| (i, i + 5)));
    let a = DMatrix::from_row_slice(3, 3, &[2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0]);
    let lmax = (|| -> Result<f64, crate::conic::ConicError> {
        let mut p = Problem::new();
        let t = p.scalar("t");
        p.add_psd(&MatExpr::scaled_identity(3, t).try_sub(&MatExpr::constant(&a))?)?;
        p.minimize(t);
        Ok(p.solve(&Settings::default())?.primal_objective)
    })();
    let rows = [
        (
            "λmax of tridiag(−1, 2, −1) (n = 3)",
            lmax,
            2.0 + 2f64.sqrt(),
        ),
        ("Lovász θ of the 5-cycle", lovasz_theta(5, &c5), 5f64.sqrt()),
        (
            "Lovász θ of the Petersen graph",
            lovasz_theta(10, &petersen),
            4.0,
        ),
    ];
    println!("momentlmi demo: conic layer examples (computed vs known)");
    let mut code = 0;
    for (name, got, want) in rows {
        match got {
            Ok(v) => println!(
                "  {name:<40} {v:>14.9}   known {want:>14.9}   |err| {:.1e}",
                (v - want).abs()
            ),
            Err(e) => {
                println!("  {name:<40} error: {e}");
                code = 1;
            }
        }
    }
    code
}
