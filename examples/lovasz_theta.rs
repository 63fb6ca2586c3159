//! The Lovász θ number of a graph — the classic SDP — for the 5-cycle
//! (θ(C₅) = √5): `max ⟨J, X⟩ s.t. tr X = 1, X_ij = 0 for every edge, X ⪰ 0`.
//!
//! Run: `cargo run --release --example lovasz_theta`
//!
//! The same in CVXPY (5 lines of model; 7 here):
//! ```text
//! X = cp.Variable((n, n), symmetric=True)
//! cons = [X >> 0, cp.trace(X) == 1]
//! cons += [X[i, j] == 0 for (i, j) in edges]
//! prob = cp.Problem(cp.Maximize(cp.sum(X)), cons)
//! prob.solve()
//! ```

use momentlmi::conic::{Problem, Settings};

/// θ of the graph on `n` vertices with these edges, and the shadow price of
/// `tr X = 1` (equal to θ: scaling the trace scales the optimum).
pub fn run(n: usize, edges: &[(usize, usize)]) -> Result<(f64, f64), Box<dyn std::error::Error>> {
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    p.add_psd(&x)?;
    let trace = p.add_eq(x.expr().trace(), 1.0)?;
    for &(i, j) in edges {
        p.add_eq(x[(i, j)], 0.0)?;
    }
    p.maximize(x.expr().sum());
    let sol = p.solve(&Settings::default())?.solved()?;
    Ok((sol.primal_objective, sol.sensitivity(trace)?))
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let c5: Vec<(usize, usize)> = (0..5).map(|i| (i, (i + 1) % 5)).collect();
    let (theta, price) = run(5, &c5)?;
    println!(
        "θ(C₅) = {theta:.9} (√5 = {:.9}); shadow price of tr X = 1: {price:.9}",
        5f64.sqrt()
    );
    Ok(())
}
