//! The SDPA data structure, its text format and its conic form.

use super::error::SdpaError;
use crate::conic::{AffExpr, ConeKind, ConicError, MatExpr, Problem, Sense, Var};
use std::fmt::Write as _;
use std::path::Path;

/// An SDPA problem: `min cᵀx s.t. Σ xᵢ Fᵢ − F₀ ⪰ 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct SdpaProblem {
    /// Cost vector c (length m).
    pub c: Vec<f64>,
    /// Block sizes: `n > 0` a dense `n × n` block, `n < 0` a diagonal block of size `|n|`.
    pub blocks: Vec<i64>,
    /// Entries `(matrix 0..=m, block 0-based, i, j, value)`, 0-based `i ≤ j`.
    pub entries: Vec<(usize, usize, usize, usize, f64)>,
}

/// Tokeniser that keeps line numbers and treats `,{}()` as blanks.
struct Tokens<'a> {
    lines: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'a>>>,
}

impl<'a> Tokens<'a> {
    fn clean(s: &str) -> String {
        s.chars()
            .map(|c| if ",{}()".contains(c) { ' ' } else { c })
            .collect()
    }

    /// The next non-empty line's tokens with its 1-based number.
    fn next_line(&mut self) -> Option<(usize, Vec<String>)> {
        for (i, l) in self.lines.by_ref() {
            let toks: Vec<String> = Self::clean(l)
                .split_whitespace()
                .map(str::to_string)
                .collect();
            if !toks.is_empty() {
                return Some((i + 1, toks));
            }
        }
        None
    }
}

fn num<T: std::str::FromStr>(tok: &str, line: usize, what: &str) -> Result<T, SdpaError> {
    tok.parse::<T>().map_err(|_| SdpaError::Parse {
        line,
        message: format!("{what}: cannot read '{tok}' as a number"),
    })
}

fn parse_f64(tok: &str, line: usize, what: &str) -> Result<f64, SdpaError> {
    // Fortran-style exponents (1.0D+00) appear in some files.
    let v: f64 = num(&tok.replace(['D', 'd'], "e"), line, what)?;
    if !v.is_finite() {
        return Err(SdpaError::Parse {
            line,
            message: format!("{what}: non-finite value '{tok}'"),
        });
    }
    Ok(v)
}

impl SdpaProblem {
    /// Number of variables m.
    pub fn m(&self) -> usize {
        self.c.len()
    }

    /// Reads a file.
    pub fn read(path: &Path) -> Result<Self, SdpaError> {
        let text = std::fs::read_to_string(path).map_err(|e| SdpaError::Io {
            path: path.to_path_buf(),
            source: e,
        })?;
        Self::parse(&text)
    }

    /// Parses SDPA sparse text.
    pub fn parse(text: &str) -> Result<Self, SdpaError> {
        let mut t = Tokens {
            lines: text.lines().enumerate().peekable(),
        };
        // skip leading comments
        while let Some((_, l)) = t.lines.peek() {
            let s = l.trim_start();
            if s.starts_with('"') || s.starts_with('*') || s.is_empty() {
                t.lines.next();
            } else {
                break;
            }
        }
        let eof = |w: &str| SdpaError::UnexpectedEof(format!("expected {w}"));
        let (line, toks) = t
            .next_line()
            .ok_or_else(|| eof("the number of constraint matrices m"))?;
        let m: usize = num(&toks[0], line, "m")?;
        let (line, toks) = t.next_line().ok_or_else(|| eof("the number of blocks"))?;
        let nb: usize = num(&toks[0], line, "number of blocks")?;
        let mut blocks = Vec::with_capacity(nb);
        while blocks.len() < nb {
            let (line, toks) = t.next_line().ok_or_else(|| eof("the block sizes"))?;
            for tok in toks {
                if blocks.len() == nb {
                    break;
                }
                let b: i64 = num(&tok, line, "block size")?;
                if b == 0 {
                    return Err(SdpaError::Parse {
                        line,
                        message: "block size 0".into(),
                    });
                }
                blocks.push(b);
            }
        }
        let mut c = Vec::with_capacity(m);
        while c.len() < m {
            let (line, toks) = t.next_line().ok_or_else(|| eof("the cost vector c"))?;
            for tok in toks {
                if c.len() == m {
                    return Err(SdpaError::Parse {
                        line,
                        message: format!("more than m = {m} entries in c"),
                    });
                }
                c.push(parse_f64(&tok, line, "cost vector entry")?);
            }
        }
        let mut entries = Vec::new();
        while let Some((line, toks)) = t.next_line() {
            if toks.len() < 5 {
                return Err(SdpaError::Parse {
                    line,
                    message: format!(
                        "expected 'matno blkno i j value', found {} fields",
                        toks.len()
                    ),
                });
            }
            let mat: usize = num(&toks[0], line, "matrix number")?;
            let blk: usize = num(&toks[1], line, "block number")?;
            let i: usize = num(&toks[2], line, "row")?;
            let j: usize = num(&toks[3], line, "column")?;
            let v = parse_f64(&toks[4], line, "value")?;
            if mat > m {
                return Err(SdpaError::Parse {
                    line,
                    message: format!("matrix number {mat} > m = {m}"),
                });
            }
            if blk == 0 || blk > nb {
                return Err(SdpaError::Parse {
                    line,
                    message: format!("block number {blk} not in 1..={nb}"),
                });
            }
            let size = blocks[blk - 1].unsigned_abs() as usize;
            if i == 0 || j == 0 || i > size || j > size {
                return Err(SdpaError::Parse {
                    line,
                    message: format!("entry ({i}, {j}) outside block {blk} of size {size}"),
                });
            }
            if blocks[blk - 1] < 0 && i != j {
                return Err(SdpaError::Parse {
                    line,
                    message: format!("off-diagonal entry ({i}, {j}) in diagonal block {blk}"),
                });
            }
            let (i, j) = if i <= j { (i, j) } else { (j, i) };
            entries.push((mat, blk - 1, i - 1, j - 1, v));
        }
        Ok(Self { c, blocks, entries })
    }

    /// The SDPA sparse text.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "\"written by momentlmi");
        let _ = writeln!(s, "{}", self.m());
        let _ = writeln!(s, "{}", self.blocks.len());
        let _ = writeln!(
            s,
            "{}",
            self.blocks
                .iter()
                .map(|b| b.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        );
        let _ = writeln!(
            s,
            "{}",
            self.c
                .iter()
                .map(|v| format!("{v:e}"))
                .collect::<Vec<_>>()
                .join(" ")
        );
        for &(mat, blk, i, j, v) in &self.entries {
            let _ = writeln!(s, "{} {} {} {} {:e}", mat, blk + 1, i + 1, j + 1, v);
        }
        s
    }

    /// Writes the file whole (to a temporary beside it, then renamed).
    pub fn write(&self, path: &Path) -> Result<(), SdpaError> {
        let io = |e| SdpaError::Io {
            path: path.to_path_buf(),
            source: e,
        };
        let tmp = path.with_extension("dat-s.tmp");
        std::fs::write(&tmp, self.to_text()).map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    }

    /// The conic problem and its variables x₁..x_m.
    pub fn to_problem(&self) -> Result<(Problem, Vec<Var>), SdpaError> {
        let mut p = Problem::new();
        let x = p.vector("x", self.m());
        p.minimize(AffExpr::linear(&x, &self.c, 0.0)?);
        let mut per_block: Vec<Vec<usize>> = vec![Vec::new(); self.blocks.len()];
        for (k, e) in self.entries.iter().enumerate() {
            per_block[e.1].push(k);
        }
        for (b, &size) in self.blocks.iter().enumerate() {
            let n = size.unsigned_abs() as usize;
            // F(x) = Σ xᵢ Fᵢ − F₀
            let mut mat = MatExpr::zeros(n, n);
            for &k in &per_block[b] {
                let (mi, _, i, j, v) = self.entries[k];
                let term = if mi == 0 {
                    AffExpr::constant(-v)
                } else {
                    AffExpr::term(x[mi - 1], v)
                };
                *mat.get_mut(i, j)? += term.clone();
                if i != j {
                    *mat.get_mut(j, i)? += term;
                }
            }
            let id = if size > 0 {
                p.add_psd(&mat)?
            } else {
                p.add_nonneg(
                    (0..n)
                        .map(|i| mat.get(i, i).cloned())
                        .collect::<Result<Vec<_>, _>>()?,
                )?
            };
            p.set_name(id, &format!("block {}", b + 1))?;
        }
        Ok((p, x))
    }

    /// Writes a conic problem in SDPA form. Nonnegative rows become diagonal
    /// blocks, equalities pairs of opposite rows, second-order cones the arrow
    /// LMI `[[t, uᵀ], [u, tI]] ⪰ 0`, PSD constraints dense blocks. Least-squares
    /// terms and objective constants have no SDPA form and are rejected.
    pub fn from_problem(p: &Problem) -> Result<Self, SdpaError> {
        if !p.squares.is_empty() {
            return Err(
                ConicError::Unsupported("least-squares terms in SDPA output".into()).into(),
            );
        }
        if p.linear.constant_term() != 0.0 {
            return Err(
                ConicError::Unsupported("an objective constant in SDPA output".into()).into(),
            );
        }
        let sign = if p.sense == Sense::Maximize {
            -1.0
        } else {
            1.0
        };
        let mut c = vec![0.0; p.num_vars()];
        for (v, a) in p.linear.coefficients() {
            c[v.index()] += sign * a;
        }
        let mut blocks = Vec::new();
        let mut entries = Vec::new();
        // entry (i, j) of the current block = expression e: Fᵢ gets the
        // coefficients, F₀ the negated constant.
        let mut put = |blk: usize, i: usize, j: usize, e: &AffExpr| {
            for (v, a) in e.coefficients() {
                entries.push((v.index() + 1, blk, i, j, a));
            }
            if e.constant_term() != 0.0 {
                entries.push((0, blk, i, j, -e.constant_term()));
            }
        };
        let s2 = std::f64::consts::SQRT_2;
        for con in &p.constraints {
            let blk = blocks.len();
            let k = con.rows.len();
            match con.kind {
                ConeKind::Nonnegative => {
                    blocks.push(-(k as i64));
                    for (r, e) in con.rows.iter().enumerate() {
                        put(blk, r, r, e);
                    }
                }
                ConeKind::Zero => {
                    blocks.push(-2 * k as i64);
                    for (r, e) in con.rows.iter().enumerate() {
                        put(blk, 2 * r, 2 * r, e);
                        put(blk, 2 * r + 1, 2 * r + 1, &(e * -1.0));
                    }
                }
                ConeKind::SecondOrder => {
                    blocks.push(k as i64);
                    for r in 0..k {
                        put(blk, r, r, &con.rows[0]);
                    }
                    for r in 1..k {
                        put(blk, 0, r, &con.rows[r]);
                    }
                }
                ConeKind::Psd { n } => {
                    blocks.push(n as i64);
                    for j in 0..n {
                        for i in 0..=j {
                            let e = &con.rows[j * (j + 1) / 2 + i];
                            if i == j {
                                put(blk, i, j, e)
                            } else {
                                put(blk, i, j, &(e * (1.0 / s2)))
                            }
                        }
                    }
                }
            }
            if k == 0 {
                blocks.pop();
            }
        }
        Ok(Self { c, blocks, entries })
    }
}
