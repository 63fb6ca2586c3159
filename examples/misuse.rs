//! Deliberate misuse of the modelling layer: every mistake is an error that
//! says what is wrong — none is an alias, a silent zero or a panic.
//!
//! Run: `cargo run --release --example misuse`

use momentlmi::conic::{AffExpr, ConicError, MatExpr, Problem, Settings};

/// Each mistake and the error it gives.
pub fn run() -> Result<Vec<(&'static str, ConicError)>, ConicError> {
    let mut a = Problem::new();
    let x = a.scalar("x");
    let mut b = Problem::new();
    let y = b.scalar("y"); // the same index as x in its own problem
    let by = b.add_ge(y, 1.0)?;
    let mut out = vec![];
    let mut record = |what, r: Result<(), ConicError>| {
        if let Err(e) = r {
            out.push((what, e));
        }
    };
    record(
        "a variable of another problem",
        a.add_ge(y, 1.0).map(|_| ()),
    );
    record(
        "an expression mixing two problems",
        a.add_eq(x + y, 0.0).map(|_| ()),
    );
    record(
        "mismatched coefficient count",
        AffExpr::linear(&[x], &[1.0, 2.0], 0.0).map(|_| ()),
    );
    record(
        "a non-square LMI",
        a.add_psd(MatExpr::zeros(2, 3)).map(|_| ()),
    );
    record(
        "adding 2×2 and 3×3",
        MatExpr::identity(2)
            .try_add(&MatExpr::identity(3))
            .map(|_| ()),
    );
    // infeasible: x ≥ 1 and x ≤ 0; then read a value anyway
    a.add_ge(x, 1.0)?;
    a.add_le(x, 0.0)?;
    a.minimize(x);
    let sol = a.solve(&Settings::default())?;
    record(
        "reading x of an infeasible problem",
        sol.value(x).map(|_| ()),
    );
    record(
        "the dual of another problem's constraint",
        sol.dual(by).map(|_| ()),
    );
    record("requiring a solution", sol.clone().solved().map(|_| ()));
    let mut c = Problem::new();
    let z = c.scalar("z");
    c.add_square(-1.0, z - 1.0);
    record(
        "a negative weight",
        c.solve(&Settings::default()).map(|_| ()),
    );
    Ok(out)
}

#[allow(dead_code)]
fn main() -> Result<(), ConicError> {
    for (what, e) in run()? {
        println!("{what:<42} → {e}");
    }
    Ok(())
}
