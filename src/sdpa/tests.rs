//! Hostile SDPA input: headers that wrap or ask for terabytes, non-finite
//! numbers, entries outside the declared sizes, duplicates, problems built
//! in code, and diagonal (LP) blocks that must cost O(n).

use super::options::GIB;
use super::*;
use crate::conic::{AffExpr, Decomposition, MatExpr, Problem, Settings, Status};

/// A block of side `side` with one entry, m = 1.
fn one_block(side: &str) -> String {
    format!("1\n1\n{side}\n1.0\n1 1 1 1 1.0\n")
}

fn parse_err(text: &str) -> SdpaError {
    SdpaProblem::parse(text).expect_err(text)
}

#[test]
fn wrapping_block_sides_are_named_errors_not_panics() {
    // n = 2³²: n·n wraps to 0 in 64 bits; 2⁶²: n(n+1)/2 wraps too
    for side in ["4294967296", "4611686018427387904", "9223372036854775807"] {
        let p = SdpaProblem::parse(&one_block(side)).unwrap();
        let e = p.memory_estimate().unwrap_err();
        assert!(matches!(e, SdpaError::Limit { .. }), "{side}: {e}");
        let msg = p.to_problem().unwrap_err().to_string();
        assert!(msg.contains("block 1 side") && msg.contains(side), "{msg}");
    }
}

#[test]
fn terabyte_header_fails_before_allocating() {
    // a PSD block of side 10⁶ would need ~10¹⁶ GiB; one of side 4000, ~3.3 PiB
    // (undecomposed; side 10⁶ is too large for the clique analysis, so it
    // counts as dense with decomposition too)
    let off = SdpaOptions::default().decomposition(Decomposition::Off);
    for (side, at_least_gib, opts) in [
        ("1000000", 1e15, SdpaOptions::default()),
        ("4000", 3e6, off),
    ] {
        let p = SdpaProblem::parse(&one_block(side)).unwrap();
        let est = p.memory_estimate().unwrap();
        assert!(
            est.total_gib() > at_least_gib,
            "{side}: {}",
            est.total_gib()
        );
        let e = p.to_problem_with(&opts).unwrap_err();
        let SdpaError::TooLarge {
            needed_gib,
            limit_gib,
            ..
        } = e
        else {
            panic!("{side}: {e}")
        };
        assert_eq!(limit_gib, DEFAULT_MAX_MEMORY_GIB);
        assert!(needed_gib > at_least_gib);
        assert!(
            e.to_string().contains(&format!("largest of side {side}")),
            "{e}"
        );
    }
}

/// An SDPA problem of side n, m = n, whose F₀ has a star's pattern (entry
/// (1, k) for every k), Fₖ = eₖeₖᵀ.
fn star(n: usize) -> String {
    let mut text = format!("{n}\n1\n{n}\n{}\n", vec!["1"; n].join(" "));
    for k in 1..=n {
        text += &format!("{k} 1 {k} {k} 1.0\n0 1 1 {k} 0.5\n");
    }
    text
}

#[test]
fn a_max_cut_of_side_250_is_estimated_at_tens_of_gib() {
    // Θ(n⁴): t = n(n+1)/2 = 31375 rows, 56·t² ≈ 51 GiB undecomposed; F₀'s
    // pattern is a star, whose maximal cliques are its 249 edges, so the
    // decomposed estimate is mostly the coupling term (≈ 0.23 GiB), the
    // linear part and the n × n expression
    let p = SdpaProblem::parse(&star(250)).unwrap();
    let est = p.memory_estimate().unwrap();
    assert_eq!(est.rows, 31375);
    assert!(
        (45.0..60.0).contains(&est.total_gib()),
        "{}",
        est.total_gib()
    );
    let off = SdpaOptions::default().decomposition(Decomposition::Off);
    assert!(matches!(
        p.to_problem_with(&off),
        Err(SdpaError::TooLarge { .. })
    ));
    let roomy = off.max_memory_gib(64.0);
    assert!(est.check(&roomy).is_ok());
    // decomposed: S = 249 · 2³, Σ t² ≤ S^{1/3} · S
    let s = 249.0 * 8.0f64;
    assert_eq!(est.decomposed_blocks, 1);
    let expected = est.dense_bytes + BYTES_PER_DENSE * (s.cbrt() * s - 31375f64.powi(2));
    approx::assert_relative_eq!(est.decomposed_dense_bytes, expected, max_relative = 1e-9);
    assert!(est.decomposed_total_bytes() < 0.5 * GIB, "{}", est.detail());
    assert!(est.check(&SdpaOptions::default()).is_ok());
}

#[test]
fn a_decomposed_estimate_that_fits_forbids_an_undecomposed_fall_back_that_does_not() {
    // the star of side 120: ≈ 2.75 GiB whole, ≈ 60 MiB decomposed
    let est = SdpaProblem::parse(&star(120))
        .unwrap()
        .memory_estimate()
        .unwrap();
    assert!(est.total_gib() > 1.0 && est.decomposed_total_bytes() < 0.1 * GIB);
    let tight = SdpaOptions::default().max_memory_gib(0.5);
    assert!(est.check(&tight).is_ok());
    let s = est.settings_for(&tight, Settings::default());
    assert!(
        s.no_fallback
            .as_deref()
            .is_some_and(|w| w.contains("max_memory_gib"))
    );
    let roomy = SdpaOptions::default();
    assert_eq!(
        est.settings_for(&roomy, Settings::default()),
        Settings::default()
    );
    let off = tight.clone().decomposition(Decomposition::Off);
    assert!(matches!(est.check(&off), Err(SdpaError::TooLarge { .. })));
}

#[test]
fn huge_m_and_block_counts_are_checked_against_the_file() {
    let e = parse_err("18446744073709551615\n1\n2\n1.0\n");
    assert!(
        e.to_string().contains("line 1") && e.to_string().contains("limit"),
        "{e}"
    );
    let e = parse_err("18446744073709551616\n1\n2\n1.0\n");
    assert!(e.to_string().contains("line 1"), "{e}");
    // the declared counts are compared with what the file holds
    let e = parse_err("1000000000\n1\n2\n1.0 2.0\n");
    assert!(
        e.to_string()
            .contains("declares m = 1000000000 but the file ends after 2 entries"),
        "{e}"
    );
    let e = parse_err("1\n18446744073709551615\n2 3\n");
    assert!(e.to_string().contains("after 2 block sizes"), "{e}");
    let e = parse_err("1\n3\n2 3\n1.0\n");
    assert!(
        e.to_string().contains("line 4: block size 3 of 3: '1.0'"),
        "{e}"
    );
}

#[test]
fn negative_sizes_are_lp_blocks_and_the_most_negative_is_estimated() {
    let p = SdpaProblem::parse(&one_block("-9223372036854775808")).unwrap();
    let est = p.memory_estimate().unwrap();
    assert_eq!(est.rows, 1 << 63);
    assert_eq!(est.dense_bytes, 0.0);
    assert!(matches!(p.to_problem(), Err(SdpaError::TooLarge { .. })));
    let e = parse_err("1\n1\n-9223372036854775809\n1.0\n");
    assert!(e.to_string().contains("line 3"), "{e}");
}

#[test]
fn an_lp_block_of_100000_is_a_nonnegative_orthant_in_linear_memory() {
    // min x s.t. x − k/n ≥ 0 for k = 1..n: x = 1
    let n = 100_000;
    let mut entries = Vec::with_capacity(2 * n);
    for k in 0..n {
        entries.push((1, 0, k, k, 1.0));
        entries.push((0, 0, k, k, (k + 1) as f64 / n as f64));
    }
    let p = SdpaProblem {
        c: vec![1.0],
        blocks: vec![-(n as i64)],
        entries,
    };
    let est = p.memory_estimate().unwrap();
    assert_eq!((est.rows, est.dense_bytes), (n, 0.0));
    assert!(est.total_gib() < 0.2, "{}", est.total_gib());
    let (prob, x) = p.to_problem().unwrap();
    assert_eq!(prob.num_constraints(), 1);
    let c = prob.compile(&Settings::default()).unwrap();
    assert_eq!(c.num_rows(), n);
    let sol = prob.solve(&Settings::default()).unwrap();
    assert_eq!(sol.status, Status::Solved);
    assert!((sol.value(x[0]).unwrap() - 1.0).abs() < 1e-6);
}

/// The conversion before LP blocks got their own rows: every block as a
/// dense n × n expression, LP blocks through its diagonal.
fn dense_reference(p: &SdpaProblem) -> Problem {
    let mut q = Problem::new();
    let x = q.vector("x", p.m());
    q.minimize(AffExpr::linear(&x, &p.c, 0.0).unwrap());
    for (b, &size) in p.blocks.iter().enumerate() {
        let n = size.unsigned_abs() as usize;
        let mut mat = MatExpr::zeros(n, n);
        for &(mi, _, i, j, v) in p.entries.iter().filter(|e| e.1 == b) {
            let t = if mi == 0 {
                AffExpr::constant(-v)
            } else {
                AffExpr::term(x[mi - 1], v)
            };
            *mat.get_mut(i, j).unwrap() += t.clone();
            if i != j {
                *mat.get_mut(j, i).unwrap() += t;
            }
        }
        if size > 0 {
            q.add_psd(&mat).unwrap();
        } else {
            q.add_nonneg(mat.diagonal()).unwrap();
        }
    }
    q
}

#[test]
fn lp_blocks_compile_to_the_same_rows_as_the_dense_construction() {
    // two PSD and two LP blocks, entries interleaved, repeated terms of one
    // variable in one row: the compiled (A, b, q, cones) are bit-identical
    let text = "3\n4\n{2, -3, 3, -2}\n1 -2 0.5\n\
        0 1 1 1 1.0\n1 2 1 1 1.0\n2 2 1 1 -1.0\n0 2 2 2 0.25\n1 1 1 2 0.3\n\
        3 2 3 3 2.0\n1 3 1 3 0.7\n0 4 2 2 -1.0\n2 4 2 2 1.0\n3 4 1 1 1.0\n\
        2 1 2 2 1.0\n3 3 2 2 1.0\n1 3 3 3 1.0\n0 2 3 3 -0.5\n";
    let p = SdpaProblem::parse(text).unwrap();
    let s = Settings::default();
    let (new, _) = p.to_problem().unwrap();
    let (a, b) = (
        new.compile(&s).unwrap(),
        dense_reference(&p).compile(&s).unwrap(),
    );
    assert_eq!(a.a.colptr, b.a.colptr);
    assert_eq!(a.a.rowval, b.a.rowval);
    assert_eq!(a.a.nzval, b.a.nzval);
    assert_eq!(a.b, b.b);
    assert_eq!(a.q, b.q);
    assert_eq!(format!("{:?}", a.cones), format!("{:?}", b.cones));
    assert_eq!(new.num_constraints(), 4);
}

#[test]
fn lp_block_constraints_are_nonnegative_cones_of_their_size() {
    let p = SdpaProblem::parse("1\n2\n-4 2\n1\n1 1 1 1 1\n1 2 2 2 1\n").unwrap();
    let (prob, _) = p.to_problem().unwrap();
    let c = prob.compile(&Settings::default()).unwrap();
    let cones = format!("{:?}", c.cones);
    assert!(cones.contains("NonnegativeConeT(4)"), "{cones}");
    assert!(cones.contains("PSDTriangleConeT(2)"), "{cones}");
}

#[test]
fn non_finite_numbers_are_errors_with_their_line() {
    for bad in [
        "nan", "NaN", "inf", "-inf", "infinity", "1e400", "-1e400", "1D400",
    ] {
        let e = parse_err(&format!("1\n1\n2\n{bad}\n1 1 1 1 1.0\n"));
        assert!(
            e.to_string().contains("line 4: cost vector entry c1"),
            "{bad}: {e}"
        );
        let e = parse_err(&format!("1\n1\n2\n1.0\n1 1 1 1 1.0\n\n1 1 2 2 {bad}\n"));
        assert!(
            e.to_string().contains("line 7: value") && e.to_string().contains("non-finite"),
            "{bad}: {e}"
        );
    }
    // tiny numbers underflow to 0 (finite) and are kept
    assert!(SdpaProblem::parse("1\n1\n2\n1e-400\n1 1 1 1 1e-400\n").is_ok());
}

#[test]
fn entries_outside_the_declared_sizes_are_errors_with_their_line() {
    let head = "2\n2\n{2, -3}\n1 1\n1 1 1 1 1.0\n";
    let cases = [
        ("3 1 1 1 1.0", "matrix number 3 > m = 2"),
        ("1 0 1 1 1.0", "block number 0 not in 1..=2"),
        ("1 3 1 1 1.0", "block number 3 not in 1..=2"),
        ("1 1 0 1 1.0", "outside block 1 of size 2"),
        ("1 1 1 3 1.0", "outside block 1 of size 2"),
        ("1 2 4 4 1.0", "outside block 2 of size 3"),
        (
            "1 2 1 2 1.0",
            "off-diagonal entry (1, 2) in diagonal block 2",
        ),
        ("-1 1 1 1 1.0", "matrix number: '-1' is not an integer"),
        (
            "1 1 99999999999999999999 1 1.0",
            "row: '99999999999999999999'",
        ),
        ("1 1 1.0 1 1.0", "row: '1.0'"),
        ("1 1 1 1", "found 4 fields"),
    ];
    for (line, want) in cases {
        let e = parse_err(&format!("{head}{line}\n"));
        let msg = e.to_string();
        assert!(
            msg.starts_with("line 6: ") && msg.contains(want),
            "{line}: {msg}"
        );
    }
}

#[test]
fn duplicate_entries_are_errors_naming_both_lines() {
    let e = parse_err("1\n1\n2\n1\n1 1 1 2 1.0\n0 1 1 1 1.0\n1 1 2 1 1.0\n");
    assert!(
        matches!(
            e,
            SdpaError::Duplicate {
                line: 7,
                first_line: 5,
                matrix: 1,
                block: 1,
                row: 1,
                col: 2
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("either triangle"), "{e}");
    // the same position in another matrix is not a duplicate
    assert!(SdpaProblem::parse("1\n1\n2\n1\n1 1 1 2 1.0\n0 1 1 2 1.0\n").is_ok());
}

#[test]
fn problems_built_in_code_are_validated_not_panicked_on() {
    let good = SdpaProblem::parse("1\n1\n2\n1\n1 1 1 1 1\n1 1 2 2 1\n").unwrap();
    let cases: Vec<(SdpaProblem, &str)> = vec![
        (
            SdpaProblem {
                entries: vec![(1, 5, 0, 0, 1.0)],
                ..good.clone()
            },
            "entries[0]: block number 6",
        ),
        (
            SdpaProblem {
                entries: vec![(1, 0, 0, usize::MAX, 1.0)],
                ..good.clone()
            },
            "outside block 1",
        ),
        (
            SdpaProblem {
                entries: vec![(2, 0, 0, 0, 1.0)],
                ..good.clone()
            },
            "matrix number 2 > m = 1",
        ),
        (
            SdpaProblem {
                entries: vec![(1, 0, 0, 0, f64::NAN)],
                ..good.clone()
            },
            "not finite",
        ),
        (
            SdpaProblem {
                entries: vec![(1, 0, 0, 1, 1.0), (1, 0, 1, 0, 1.0)],
                ..good.clone()
            },
            "entries[1]: entry (matrix 1, block 1, 1, 2) repeats entries[0]",
        ),
        (
            SdpaProblem {
                blocks: vec![0],
                ..good.clone()
            },
            "blocks[0]: block size 0",
        ),
        (
            SdpaProblem {
                c: vec![f64::INFINITY],
                ..good.clone()
            },
            "c[0]",
        ),
    ];
    for (p, want) in cases {
        let e = p.to_problem().unwrap_err().to_string();
        assert!(e.contains(want), "{want}: {e}");
    }
    assert!(good.to_problem().is_ok());
}

#[test]
fn options_are_validated() {
    let p = SdpaProblem::parse("1\n1\n2\n1\n1 1 1 1 1\n").unwrap();
    for bad in [f64::NAN, 0.0, -1.0, f64::INFINITY] {
        let o = SdpaOptions::default().max_memory_gib(bad);
        assert!(
            matches!(o.validate(), Err(SdpaError::InvalidOption { .. })),
            "{bad}"
        );
        assert!(p.to_problem_with(&o).is_err());
    }
}

#[test]
fn reading_checks_the_file_size_and_encoding_first() {
    let dir = std::env::temp_dir().join(format!("momentlmi-sdpa-unit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("small.dat-s");
    std::fs::write(&f, one_block("2")).unwrap();
    let tiny = SdpaOptions::default().max_memory_gib(1e-9);
    let e = SdpaProblem::read_with(&f, &tiny).unwrap_err();
    assert!(
        matches!(&e, SdpaError::TooLarge { what, .. } if what.starts_with("reading")),
        "{e}"
    );
    assert!(SdpaProblem::read(&f).is_ok());
    std::fs::write(&f, b"1\n1\n2\n1.0\n1 1 1 1 \xff\n").unwrap();
    let e = SdpaProblem::read(&f).unwrap_err();
    assert!(matches!(e, SdpaError::Encoding { line: 5, .. }), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_memory_estimate_follows_its_formula() {
    // one PSD block of side 10 (t = 55) touched by 2 variables, an LP block of 7
    let p = SdpaProblem::parse("2\n2\n10 -7\n1 1\n1 1 1 1 1\n2 1 2 3 1\n0 1 4 4 1\n1 2 7 7 1\n")
        .unwrap();
    let est = p.memory_estimate().unwrap();
    let t = 55.0f64;
    let dense = BYTES_PER_DENSE * t * t + 16.0 * (2.0 * t * 2.0 + 4.0) + 64.0 * 100.0;
    assert_eq!(est.dense_bytes, dense);
    assert_eq!(est.rows, 62);
    let linear = BYTES_FIXED
        + BYTES_PER_ROW * 62.0
        + BYTES_PER_VARIABLE * 2.0
        + BYTES_PER_ENTRY * 4.0
        + 2048.0;
    assert_eq!(est.linear_bytes, linear);
    assert_eq!(est.largest_psd_side, 10);
}

#[test]
fn values_whose_arithmetic_overflows_name_their_block() {
    // F(x)'s off-diagonal is averaged over both triangles: 1.7e308 + 1.7e308 = ∞
    let p = SdpaProblem::parse("1\n2\n-1 2\n1\n1 1 1 1 1\n1 2 1 2 1.7e308\n").unwrap();
    let e = p.to_problem().unwrap_err();
    assert!(matches!(e, SdpaError::Block { block: 2, .. }), "{e}");
    assert!(e.to_string().starts_with("block 2: non-finite"), "{e}");
}
