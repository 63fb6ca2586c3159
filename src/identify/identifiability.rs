//! What the data can tell: the numerical rank of the reduced regressor, its
//! base parameters (named combinations), its condition number, the
//! parameters that do not enter the data, and the standard deviations of
//! the identified base parameters.
//!
//! With `R` (r × p) the reduced regressor ([`super::Reduced::r_d`]) and `S`
//! the diagonal of its inverse column norms, everything is read off the
//! column-scaled `R S` (units drop out):
//! - the **rank** is the number of singular values of `R S` above
//!   [`RANK_TOL`] × the largest (the reduced factor already dropped
//!   directions below `√((p + 1) ε)` of a unit column);
//! - the **condition number** is the largest over the smallest of those;
//! - the **base parameters**: `rank` independent columns `b` picked greedily,
//!   each the column farthest from the span of those already picked (a
//!   column-pivoted QR's choice), columns within [`TIE_TOL`] of the farthest
//!   counted as tied and the first in θ's order taken, so that rounding (the
//!   order a reduction added its samples in) does not choose; every other
//!   column `d` is a combination of them (`R_d = R_b K`, the QR `R S [b d] =
//!   Q [R₁ R₂]`, `K = S_b R₁⁻¹ R₂ S_d⁻¹`), so the data see θ only through
//!   `β = θ_b + K θ_d` (Gautier's base parameters), listed in θ's order;
//! - **unidentifiable**: the parameters whose column is zero
//!   (norm ≤ [`ZERO_COLUMN_TOL`] × the largest: a column at rounding level
//!   counts as zero, not scaled up), which enter no torque; the rank and
//!   the base are taken on the other columns;
//! - **directions**: a basis of the null space: each zero column alone,
//!   then per dependent column `d` (θ's order) the direction `e_d − K e_b`
//!   (in the scaled columns, unit length) that the base leaves unseen, each
//!   named by its largest components;
//! - the base parameters' **standard deviations**: `σ̂² (R_bᵀ R_b)⁻¹` with
//!   `σ̂² = ‖R θ − d‖² / (rows − rank)`, the unconstrained least-squares
//!   covariance (active constraints narrow it further).

use super::error::IdentifyError;
use faer::Mat;
use serde::Serialize;

/// Singular values of the column-scaled reduced regressor above this
/// fraction of the largest count toward the rank.
pub const RANK_TOL: f64 = 1e-8;

/// A column whose norm is at most this fraction of the largest column's
/// enters no torque: its parameter is unidentifiable.
pub const ZERO_COLUMN_TOL: f64 = 1e-10;

/// A dependent column's coefficient (in the scaled columns) below this is
/// left out of a base parameter's combination.
const TERM_TOL: f64 = 1e-6;

/// Columns whose distance from the span of the base columns already picked
/// is within this fraction of the farthest one's are tied: the first in θ's
/// order is picked. Wide enough that two reductions of the same data (their
/// sums added in another order) pick the same columns; narrow enough that a
/// picked column is as well determined as the farthest, to 1e-3.
pub const TIE_TOL: f64 = 1e-3;

/// One base parameter: an identified column plus the dependent ones it
/// stands for.
#[derive(Clone, Debug, Serialize)]
pub struct BaseParameter {
    /// The combination, e.g. `link2.hx + 0.3·link3.m` (coefficients in SI
    /// units: the dependent parameter's unit over the column's).
    pub combination: String,
    /// Its value at the identified θ.
    pub value: f64,
    /// Its standard deviation (same unit); `None` without residual degrees
    /// of freedom.
    pub std_dev: Option<f64>,
}

/// The identifiability report.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Identifiability {
    /// Numerical rank of the reduced regressor (all columns: links, rotors,
    /// friction).
    pub rank: usize,
    /// Its number of columns.
    pub columns: usize,
    /// The most any data could identify: the rank of the regressor on
    /// random states ([`structural_rank`]); `None` with a load friction
    /// term (its column needs torques).
    pub structural_rank: Option<usize>,
    /// Condition number of the base columns (scaled to unit norm).
    pub condition_number: f64,
    /// The rank tolerance ([`RANK_TOL`]).
    pub rank_tolerance: f64,
    /// The base parameters, in θ's order of their base columns (canonical:
    /// the same for any reduction of the same data, see [`TIE_TOL`]).
    pub base_parameters: Vec<BaseParameter>,
    /// Parameters that enter no torque of the data.
    pub unidentifiable: Vec<String>,
    /// The parameter directions the data do not excite (p − rank of them),
    /// each named by its largest components: each zero column's, then each
    /// dependent column's unseen combination; set by the prior and the
    /// constraints.
    pub directions: Vec<String>,
    /// The base columns (indices into θ), ascending.
    #[serde(skip)]
    pub base_columns: Vec<usize>,
    /// `K` (rank × p): base parameter k is `Σ_j K[k][j] θ_j`.
    #[serde(skip)]
    pub combinations: Vec<Vec<f64>>,
    /// An orthonormal basis of the null space of the column-scaled
    /// regressor (p − rank vectors of p).
    #[serde(skip)]
    pub null_space: Vec<Vec<f64>>,
}

/// Column norms of `r`.
fn column_norms(r: &Mat<f64>) -> Vec<f64> {
    (0..r.ncols())
        .map(|j| {
            (0..r.nrows())
                .map(|i| r[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect()
}

/// `r` with unit columns (zero columns stay zero), padded with zero rows
/// to at least p rows.
fn scaled(r: &Mat<f64>, norms: &[f64]) -> Mat<f64> {
    let p = r.ncols();
    Mat::from_fn(r.nrows().max(p), p, |i, j| {
        if i < r.nrows() && norms[j] > 0.0 {
            r[(i, j)] / norms[j]
        } else {
            0.0
        }
    })
}

impl Identifiability {
    /// The structure of the reduced regressor `r` (r × p) whose columns are
    /// the parameters `names` (p of them).
    pub fn of(r: &Mat<f64>, names: &[String]) -> Result<Self, IdentifyError> {
        let p = r.ncols();
        if names.len() != p {
            return Err(IdentifyError::Columns {
                expected: p,
                found: names.len(),
            });
        }
        let norms = column_norms(r);
        let nmax = norms.iter().cloned().fold(0.0, f64::max);
        // a column at rounding level is no column: scaled up it would count
        let live: Vec<usize> = (0..p)
            .filter(|&j| norms[j] > ZERO_COLUMN_TOL * nmax)
            .collect();
        let norms_live: Vec<f64> = (0..p)
            .map(|j| if live.contains(&j) { norms[j] } else { 0.0 })
            .collect();
        let rs = scaled(r, &norms_live);
        let rl = Mat::from_fn(rs.nrows().max(live.len()), live.len(), |i, c| {
            if i < rs.nrows() {
                rs[(i, live[c])]
            } else {
                0.0
            }
        });
        let svd = rl.svd().map_err(|_| IdentifyError::Factorisation {
            what: "SVD of the reduced regressor (identifiability)",
        })?;
        let s = svd.S().column_vector();
        let s: Vec<f64> = (0..s.nrows()).map(|i| s[i]).collect();
        let smax = s.iter().cloned().fold(0.0, f64::max);
        let tol = RANK_TOL * smax.max(f64::MIN_POSITIVE);
        let rank = s.iter().filter(|&&v| v > tol).count();
        let smin = (s.iter().cloned())
            .filter(|&v| v > tol)
            .fold(f64::INFINITY, f64::min);
        let null_space = null_space(svd.V(), &live, p, rank);
        let base = base_columns(&rs, &norms_live, rank)?;
        let (base_columns, combinations) = (base.columns, base.combinations);
        // the unseen directions: each dead column alone, then the base's own
        let dead = p - live.len();
        let directions = (null_space[..dead].iter())
            .chain(&base.unseen)
            .map(|x| direction_name(x, names))
            .collect();
        let unidentifiable = ((0..p).filter(|j| !live.contains(j)))
            .map(|j| names[j].clone())
            .collect();
        let base_parameters = (base_columns.iter().zip(&combinations))
            .map(|(&b, k)| BaseParameter {
                combination: combination_name(b, k, names),
                value: f64::NAN,
                std_dev: None,
            })
            .collect();
        Ok(Self {
            rank,
            columns: p,
            structural_rank: None,
            condition_number: if rank > 0 { smax / smin } else { f64::INFINITY },
            rank_tolerance: RANK_TOL,
            base_parameters,
            unidentifiable,
            directions,
            base_columns,
            combinations,
            null_space,
        })
    }

    /// Whether parameter `k` is determined by the data alone (its unit
    /// vector is orthogonal to the null space, to 1e-6).
    pub fn determined_alone(&self, k: usize) -> bool {
        self.null_space.iter().map(|n| n[k] * n[k]).sum::<f64>() < 1e-12
    }

    /// The base parameters' values at θ and their standard deviations from
    /// the residual `‖r θ − d‖²` over `rows` rows of data (samples × joints).
    pub fn estimate(
        &mut self,
        r: &Mat<f64>,
        d: &[f64],
        theta: &[f64],
        rows: usize,
    ) -> Result<(), IdentifyError> {
        let rss = rss(r, d, theta);
        let dof = rows.saturating_sub(self.rank);
        let variances = base_variances(r, &self.base_columns)?;
        for (bp, (k, var)) in
            (self.base_parameters.iter_mut()).zip(self.combinations.iter().zip(variances))
        {
            bp.value = k.iter().zip(theta).map(|(a, b)| a * b).sum();
            bp.std_dev = (dof > 0).then(|| (rss / dof as f64 * var).sqrt());
        }
        Ok(())
    }

    /// The one-line summary: rank, condition number, the parameters that
    /// enter no torque.
    pub fn summary(&self) -> String {
        let most = (self.structural_rank).map_or_else(String::new, |m| {
            format!(", of the {m} any data could identify")
        });
        let mut s = format!(
            "{} of {} parameter directions identified by the data{most} (condition number {:.3e})",
            self.rank, self.columns, self.condition_number
        );
        if self.rank < self.columns {
            s += &format!(
                "; {} set by the prior and the constraints",
                self.columns - self.rank
            );
        }
        if !self.unidentifiable.is_empty() {
            s += &format!(
                "; {} parameters enter no torque ({})",
                self.unidentifiable.len(),
                abbreviated(&self.unidentifiable, 6)
            );
        }
        s
    }
}

/// An orthonormal basis of the null space of the column-scaled regressor
/// (`p` columns, those in `live` not zero, of rank `rank`; `v` the right
/// singular vectors of the live columns): each dead column alone, then the
/// live columns' own.
fn null_space(v: faer::MatRef<'_, f64>, live: &[usize], p: usize, rank: usize) -> Vec<Vec<f64>> {
    ((0..p).filter(|j| !live.contains(j)))
        .map(|j| (0..p).map(|k| if k == j { 1.0 } else { 0.0 }).collect())
        .chain((rank..live.len()).map(|k| {
            let mut x = vec![0.0; p];
            for (c, &j) in live.iter().enumerate() {
                x[j] = v[(c, k)];
            }
            x
        }))
        .collect()
}

/// The rank of `model`'s regressor on 400 random states
/// ([`on_random_states`]): the most any data could identify; `None` with a
/// load friction term (its column needs torques).
pub fn structural_rank(model: &crate::dynamics::Model) -> Result<Option<usize>, IdentifyError> {
    use crate::dynamics::FrictionTerm;
    if model.friction_terms().contains(&FrictionTerm::Load) {
        return Ok(None);
    }
    Ok(Some(on_random_states(model)?.0.rank))
}

/// The identifiability of `model`'s regressor on 400 random states
/// ([`crate::dynamics::random_states`]: positions within the limits or ±1,
/// velocities and accelerations ±2), the structure any data share, and
/// each column's RMS over those states. A load friction term's columns are
/// not finite without torques: drop the term first.
pub fn on_random_states(
    model: &crate::dynamics::Model,
) -> Result<(Identifiability, Vec<f64>), IdentifyError> {
    let [q, qd, qdd] = crate::dynamics::random_states(model, 400, 1);
    let y = crate::dynamics::regressor_batch(model, &q, &qd, &qdd)?;
    let p = model.regressor_columns();
    let rows = y.len() / p;
    let full = Mat::from_fn(rows, p, |i, j| y[i * p + j]);
    // the thin QR's R (p × p) has the regressor's column space and norms
    let r = full.qr().thin_R().to_owned();
    let id = Identifiability::of(&r, &model.layout().parameter_names())?;
    let rms = (0..p)
        .map(|j| ((0..rows).map(|i| full[(i, j)].powi(2)).sum::<f64>() / rows as f64).sqrt())
        .collect();
    Ok((id, rms))
}

/// `‖R θ − d‖²`: the residual sum of squares of reduced data.
pub(super) fn rss(r: &Mat<f64>, d: &[f64], theta: &[f64]) -> f64 {
    (0..r.nrows())
        .map(|i| ((0..r.ncols()).map(|j| r[(i, j)] * theta[j]).sum::<f64>() - d[i]).powi(2))
        .sum::<f64>()
}

/// The first `most` names, then how many more.
fn abbreviated(names: &[String], most: usize) -> String {
    if names.len() <= most {
        return names.join(", ");
    }
    format!(
        "{}, … {} more",
        names[..most].join(", "),
        names.len() - most
    )
}

/// A null direction named by its up to three largest components (as
/// printed, to 2 decimals; equal ones in θ's order, so that rounding does
/// not order them).
fn direction_name(x: &[f64], names: &[String]) -> String {
    let mut comp: Vec<(usize, f64)> = x.iter().copied().enumerate().collect();
    let shown = |c: f64| (c.abs() * 100.0).round();
    comp.sort_by(|a, b| shown(b.1).total_cmp(&shown(a.1)).then(a.0.cmp(&b.0)));
    let terms: Vec<String> = (comp.iter().take(3))
        .filter(|c| c.1.abs() > 0.05)
        .map(|&(j, c)| format!("{c:+.2}·{}", names[j]))
        .collect();
    terms.join(" ")
}

/// The base of the unit-column `rs` ([`pick_base`]) and what it says.
struct Base {
    /// The base columns, ascending.
    columns: Vec<usize>,
    /// Per base column its row of `K` in SI units (1 at itself).
    combinations: Vec<Vec<f64>>,
    /// Per dependent column whose norm is not zero (ascending), the unit
    /// direction `e_d − K_s e_b` (scaled columns) that the data do not see.
    unseen: Vec<Vec<f64>>,
}

/// The canonical base of the unit-column `rs` (columns `norms` > 0 live),
/// `rank` columns, with `K` from the QR of `rs` with the base columns
/// first: `K_s = R₁⁻¹ R₂`.
fn base_columns(rs: &Mat<f64>, norms: &[f64], rank: usize) -> Result<Base, IdentifyError> {
    let p = rs.ncols();
    let base = pick_base(rs, rank);
    let rank = base.len();
    let order: Vec<usize> = (base.iter().copied())
        .chain((0..p).filter(|j| !base.contains(j)))
        .collect();
    let permuted = Mat::from_fn(rs.nrows(), p, |i, c| rs[(i, order[c])]);
    let rr = permuted.qr().thin_R().to_owned();
    let r1 = Mat::from_fn(rank, rank, |i, j| rr[(i, j)]);
    let r2 = Mat::from_fn(rank, p - rank, |i, j| rr[(i, rank + j)]);
    let ks = back_substituted(&r1, r2)?;
    let rows = (0..rank)
        .map(|i| {
            let mut k = vec![0.0; p];
            k[base[i]] = 1.0;
            for (c, &dj) in order[rank..].iter().enumerate() {
                if ks[(i, c)].abs() > TERM_TOL && norms[base[i]] > 0.0 {
                    k[dj] = ks[(i, c)] * norms[dj] / norms[base[i]];
                }
            }
            k
        })
        .collect();
    let unseen = (order[rank..].iter().enumerate())
        .filter(|&(_, &dj)| norms[dj] > 0.0)
        .map(|(c, &dj)| {
            let mut x = vec![0.0; p];
            x[dj] = 1.0;
            (0..rank).for_each(|i| x[base[i]] = -ks[(i, c)]);
            let len = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            x.iter().map(|v| v / len).collect()
        })
        .collect();
    Ok(Base {
        columns: base,
        combinations: rows,
        unseen,
    })
}

/// `R₁⁻¹ R₂` (`r1` upper triangular: back substitution); an error at a
/// zero pivot.
fn back_substituted(r1: &Mat<f64>, mut ks: Mat<f64>) -> Result<Mat<f64>, IdentifyError> {
    let rank = r1.nrows();
    for c in 0..ks.ncols() {
        for i in (0..rank).rev() {
            let mut v = ks[(i, c)];
            for j in i + 1..rank {
                v -= r1[(i, j)] * ks[(j, c)];
            }
            if r1[(i, i)] == 0.0 {
                return Err(IdentifyError::Factorisation {
                    what: "the base parameters' triangular solve (a zero pivot)",
                });
            }
            ks[(i, c)] = v / r1[(i, i)];
        }
    }
    Ok(ks)
}

/// `rank` columns of the unit-column `rs` picked one at a time, each the
/// column farthest from the span of those picked (Gram–Schmidt, each
/// projection made twice), ties within [`TIE_TOL`] of the farthest going
/// to the first in θ's order; ascending. Fewer if the rest are all in the
/// span (rounding).
fn pick_base(rs: &Mat<f64>, rank: usize) -> Vec<usize> {
    let (m, p) = (rs.nrows(), rs.ncols());
    let mut rest: Vec<Vec<f64>> = (0..p)
        .map(|j| (0..m).map(|i| rs[(i, j)]).collect())
        .collect();
    let mut picked: Vec<usize> = Vec::with_capacity(rank);
    let norm = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
    for _ in 0..rank {
        let dist: Vec<f64> = (0..p)
            .map(|j| {
                if picked.contains(&j) {
                    0.0
                } else {
                    norm(&rest[j])
                }
            })
            .collect();
        let far = dist.iter().copied().fold(0.0, f64::max);
        if !(far > 0.0 && far.is_finite()) {
            break;
        }
        let Some(j) = (0..p).find(|&j| dist[j] >= (1.0 - TIE_TOL) * far) else {
            break;
        };
        let u: Vec<f64> = rest[j].iter().map(|v| v / dist[j]).collect();
        for (k, col) in rest.iter_mut().enumerate() {
            if k != j && !picked.contains(&k) {
                (0..2).for_each(|_| project_out(col, &u));
            }
        }
        picked.push(j);
    }
    picked.sort_unstable();
    picked
}

/// `x − (x·u) u` in place (`u` of unit length).
fn project_out(x: &mut [f64], u: &[f64]) {
    let c: f64 = x.iter().zip(u).map(|(a, b)| a * b).sum();
    x.iter_mut().zip(u).for_each(|(a, b)| *a -= c * b);
}

/// `base's name + Σ coef·name`, coefficients to 4 significant digits.
fn combination_name(b: usize, k: &[f64], names: &[String]) -> String {
    let mut s = names[b].clone();
    for (j, &c) in k.iter().enumerate() {
        if j == b || c == 0.0 {
            continue;
        }
        let sign = if c < 0.0 { '−' } else { '+' };
        s += &format!(" {sign} {}·{}", crate::numfmt::sig4(c.abs()), names[j]);
    }
    s
}

/// The diagonal of `(R_bᵀ R_b)⁻¹` (R_b: the base columns of r), from the
/// SVD of R_b.
fn base_variances(r: &Mat<f64>, base: &[usize]) -> Result<Vec<f64>, IdentifyError> {
    let k = base.len();
    if k == 0 {
        return Ok(vec![]);
    }
    let rb = Mat::from_fn(r.nrows().max(k), k, |i, j| {
        if i < r.nrows() { r[(i, base[j])] } else { 0.0 }
    });
    let svd = rb.svd().map_err(|_| IdentifyError::Factorisation {
        what: "SVD of the base columns (standard deviations)",
    })?;
    let (s, v) = (svd.S().column_vector(), svd.V());
    Ok((0..k)
        .map(|j| {
            (0..k)
                .filter(|&i| s[i] > 0.0)
                .map(|i| (v[(j, i)] / s[i]).powi(2))
                .sum()
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(p: usize) -> Vec<String> {
        (0..p).map(|j| format!("x{j}")).collect()
    }

    #[test]
    fn a_dependent_column_becomes_a_combination_and_a_zero_one_unidentifiable() {
        // columns: a, b, 2a + 3b (scaled by 10), 0
        let r = Mat::from_fn(5, 4, |i, j| {
            let a = [1.0, 0.0, 2.0, -1.0, 0.5][i];
            let b = [0.0, 1.0, 1.0, 3.0, -2.0][i];
            match j {
                0 => a,
                1 => b,
                2 => 10.0 * (2.0 * a + 3.0 * b),
                _ => 0.0,
            }
        });
        let id = Identifiability::of(&r, &names(4)).unwrap();
        assert_eq!((id.rank, id.columns), (2, 4));
        assert_eq!(id.unidentifiable, vec!["x3".to_string()]);
        assert_eq!(id.directions.len(), 2);
        // R θ = R_b β for any θ
        let theta = [0.3, -1.2, 0.7, 5.0];
        let beta: Vec<f64> = (id.combinations.iter())
            .map(|k| k.iter().zip(&theta).map(|(a, b)| a * b).sum())
            .collect();
        for i in 0..5 {
            let full: f64 = (0..4).map(|j| r[(i, j)] * theta[j]).sum();
            let base: f64 = (id.base_columns.iter().zip(&beta))
                .map(|(&j, b)| r[(i, j)] * b)
                .sum();
            assert!((full - base).abs() < 1e-12, "row {i}: {full} vs {base}");
        }
        assert!(!id.combinations.iter().any(|k| k[3] != 0.0));
    }

    /// A random orthogonal `k × k` matrix (the Q of a random matrix's QR).
    fn rotation(k: usize, seed: u64) -> Mat<f64> {
        let mut x = seed;
        let mut next = move || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let a = Mat::from_fn(k, k, |_, _| next());
        a.qr().compute_Q()
    }

    #[test]
    fn tied_columns_go_to_the_first_whatever_the_rounding() {
        // columns a, b, a again, 2b: ties at every step; the rows rotated
        // (another reduction of the same data) round them otherwise
        let r = Mat::from_fn(4, 4, |i, j| {
            let a = [1.0, 0.5, -2.0, 0.0][i];
            let b = [0.0, 1.0, 3.0, -1.0][i];
            [a, b, a, 2.0 * b][j]
        });
        for seed in 0..20 {
            let rotated = rotation(4, seed) * &r;
            let id = Identifiability::of(&rotated, &names(4)).unwrap();
            assert_eq!(id.base_columns, vec![0, 1], "seed {seed}");
            let named: Vec<&str> = (id.base_parameters.iter())
                .map(|b| b.combination.as_str())
                .collect();
            assert_eq!(named, ["x0 + 1·x2", "x1 + 2·x3"], "seed {seed}");
            assert_eq!(id.directions, ["-0.71·x0 +0.71·x2", "-0.71·x1 +0.71·x3"]);
        }
    }

    #[test]
    fn standard_deviations_match_the_least_squares_covariance() {
        // one column x, data y = 2x + noise: σ(β) = σ̂ / ‖x‖
        let x = [1.0, 2.0, -1.0, 0.5];
        let y = [2.1, 3.9, -2.05, 1.0];
        let r = Mat::from_fn(4, 1, |i, _| x[i]);
        let mut id = Identifiability::of(&r, &names(1)).unwrap();
        let xx: f64 = x.iter().map(|v| v * v).sum();
        let beta = x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>() / xx;
        let rss: f64 = x.iter().zip(&y).map(|(a, b)| (a * beta - b).powi(2)).sum();
        id.estimate(&r, &y, &[beta], 4).unwrap();
        let want = (rss / 3.0 / xx).sqrt();
        let got = id.base_parameters[0].std_dev.unwrap();
        assert!((got - want).abs() < 1e-12 * want, "{got} vs {want}");
        assert!((id.base_parameters[0].value - beta).abs() < 1e-15);
    }
}
