//! Consistency and realizability checks that return reports with margins.
//!
//! Numerical tolerance is explicit: a quantity that must be ≥ 0 counts as
//! satisfied when it is ≥ `−tol · scale`, with `scale` the natural size of
//! the matrix it comes from (its largest eigenvalue). With the default
//! `tol = 1e-12` round-off never rejects a body on the boundary, while the
//! reported margins keep the exact computed values (the identified Cheetah 3
//! inertias come out consistent with margins around 1e-7).

use super::ellipsoid::Ellipsoid;
use super::params::InertialParams;
use nalgebra::{Matrix4, SymmetricEigen, Vector3};
use serde::Serialize;

/// Default relative tolerance of the checks.
pub const DEFAULT_TOL: f64 = 1e-12;

/// The overall verdict of [`check_consistency`], most severe first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// m = 0 and Ī = 0 (and h = 0): a massless frame, not a body.
    Placeholder,
    /// m ≤ 0 with some non-zero moment.
    NonpositiveMass,
    /// m > 0 but Ī_C is not positive definite (Theorem 1 fails).
    NotPositiveDefinite,
    /// Ī_C ≻ 0 but a triangle inequality fails (Theorem 3 fails).
    TriangleViolation,
    /// J(π) ⪰ 0 within the tolerance: physically consistent.
    Ok,
}

impl Verdict {
    /// The JSON name.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Placeholder => "placeholder",
            Verdict::NonpositiveMass => "nonpositive_mass",
            Verdict::NotPositiveDefinite => "not_positive_definite",
            Verdict::TriangleViolation => "triangle_violation",
            Verdict::Ok => "ok",
        }
    }
}

/// The report of [`check_consistency`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConsistencyReport {
    /// The verdict.
    pub verdict: Verdict,
    /// Mass m (kg).
    pub mass: f64,
    /// Principal moments J₁ ≤ J₂ ≤ J₃ of Ī_C (kg·m²); when m ≤ 0 (no CoM)
    /// those of Ī about the body origin (zero for a placeholder).
    pub principal_moments: [f64; 3],
    /// `I(π) ≻ 0`, i.e. m > 0 and Ī_C ≻ 0 (physical semi-consistency).
    pub semi_consistent: bool,
    /// Triangle margins `Jⱼ + Jₖ − Jᵢ` for i = 1, 2, 3 (kg·m²), i.e. `2μᵢ`
    /// with μᵢ the eigenvalues of Σ_C.
    pub triangle_margins: [f64; 3],
    /// Margins relative to the largest principal moment J₃.
    pub triangle_margins_rel: [f64; 3],
    /// Index (0-based) of the principal moment that exceeds the sum of the
    /// other two, if any.
    pub violated_triangle: Option<usize>,
    /// Smallest eigenvalue of J(π) (kg·m² / kg·m / kg mixed units).
    pub pseudo_inertia_min_eig: f64,
    /// Smallest over largest eigenvalue of J(π).
    pub pseudo_inertia_margin_rel: f64,
    /// `J(π) ⪰ 0` within the tolerance and m > 0 (full consistency, Theorem 3).
    pub consistent: bool,
}

impl ConsistencyReport {
    /// The worst relative triangle margin (negative: violated by that fraction).
    pub fn triangle_margin_rel(&self) -> f64 {
        self.triangle_margins_rel
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }
}

fn sorted_eigs4(j: &Matrix4<f64>) -> (f64, f64) {
    let e = SymmetricEigen::new(*j).eigenvalues;
    (e.min(), e.max())
}

/// Mass, semi-consistency, triangle inequalities and J ⪰ 0, with margins.
pub fn check_consistency(pi: &InertialParams, tol: f64) -> ConsistencyReport {
    let m = pi.mass();
    let j = pi.pseudo_inertia();
    let (jmin, jmax) = sorted_eigs4(&j);
    let scale = jmax.abs().max(f64::MIN_POSITIVE);
    let all_zero = pi.0.iter().all(|&x| x == 0.0);
    if m <= 0.0 {
        // no centre of mass: the moments are those about the body origin
        // (all zero for a placeholder), so that no report holds a NaN
        let mut pm: [f64; 3] = SymmetricEigen::new(pi.inertia()).eigenvalues.into();
        pm.sort_by(f64::total_cmp);
        let sum: f64 = pm.iter().sum();
        let margins = pm.map(|p| sum - 2.0 * p);
        let top = pm[2].abs().max(f64::MIN_POSITIVE);
        return ConsistencyReport {
            verdict: if all_zero {
                Verdict::Placeholder
            } else {
                Verdict::NonpositiveMass
            },
            mass: m,
            principal_moments: pm,
            semi_consistent: false,
            triangle_margins: margins,
            triangle_margins_rel: margins.map(|x| if all_zero { 0.0 } else { x / top }),
            violated_triangle: None,
            pseudo_inertia_min_eig: jmin,
            pseudo_inertia_margin_rel: jmin / scale,
            consistent: false,
        };
    }
    let (pm, _) = pi.principal_moments();
    let jmax3 = pm[2].abs().max(f64::MIN_POSITIVE);
    // Tolerances scale with the inertia about the body origin, the quantity
    // a solver or a file actually holds: for a body far from its origin
    // (m c² ≫ Ī_C) round-off in Ī_C is relative to that, not to Ī_C.
    let iscale = jmax3.max(0.5 * pi.inertia().trace().abs());
    let sum = pm.sum();
    let margins = [sum - 2.0 * pm[0], sum - 2.0 * pm[1], sum - 2.0 * pm[2]];
    let rel = margins.map(|x| x / jmax3);
    let pd = pm[0] > -tol * iscale;
    let violated = (0..3)
        .filter(|&i| margins[i] < -tol * iscale)
        .min_by(|&a, &b| rel[a].total_cmp(&rel[b]));
    let consistent = jmin >= -tol * scale;
    let verdict = if !pd {
        Verdict::NotPositiveDefinite
    } else if violated.is_some() || !consistent {
        Verdict::TriangleViolation
    } else {
        Verdict::Ok
    };
    ConsistencyReport {
        verdict,
        mass: m,
        principal_moments: [pm[0], pm[1], pm[2]],
        semi_consistent: pd,
        triangle_margins: margins,
        triangle_margins_rel: rel,
        violated_triangle: violated,
        pseudo_inertia_min_eig: jmin,
        pseudo_inertia_margin_rel: jmin / scale,
        consistent: consistent && verdict == Verdict::Ok,
    }
}

/// The report of [`check_realizable`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RealizabilityReport {
    /// J(π) ⪰ 0 within tolerance.
    pub consistent: bool,
    /// `tr(J(π) Q)` (kg): ≥ 0 is needed for realizability (Theorem 4).
    pub trace_jq: f64,
    /// `tr(J Q) / m`: the mean of `1 − (x − c)ᵀP(x − c)` over the mass, ≤ 1.
    pub trace_jq_rel: f64,
    /// The CoM lies in the ellipsoid (LMI (22)).
    pub com_inside: bool,
    /// `1 − (c − cₛ)ᵀ P (c − cₛ)`, the CoM's level in the ellipsoid (≥ 0 inside).
    pub com_level: f64,
    /// Density realizable in the ellipsoid: consistent and `tr(JQ) ≥ −tol·m`.
    pub realizable: bool,
}

/// Density realizability of π in an ellipsoid (Theorem 4), with margins.
pub fn check_realizable(pi: &InertialParams, s: &Ellipsoid, tol: f64) -> RealizabilityReport {
    let c = check_consistency(pi, tol);
    let m = pi.mass();
    let tr = (pi.pseudo_inertia() * s.q_matrix()).trace();
    let com: Vector3<f64> = pi.com();
    let level = if m > 0.0 { s.level(&com) } else { f64::NAN };
    RealizabilityReport {
        consistent: c.consistent,
        trace_jq: tr,
        trace_jq_rel: tr / m,
        com_inside: level >= -tol,
        com_level: level,
        realizable: c.consistent && tr >= -tol * m.abs(),
    }
}
