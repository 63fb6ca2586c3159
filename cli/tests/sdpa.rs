//! `momentlmi sdpa` on hostile files written here: every error is a named
//! message with exit code 2, never a panic (101) or an abort; the memory
//! limit; the --decomposition choice in --help and --json.

use std::process::Output;

mod common;
use common::{TempDir, bin};

/// min x₁ + x₂ s.t. [[x₁, 1], [1, x₂]] ⪰ 0, x₁ ≥ 0.5: value 2.
const SMALL: &str =
    "2\n2\n{2, -1}\n1.0 1.0\n0 1 1 2 -1.0\n1 1 1 1 1.0\n2 1 2 2 1.0\n1 2 1 1 1.0\n0 2 1 1 0.5\n";

fn run(args: &[&str]) -> (i32, String, String) {
    let Output {
        status,
        stdout,
        stderr,
    } = bin().args(args).output().unwrap();
    (
        status.code().unwrap_or(-1),
        String::from_utf8_lossy(&stdout).into_owned(),
        String::from_utf8_lossy(&stderr).into_owned(),
    )
}

fn sdpa(file: &std::path::Path, extra: &[&str]) -> (i32, String, String) {
    let mut args = vec!["sdpa", file.to_str().unwrap()];
    args.extend_from_slice(extra);
    run(&args)
}

#[test]
fn hostile_headers_are_named_errors_with_exit_code_2() {
    let d = TempDir::new("sdpa-hostile");
    let cases = [
        (
            "wrap32",
            "1\n1\n4294967296\n1.0\n1 1 1 1 1.0\n",
            "block 1 side = 4294967296",
        ),
        (
            "wrap62",
            "1\n1\n4611686018427387904\n1.0\n1 1 1 1 1.0\n",
            "block 1 side",
        ),
        (
            "tera",
            "1\n1\n1000000\n1.0\n1 1 1 1 1.0\n",
            "would need about",
        ),
        (
            "lpmin",
            "1\n1\n-9223372036854775808\n1.0\n1 1 1 1 1.0\n",
            "would need about",
        ),
        (
            "hugem",
            "18446744073709551615\n1\n2\n1.0\n",
            "line 1: m = 18446744073709551615",
        ),
        (
            "hugenb",
            "1\n18446744073709551615\n2\n1.0\n",
            "line 4: block size 2 of",
        ),
        (
            "shortc",
            "1000000000\n1\n2\n1.0\n",
            "declares m = 1000000000",
        ),
        (
            "nan",
            "1\n1\n2\n1.0\n1 1 1 1 nan\n",
            "line 5: value: 'nan' is non-finite",
        ),
        (
            "e400",
            "1\n1\n2\n1e400\n",
            "line 4: cost vector entry c1: '1e400'",
        ),
        (
            "matno",
            "1\n1\n2\n1.0\n2 1 1 1 1.0\n",
            "line 5: matrix number 2 > m = 1",
        ),
        (
            "outside",
            "1\n1\n2\n1.0\n1 1 3 1 1.0\n",
            "line 5: entry (3, 1) outside block 1",
        ),
        (
            "dup",
            "1\n1\n2\n1.0\n1 1 1 2 1.0\n1 1 2 1 1.0\n",
            "line 6: entry (matrix 1, block 1, 1, 2) was already given on line 5",
        ),
        ("empty", "", "unexpected end of file"),
    ];
    for (name, text, want) in cases {
        let f = d.write(&format!("{name}.dat-s"), text);
        let (code, _, err) = sdpa(&f, &[]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains(want), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
    }
}

#[test]
fn the_memory_limit_is_a_setting() {
    let d = TempDir::new("sdpa-memory");
    // a PSD block of side 60: about 0.2 GiB by the estimate undecomposed;
    // its pattern is diagonal, so decomposed it is 60 cones of side 1
    let mut text = "1\n1\n60\n1.0\n".to_string();
    for k in 1..=60 {
        text += &format!("1 1 {k} {k} 1.0\n");
    }
    let f = d.write("side60.dat-s", &text);
    let off = ["--max-memory-gib", "0.05", "--decomposition", "off"];
    let (code, _, err) = sdpa(&f, &off);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("more than the limit of 0.050 GiB") && err.contains("largest of side 60"),
        "{err}"
    );
    for bad in ["nan", "0", "-1", "inf"] {
        let (code, _, err) = sdpa(&f, &[&format!("--max-memory-gib={bad}")]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(err.contains("max_memory_gib"), "{bad}: {err}");
    }
    let small = d.write("small.dat-s", SMALL);
    let (code, out, err) = sdpa(&small, &["--max-memory-gib", "1", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["memory_estimate_gib"].as_f64().unwrap() < 0.1);
    assert!((v["primal_objective"].as_f64().unwrap() - 2.0).abs() < 1e-6);
}

#[test]
fn an_lp_block_of_100000_solves_in_linear_memory() {
    // min x s.t. x ≥ k/n for every k: x = 1
    let n = 100_000;
    let mut text = format!("1\n1\n-{n}\n1.0\n");
    for k in 1..=n {
        text += &format!("1 1 {k} {k} 1\n0 1 {k} {k} {}\n", k as f64 / n as f64);
    }
    let d = TempDir::new("sdpa-lp");
    let f = d.write("lp.dat-s", &text);
    let (code, out, err) = sdpa(&f, &["--json", "--max-memory-gib", "0.5"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(
        (v["primal_objective"].as_f64().unwrap() - 1.0).abs() < 1e-6,
        "{out}"
    );
}

#[test]
fn decomposition_is_a_choice_reported_in_json() {
    let (code, out, _) = run(&["sdpa", "--help"]);
    assert_eq!(code, 0);
    let help = out.replace('\n', " ");
    for v in [
        "verified",
        "unchecked",
        "off",
        "wrong optimum",
        "--max-memory-gib",
    ] {
        assert!(help.contains(v), "{v}: {out}");
    }
    let d = TempDir::new("sdpa-decomposition");
    let f = d.write("small.dat-s", SMALL);
    let (code, out, err) = sdpa(&f, &["--json", "--decomposition", "off"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("json");
    assert_eq!(v["decomposition"], "off", "{out}");
    let (code, _, err) = sdpa(&f, &["--decomposition", "sometimes"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("sometimes"), "{err}");
}

/// The max-cut relaxation of a star of side n in SDPA form,
/// min Σ yᵢ s.t. diag(y) − L/4 ⪰ 0 (F₀ = L/4, the star's pattern, whose
/// maximal cliques are its edges).
fn star_max_cut(n: usize) -> String {
    let mut text = format!("{n}\n1\n{n}\n{}\n", vec!["1"; n].join(" "));
    for k in 1..=n {
        text += &format!("{k} 1 {k} {k} 1.0\n");
    }
    text += &format!("0 1 1 1 {}\n", 0.25 * (n - 1) as f64);
    for k in 2..=n {
        text += &format!("0 1 {k} {k} 0.25\n0 1 1 {k} -0.25\n");
    }
    text
}

#[test]
fn a_problem_that_fits_only_decomposed_is_solved_decomposed() {
    // side 120: ≈ 2.75 GiB undecomposed, ≈ 60 MiB as 119 cones of side 2
    let d = TempDir::new("sdpa-fits-decomposed");
    let f = d.write("star.dat-s", &star_max_cut(120));
    let (code, out, err) = sdpa(&f, &["--json", "--max-memory-gib", "0.5"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("json");
    assert_eq!(v["decomposition"], "used", "{out}");
    assert!(v["memory_estimate_gib"].as_f64().unwrap() > 1.0, "{out}");
    assert!(
        v["memory_estimate_decomposed_gib"].as_f64().unwrap() < 0.5,
        "{out}"
    );
    // the max cut of a star with unit weights cuts every edge: 119
    let obj = v["primal_objective"].as_f64().unwrap();
    assert!((obj - 119.0).abs() < 1e-5, "{out}");
    let (code, _, err) = sdpa(&f, &["--max-memory-gib", "0.5", "--decomposition", "off"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("would need") && err.contains("--max-memory-gib"),
        "{err}"
    );
}
