//! Fuzz-style properties of the SDPA reader: on random text and on valid
//! files mutated token by token (huge, negative, non-finite and malformed
//! numbers), lines deleted, duplicated or truncated, reading never panics —
//! it returns a problem or a named error — and so do validation, the memory
//! estimate and the conversion under a small limit. Only problems whose
//! declared size is tiny are solved.

use momentlmi::conic::Settings;
use momentlmi::sdpa::{SdpaOptions, SdpaProblem};
use proptest::prelude::*;

/// Two PSD blocks and an LP block, every kind of entry.
const VALID: &str = "\"a comment\n* another\n3 =mdim\n3 =nblocks\n{2, -2, 3}\n1.0 1.0 0.5\n\
0 1 1 2 -1.0\n1 1 1 1 1.0\n2 1 2 2 1.0\n1 2 1 1 1.0\n0 2 1 1 0.5\n2 2 2 2 1.0\n\
3 3 1 3 0.25\n1 3 2 2 1.0\n0 3 3 3 -1.0\n2 3 1 1 1.0\n3 3 3 3 1.0\n";

/// Tokens a hostile file might hold where a number is expected.
const HOSTILE: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "4",
    "-3",
    "1.5",
    "4294967295",
    "4294967296",
    "4611686018427387904",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "1000000",
    "-1000000",
    "1e400",
    "-1e400",
    "1e300",
    "-1e300",
    "1.7e308",
    "-1.7e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "1D3",
    "x",
    "{",
    "}",
    "\"",
    "*",
    "",
];

#[derive(Clone, Debug)]
enum Mutation {
    /// Replace token `tok` of line `line` (both taken modulo the sizes).
    Replace {
        line: usize,
        tok: usize,
        with: usize,
    },
    DeleteLine(usize),
    DuplicateLine(usize),
    /// Keep only the first `n` bytes (modulo the length).
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), any::<usize>(), 0..HOSTILE.len())
            .prop_map(|(line, tok, with)| Mutation::Replace { line, tok, with }),
        1 => any::<usize>().prop_map(Mutation::DeleteLine),
        1 => any::<usize>().prop_map(Mutation::DuplicateLine),
        1 => any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn apply(text: &str, muts: &[Mutation]) -> String {
    let mut lines: Vec<Vec<String>> = text
        .lines()
        .map(|l| l.split(' ').map(str::to_string).collect())
        .collect();
    let mut cut = None;
    for m in muts {
        if lines.is_empty() {
            break;
        }
        let n = lines.len();
        match *m {
            Mutation::Replace { line, tok, with } => {
                let l = &mut lines[line % n];
                let k = tok % l.len();
                l[k] = HOSTILE[with].to_string();
            }
            Mutation::DeleteLine(k) => {
                lines.remove(k % n);
            }
            Mutation::DuplicateLine(k) => {
                let l = lines[k % n].clone();
                lines.insert(k % n, l);
            }
            Mutation::Truncate(k) => cut = Some(k),
        }
    }
    let mut s: String = lines.iter().map(|l| l.join(" ") + "\n").collect();
    if let Some(k) = cut {
        let mut k = k % (s.len() + 1);
        while !s.is_char_boundary(k) {
            k -= 1;
        }
        s.truncate(k);
    }
    s
}

/// Read, validate, estimate and convert under a 50 MiB limit; solve only
/// tiny problems. Returns whether the text parsed.
fn exercise(text: &str) -> bool {
    let Ok(p) = SdpaProblem::parse(text) else {
        return false;
    };
    let _ = p.validate();
    let Ok(est) = p.memory_estimate() else {
        return true;
    };
    let opts = SdpaOptions::default().max_memory_gib(0.05);
    if let Ok((prob, _)) = p.to_problem_with(&opts) {
        if est.rows <= 40 && p.m() <= 10 {
            let _ = prob.solve(&Settings::default().max_iter(50));
        }
    }
    // the text written back reads again
    assert!(SdpaProblem::parse(&p.to_text()).is_ok());
    true
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn mutated_valid_files_never_panic(muts in prop::collection::vec(mutation(), 1..5)) {
        exercise(&apply(VALID, &muts));
    }

    #[test]
    fn random_token_soup_never_panics(
        toks in prop::collection::vec((0..HOSTILE.len(), 0..4u8), 0..60)
    ) {
        let mut s = String::new();
        for (t, sep) in toks {
            s += HOSTILE[t];
            s += [" ", "\n", ",", "\t"][sep as usize];
        }
        exercise(&s);
    }

    #[test]
    fn random_text_never_panics(s in "\\PC{0,300}") {
        exercise(&s);
    }
}

#[test]
fn the_valid_base_parses_and_solves() {
    assert!(exercise(VALID));
    let p = SdpaProblem::parse(VALID).unwrap();
    assert_eq!(p.blocks, vec![2, -2, 3]);
    let (prob, _) = p.to_problem().unwrap();
    assert!(prob.solve(&Settings::default()).unwrap().status.is_solved());
}

#[test]
fn every_single_token_replacement_is_read_or_rejected() {
    // exhaustive: each token of VALID replaced by each hostile token
    let (mut parsed, mut rejected) = (0, 0);
    let lines: Vec<&str> = VALID.lines().collect();
    for (li, l) in lines.iter().enumerate() {
        for tok in 0..l.split(' ').count() {
            for with in 0..HOSTILE.len() {
                let m = Mutation::Replace {
                    line: li,
                    tok,
                    with,
                };
                if exercise(&apply(VALID, &[m])) {
                    parsed += 1;
                } else {
                    rejected += 1;
                }
            }
        }
    }
    assert!(
        parsed > 100 && rejected > 100,
        "{parsed} parsed, {rejected} rejected"
    );
}
