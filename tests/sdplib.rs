//! SDPLIB instances from `../shared/sdplib/` against their published optimal
//! values. The folder is test data outside the repository: when it is absent
//! these tests print a message and pass (the SDPA reader and the conic layer
//! have their own self-contained tests in `sdpa_format.rs` and
//! `conic_known.rs`).
//!
//! Every instance is solved with the defaults: the reader's default options
//! (memory limit 8 GiB) and the default solver settings (verified chordal
//! decomposition), through `SdpaProblem::solve_with` as the command
//! does. gpp100 (a dense PSD block of side 100, which decomposition cannot
//! help: Clarabel's KKT system holds a dense `n(n+1)/2`-square block, 80 s
//! here) and arch0 (sparse: 15–17 s in release with the decomposition,
//! much longer in a debug build) are `#[ignore]`d in the default run; run
//! them with `cargo test --release --test sdplib -- --ignored`. mcp100 and
//! mcp124-1 are sparse and take 0.1–1 s with the decomposition.
//!
//! The reader's memory estimates (docs/inputs.md): mcp100 1.38 GiB (0.64
//! decomposed), mcp124-1 3.2 GiB (0.076), arch0 9.0 GiB (5.6 decomposed: it fits
//! the default limit only decomposed, so its fall-back is forbidden).

use momentlmi::conic::{DecompositionOutcome, Settings};
use momentlmi::sdpa::{SdpaOptions, SdpaProblem};
use std::path::PathBuf;

/// Published SDPLIB optimal values (facts from the SDPLIB distribution).
const PUBLISHED: &[(&str, f64)] = &[
    ("truss1", -8.999996e+00),
    ("truss3", -9.109996e+00),
    ("truss4", -9.009996e+00),
    ("control1", 1.778463e+01),
    ("control2", 8.300000e+00),
    ("hinf1", 2.0326e+00),
    ("hinf2", 1.0967e+01),
    ("theta1", 2.300000e+01),
    ("qap5", -4.360e+02),
    ("mcp100", 2.261574e+02),
    ("mcp124-1", 1.419905e+02),
    ("gpp100", -4.49435e+01),
    ("arch0", 5.66517e-01),
];

fn dir() -> Option<PathBuf> {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/sdplib");
    if d.is_dir() {
        Some(d)
    } else {
        println!(
            "skipping: {} not found (SDPLIB test data lives outside the repo)",
            d.display()
        );
        None
    }
}

/// Relative error allowed against the published value: 1e-6, except for the
/// ill-posed hinf problems (1e-3) and values published with fewer digits
/// (half a unit in the last published digit).
fn tolerance(name: &str) -> f64 {
    match name {
        "hinf1" | "hinf2" => 1e-3,
        _ => 1e-6,
    }
}

fn check(name: &str) {
    let Some(d) = dir() else { return };
    let &(_, want) = PUBLISHED
        .iter()
        .find(|(n, _)| *n == name)
        .expect("known instance");
    let prob = SdpaProblem::read(&d.join(format!("{name}.dat-s"))).expect("readable");
    let (sol, _) = prob
        .solve_with(&SdpaOptions::default(), Settings::default())
        .expect("solvable");
    let hinf = name.starts_with("hinf");
    assert!(
        sol.status.is_solved()
            && (hinf || name == "gpp100" || sol.status == momentlmi::conic::Status::Solved),
        "{name}: status {}",
        sol.status
    );
    let rel = (sol.primal_objective - want).abs() / want.abs();
    // published values carry 5–7 significant digits
    let digits_tol = match name {
        "hinf1" | "qap5" => 5e-5,
        "hinf2" | "gpp100" | "arch0" => 5e-6,
        _ => 0.0,
    };
    let tol = tolerance(name).max(digits_tol);
    println!(
        "{name}: {:.9e} (published {want:e}), rel err {rel:.2e}, {}",
        sol.primal_objective, sol.status
    );
    assert!(
        rel <= tol,
        "{name}: got {} want {want}, rel err {rel:e} > {tol:e}",
        sol.primal_objective
    );
}

macro_rules! instance {
    ($($f:ident = $name:literal),* $(,)?) => {$(
        #[test]
        fn $f() { check($name); }
    )*};
}
instance!(
    truss1 = "truss1",
    truss3 = "truss3",
    truss4 = "truss4",
    control1 = "control1",
    control2 = "control2",
    hinf1 = "hinf1",
    hinf2 = "hinf2",
    theta1 = "theta1",
    qap5 = "qap5",
    // 0.1–20 s each with the (verified) chordal decomposition; 25–800 s without
    mcp100 = "mcp100",
    mcp124_1 = "mcp124-1"
);

macro_rules! slow_instance {
    ($($f:ident = $name:literal),* $(,)?) => {$(
        #[test]
        #[ignore = "minutes: run with --ignored"]
        fn $f() { check($name); }
    )*};
}
// arch0: 15–17 s in release with the decomposition, far longer in a debug build
slow_instance!(gpp100 = "gpp100", arch0 = "arch0");

fn infeasibility(name: &str, primal: bool) {
    let Some(d) = dir() else { return };
    let prob = SdpaProblem::read(&d.join(format!("{name}.dat-s"))).expect("readable");
    let (p, _) = prob.to_problem().expect("convertible");
    let sol = p.solve(&Settings::default()).expect("solvable");
    if primal {
        assert!(sol.status.is_primal_infeasible(), "{name}: {}", sol.status);
    } else {
        assert!(sol.status.is_dual_infeasible(), "{name}: {}", sol.status);
    }
}

#[test]
fn infp1_is_primal_infeasible() {
    infeasibility("infp1", true);
}

#[test]
fn infd1_is_dual_infeasible() {
    infeasibility("infd1", false);
}

/// control1 and control2 with the decomposition requested (the default,
/// verified): Clarabel 0.11's decomposed control1 ends "solved" at 18.0568
/// (17.78463 is right); the check must catch it and the fall-back return the
/// published value. `None` when the test data are absent.
fn decomposed(name: &str) -> Option<momentlmi::conic::Solution> {
    let prob = SdpaProblem::read(&dir()?.join(format!("{name}.dat-s"))).expect("readable");
    let (p, _) = prob.to_problem().expect("convertible");
    let sol = p.solve(&Settings::default()).expect("solvable");
    println!("{name}: {} {}", sol.primal_objective, sol.decomposition);
    Some(sol)
}

#[test]
fn control1_decomposed_falls_back_to_the_right_value() {
    let Some(sol) = decomposed("control1") else {
        return;
    };
    assert!(
        matches!(sol.decomposition, DecompositionOutcome::FellBack(_)),
        "{}",
        sol.decomposition
    );
    assert!((sol.primal_objective - 17.78463).abs() / 17.78463 < 1e-6);
    check("control1");
}

#[test]
fn control2_decomposed_is_right() {
    let Some(sol) = decomposed("control2") else {
        return;
    };
    assert!(
        (sol.primal_objective - 8.3).abs() / 8.3 < 1e-6,
        "{}",
        sol.primal_objective
    );
}

#[test]
fn memory_estimates_fit_the_default_limit_arch0_only_decomposed() {
    let Some(d) = dir() else { return };
    let off = SdpaOptions::default().decomposition(momentlmi::conic::Decomposition::Off);
    for &(name, _) in PUBLISHED {
        let prob = SdpaProblem::read(&d.join(format!("{name}.dat-s"))).expect("readable");
        let est = prob.memory_estimate().expect("sizes fit");
        println!("{name}: {:.4} GiB ({})", est.total_gib(), est.detail());
        assert!(
            est.check(&SdpaOptions::default()).is_ok(),
            "{name}: {}",
            est.detail()
        );
        let fits = est.check(&off).is_ok();
        assert_eq!(fits, name != "arch0", "{name}: {} GiB", est.total_gib());
        // the clique analysis: the max-cut and arch0 blocks split (74 and 70
        // maximal cliques), gpp100's and theta1's patterns are one clique
        let splits = est.decomposed_blocks > 0;
        match name {
            "mcp100" | "mcp124-1" | "arch0" => assert!(splits, "{name}: {}", est.detail()),
            "gpp100" | "theta1" | "qap5" => assert!(!splits, "{name}: {}", est.detail()),
            _ => {}
        }
    }
}
