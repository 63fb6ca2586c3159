//! Conversion between SDPA problems and [`conic`](crate::conic) problems.
//!
//! An SDPA problem `min cᵀx s.t. F(x) = Σ xᵢ Fᵢ − F₀ ⪰ 0` becomes one conic
//! constraint per block: a dense block of side n the PSD cone on the
//! n(n+1)/2 rows of F(x)'s block, a diagonal (LP) block of size n the
//! non-negative orthant on its n diagonal rows (O(n), never an n × n matrix).

use super::error::SdpaError;
use super::memory::MemoryEstimate;
use super::options::SdpaOptions;
use super::problem::SdpaProblem;
use crate::conic::{
    AffExpr, ConeKind, ConicError, ConstraintData, ConstraintId, MatExpr, Problem, Sense, Settings,
    Solution, Var,
};

type Entry = (usize, usize, usize, usize, f64);

/// Fₖ's coefficient as a term of F(x) = Σ xᵢ Fᵢ − F₀.
fn term(x: &[Var], mat: usize, v: f64) -> AffExpr {
    if mat == 0 {
        AffExpr::constant(-v)
    } else {
        AffExpr::term(x[mat - 1], v)
    }
}

/// `F(x)`'s dense block of side n ⪰ 0.
fn psd_block(
    p: &mut Problem,
    x: &[Var],
    n: usize,
    entries: &[&Entry],
) -> Result<ConstraintId, SdpaError> {
    let mut mat = MatExpr::zeros(n, n);
    for &&(mi, _, i, j, v) in entries {
        let t = term(x, mi, v);
        *mat.get_mut(i, j)? += t.clone();
        if i != j {
            *mat.get_mut(j, i)? += t;
        }
    }
    Ok(p.add_psd(mat)?)
}

/// `F(x)`'s diagonal block of size n ≥ 0, entry by entry.
fn lp_block(
    p: &mut Problem,
    x: &[Var],
    n: usize,
    entries: &[&Entry],
) -> Result<ConstraintId, SdpaError> {
    let mut rows = vec![AffExpr::zero(); n];
    for &&(mi, _, i, _, v) in entries {
        let row = rows.get_mut(i).ok_or_else(|| ConicError::IndexOutOfRange {
            what: format!("diagonal entry {i}"),
            shape: format!("{n}"),
        })?;
        *row += term(x, mi, v);
    }
    Ok(p.add_nonneg(rows)?)
}

impl SdpaProblem {
    /// The conic problem and its variables x₁..x_m, with the default
    /// [`SdpaOptions`] (a memory limit of 8 GiB).
    pub fn to_problem(&self) -> Result<(Problem, Vec<Var>), SdpaError> {
        self.to_problem_with(&SdpaOptions::default())
    }

    /// The conic problem and its variables x₁..x_m. First validates
    /// ([`SdpaProblem::validate`]) the problem and checks its
    /// [`memory_estimate`](SdpaProblem::memory_estimate) against
    /// `opts`' limit ([`SdpaError::TooLarge`] with the numbers), so
    /// nothing is allocated for a problem that would not fit.
    ///
    /// The check is of the total `opts`' decomposition will need (the
    /// decomposed one by default): solve the problem with
    /// [`MemoryEstimate::settings_for`]'s settings, or call
    /// [`solve_with`](Self::solve_with), so that a verified decomposition does
    /// not fall back to an undecomposed solve beyond the limit.
    pub fn to_problem_with(&self, opts: &SdpaOptions) -> Result<(Problem, Vec<Var>), SdpaError> {
        self.checked(opts)?;
        self.build()
    }

    /// Validates `opts` and the problem and checks the memory estimate
    /// against `opts`' limit; the estimate.
    fn checked(&self, opts: &SdpaOptions) -> Result<MemoryEstimate, SdpaError> {
        opts.validate()?;
        self.validate()?;
        let est = self.memory_estimate()?;
        est.check(opts)?;
        Ok(est)
    }

    /// Validates, estimates the memory once and checks it against `opts`'
    /// limit, builds the problem and solves it with `settings` as
    /// [`MemoryEstimate::settings_for`] adapts them (`opts`' decomposition,
    /// and no fall-back beyond the limit). The solution's `x()` is x₁..x_m.
    pub fn solve_with(
        &self,
        opts: &SdpaOptions,
        settings: Settings,
    ) -> Result<(Solution, MemoryEstimate), SdpaError> {
        let est = self.checked(opts)?;
        let (p, _) = self.build()?;
        let sol = p.solve(&est.settings_for(opts, settings))?;
        Ok((sol, est))
    }

    /// The conic problem of a validated problem whose memory was checked.
    fn build(&self) -> Result<(Problem, Vec<Var>), SdpaError> {
        let mut p = Problem::new();
        let x = p.vector("x", self.m());
        p.minimize(AffExpr::linear(&x, &self.c, 0.0)?);
        let mut per_block: Vec<Vec<&Entry>> = vec![Vec::new(); self.blocks.len()];
        for e in &self.entries {
            per_block[e.1].push(e);
        }
        for (b, (&size, entries)) in self.blocks.iter().zip(&per_block).enumerate() {
            let n = usize::try_from(size.unsigned_abs()).map_err(|_| SdpaError::Limit {
                what: format!("block {} size", b + 1),
                value: size.to_string(),
                reason: "does not fit this machine's indices".into(),
            })?;
            let id = if size > 0 {
                psd_block(&mut p, &x, n, entries)
            } else {
                lp_block(&mut p, &x, n, entries)
            }
            .map_err(|e| match e {
                SdpaError::Conic(source) => SdpaError::Block {
                    block: b + 1,
                    source,
                },
                e => e,
            })?;
            p.set_name(id, &format!("block {}", b + 1))?;
        }
        Ok((p, x))
    }

    /// Writes a conic problem in SDPA form. Nonnegative rows become diagonal
    /// blocks, equalities pairs of opposite rows, second-order cones the arrow
    /// LMI `[[t, uᵀ], [u, tI]] ⪰ 0`, PSD constraints dense blocks. Least-squares
    /// terms, objective constants and exponential cones have no SDPA form and
    /// are rejected.
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
        let mut out = Self {
            c,
            blocks: vec![],
            entries: vec![],
        };
        for con in &p.constraints {
            out.add_constraint(con)?;
        }
        Ok(out)
    }

    /// One constraint as a block of F(x) (none for an empty one).
    fn add_constraint(&mut self, con: &ConstraintData) -> Result<(), SdpaError> {
        let blk = self.blocks.len();
        let k = con.rows.len();
        let entries = &mut self.entries;
        // entry (i, j) of this block = expression e: Fᵢ gets the
        // coefficients, F₀ the negated constant
        let mut put = |i: usize, j: usize, e: &AffExpr| {
            for (v, a) in e.coefficients() {
                entries.push((v.index() + 1, blk, i, j, a));
            }
            if e.constant_term() != 0.0 {
                entries.push((0, blk, i, j, -e.constant_term()));
            }
        };
        let size = match con.kind {
            ConeKind::Nonnegative => {
                for (r, e) in con.rows.iter().enumerate() {
                    put(r, r, e);
                }
                -(k as i64)
            }
            ConeKind::Zero => {
                for (r, e) in con.rows.iter().enumerate() {
                    put(2 * r, 2 * r, e);
                    put(2 * r + 1, 2 * r + 1, &(e * -1.0));
                }
                -2 * k as i64
            }
            ConeKind::SecondOrder => {
                for r in 0..k {
                    put(r, r, &con.rows[0]);
                }
                for r in 1..k {
                    put(0, r, &con.rows[r]);
                }
                k as i64
            }
            ConeKind::Exponential => {
                return Err(ConicError::Unsupported(format!(
                    "{}: an exponential cone has no SDPA form",
                    con.name
                ))
                .into());
            }
            ConeKind::Psd { n } => {
                let s2 = std::f64::consts::SQRT_2;
                for j in 0..n {
                    for i in 0..=j {
                        let e = &con.rows[j * (j + 1) / 2 + i];
                        if i == j {
                            put(i, j, e)
                        } else {
                            put(i, j, &(e * (1.0 / s2)))
                        }
                    }
                }
                n as i64
            }
        };
        if k > 0 {
            self.blocks.push(size);
        }
        Ok(())
    }
}
