//! The SDPA reader/writer on self-contained data: parsing, errors with line
//! numbers, round trips, and conic problems written to SDPA and read back.

use approx::assert_relative_eq;
use momentlmi::conic::{MatExpr, Problem, Settings, Status};
use momentlmi::sdpa::{SdpaError, SdpaProblem};
use nalgebra::DMatrix;

/// min x₁ + x₂ s.t. [[x₁, 1], [1, x₂]] ⪰ 0, x₁ ≥ 0.5 (diagonal block):
/// optimum x₁ = x₂ = 1, value 2.
const SMALL: &str = "\"a comment\n* another\n2 =mdim\n2 =nblocks\n{2, -1}\n1.0 1.0\n0 1 1 2 -1.0\n1 1 1 1 1.0\n2 1 2 2 1.0\n1 2 1 1 1.0\n0 2 1 1 0.5\n";

#[test]
fn parses_and_solves_a_small_file() {
    let p = SdpaProblem::parse(SMALL).unwrap();
    assert_eq!(p.m(), 2);
    assert_eq!(p.blocks, vec![2, -1]);
    assert_eq!(p.entries.len(), 5);
    let (prob, x) = p.to_problem().unwrap();
    let sol = prob.solve(&Settings::default()).unwrap();
    assert_eq!(sol.status, Status::Solved);
    assert_relative_eq!(sol.primal_objective, 2.0, epsilon = 1e-7);
    assert_relative_eq!(sol.value(x[0]).unwrap(), 1.0, epsilon = 1e-4);
}

#[test]
fn psd_and_lp_blocks_together_reach_the_known_optimum() {
    // min x₁ + x₂ s.t. [[x₁, 1], [1, x₂]] ⪰ 0 and the LP block x₁ ≥ 2,
    // x₂ ≥ 0.1: x₁x₂ ≥ 1 with x₁ ≥ 2 gives x₁ = 2, x₂ = 1/2, value 2.5
    let text = "2\n2\n{2, -2}\n1 1\n0 1 1 2 -1\n1 1 1 1 1\n2 1 2 2 1\n\
        1 2 1 1 1\n0 2 1 1 2\n2 2 2 2 1\n0 2 2 2 0.1\n";
    let p = SdpaProblem::parse(text).unwrap();
    let (prob, x) = p.to_problem().unwrap();
    let sol = prob.solve(&Settings::default()).unwrap();
    assert_eq!(sol.status, Status::Solved);
    assert_relative_eq!(sol.primal_objective, 2.5, epsilon = 1e-7);
    assert_relative_eq!(sol.value(x[0]).unwrap(), 2.0, epsilon = 1e-5);
    assert_relative_eq!(sol.value(x[1]).unwrap(), 0.5, epsilon = 1e-5);
}

#[test]
fn text_round_trip() {
    let p = SdpaProblem::parse(SMALL).unwrap();
    let q = SdpaProblem::parse(&p.to_text()).unwrap();
    assert_eq!(p, q);
}

#[test]
fn file_round_trip_writes_whole_file() {
    let p = SdpaProblem::parse(SMALL).unwrap();
    let dir = std::env::temp_dir().join(format!("momentlmi-sdpa-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("small.dat-s");
    p.write(&f).unwrap();
    assert_eq!(SdpaProblem::read(&f).unwrap(), p);
    assert!(!dir.join("small.dat-s.tmp").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn parse_errors_name_the_line() {
    let cases = [
        ("2\n1\n{2}\n1 1\n1 1 1 x 1.0\n", "line 5"),
        ("2\n1\n{2}\n1 1\n3 1 1 1 1.0\n", "matrix number 3"),
        ("2\n1\n{2}\n1 1\n1 2 1 1 1.0\n", "block number 2"),
        ("2\n1\n{2}\n1 1\n1 1 3 1 1.0\n", "outside block"),
        ("2\n1\n{-2}\n1 1\n1 1 1 2 1.0\n", "diagonal block"),
        ("2\n1\n{2}\n1 nan\n", "non-finite"),
        ("2\n1\n{2}\n1 1\n1 1 1\n", "found 3 fields"),
        ("2\n1\n", "block sizes"),
    ];
    for (text, want) in cases {
        let e = SdpaProblem::parse(text).unwrap_err();
        assert!(e.to_string().contains(want), "{text:?}: {e}");
    }
    assert!(matches!(
        SdpaProblem::read(std::path::Path::new("/nonexistent/x.dat-s")),
        Err(SdpaError::Io { .. })
    ));
}

#[test]
fn conic_problem_to_sdpa_and_back_keeps_the_optimum() {
    // Lovász θ of the 5-cycle (equalities + PSD) plus a second-order cone
    // on two extra variables: max θ-objective − t, ‖(u − 1, 2)‖ ≤ t.
    let n = 5;
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let xe = x.expr();
    let t = p.scalar("t");
    let u = p.scalar("u");
    p.add_eq(xe.trace(), 1.0).unwrap();
    for i in 0..n {
        p.add_eq(xe.get(i, (i + 1) % n).unwrap().clone(), 0.0)
            .unwrap();
    }
    p.add_psd(&xe).unwrap();
    p.add_soc(t, vec![u - 1.0, 2.0.into()]).unwrap();
    p.add_ge(u, -3.0).unwrap();
    let obj = xe.dot(&DMatrix::from_element(n, n, 1.0)) - t;
    p.maximize(obj);
    let direct = p.solve(&Settings::default()).unwrap();
    assert_relative_eq!(direct.primal_objective, 5f64.sqrt() - 2.0, epsilon = 1e-6);
    let sdpa = SdpaProblem::from_problem(&p).unwrap();
    let (q, _) = SdpaProblem::parse(&sdpa.to_text())
        .unwrap()
        .to_problem()
        .unwrap();
    let back = q.solve(&Settings::default()).unwrap();
    // SDPA minimises, so the written problem's optimum is the negation
    assert_relative_eq!(
        back.primal_objective,
        -direct.primal_objective,
        epsilon = 1e-6
    );
}

#[test]
fn sdpa_writer_rejects_what_it_cannot_express() {
    let mut p = Problem::new();
    let x = p.scalar("x");
    p.add_square(1.0, x - 1.0);
    assert!(SdpaProblem::from_problem(&p).is_err());
    let mut p = Problem::new();
    let x = p.scalar("x");
    p.minimize(x + 1.0);
    p.add_psd(&MatExpr::scaled_identity(1, x)).unwrap();
    assert!(SdpaProblem::from_problem(&p).is_err());
}
