//! The nearest physically consistent inertia to a given π.
//!
//! Metric: with a length scale L and the mass scale m₀ (the input mass when
//! positive), the distance between π and π′ is
//!
//! ```text
//! d(π, π′) = ‖D (J(π′) − J(π)) D‖_F / m₀,   D = diag(1/L, 1/L, 1/L, 1)
//! ```
//!
//! the Frobenius distance of the pseudo-inertias with lengths measured in
//! units of L: mass, first moment and second moments weigh alike, and the
//! metric does not depend on the choice of axes (it is invariant under
//! rotations of the body frame). The repaired π′ satisfies
//! `D J(π′) D ⪰ ε m₀ I` (strictly consistent with relative margin ε) and,
//! optionally, density realizability in a bounding volume: one ellipsoid,
//! `tr(J(π′) Q) ≥ ε m₀` (Theorem 4), or a union of several, `π′ = Σⱼ πⱼ` with
//! `J(πⱼ) ⪰ 0` and `tr(J(πⱼ) Qⱼ) ≥ 0` (Corollary 2; the margin on the sum).
//! By default the mass is kept (CAD masses come from weighing; inertias are
//! the usual culprits).

use super::ellipsoid::Ellipsoid;
use super::error::MomentsError;
use super::lmi::BodyVars;
use super::params::InertialParams;
use crate::conic::{AffExpr, MatExpr, Problem, Settings};
use nalgebra::DMatrix;

/// Options of [`nearest_consistent`].
#[derive(Clone, Debug, PartialEq)]
pub struct NearestOptions {
    /// Relative margin ε of the strict LMI (default 1e-6).
    pub eps: f64,
    /// Also require density realizability in the union of these ellipsoids
    /// (body frame; empty: consistency only).
    pub within: Vec<Ellipsoid>,
    /// Keep the mass unchanged when it is positive (default true).
    pub keep_mass: bool,
    /// Length scale L (m); default: the ellipsoids' largest semi-axis, else
    /// the radius of gyration `√(tr Ī_C / 2m)`, else 0.1 m.
    pub length_scale: Option<f64>,
}

impl Default for NearestOptions {
    fn default() -> Self {
        Self {
            eps: 1e-6,
            within: vec![],
            keep_mass: true,
            length_scale: None,
        }
    }
}

/// The result of [`nearest_consistent`].
#[derive(Clone, Debug, PartialEq)]
pub struct Nearest {
    /// The repaired parameters.
    pub params: InertialParams,
    /// The distance d(π, π′) in the documented metric.
    pub distance: f64,
    /// The length scale used (m).
    pub length_scale: f64,
}

/// π in other units: masses times `mass`, lengths times `length`.
fn rescaled(pi: &InertialParams, mass: f64, length: f64) -> InertialParams {
    let f = |k: usize| match k {
        0 => mass,
        1..=3 => mass * length,
        _ => mass * length * length,
    };
    InertialParams(std::array::from_fn(|k| pi.0[k] * f(k)))
}

/// Density realizability of `b` in the union of `within`: for one ellipsoid
/// `tr(J Q) ≥ margin`; for several, pieces `πⱼ` that sum to `b`, each
/// `J(πⱼ) ⪰ 0` and `tr(J(πⱼ) Qⱼ) ≥ 0`, and `Σⱼ tr(J(πⱼ) Qⱼ) ≥ margin`.
fn add_within(
    p: &mut Problem,
    b: &BodyVars,
    within: &[Ellipsoid],
    margin: f64,
) -> Result<(), MomentsError> {
    match within {
        [] => {}
        [e] => {
            p.add_ge(b.trace_jq(e), margin)?;
        }
        many => {
            let pieces: Vec<BodyVars> = (0..many.len())
                .map(|j| BodyVars::new(p, &format!("piece{j}")))
                .collect();
            let mut total = AffExpr::zero();
            for (q, e) in pieces.iter().zip(many) {
                p.add_psd(q.pseudo_inertia())?;
                let t = q.trace_jq(e);
                p.add_ge(t.clone(), 0.0)?;
                total += &t;
            }
            p.add_ge(total, margin)?;
            for k in 0..10 {
                let sum: AffExpr = pieces.iter().map(|q| &q.params()[k]).sum();
                p.add_eq(sum - &b.params()[k], 0.0)?;
            }
        }
    }
    Ok(())
}

/// Finds the nearest π′ to π with `J(π′) ⪰ ε m₀ L²-scaled I` (see the module
/// documentation for the metric).
pub fn nearest_consistent(
    pi: &InertialParams,
    opts: &NearestOptions,
) -> Result<Nearest, MomentsError> {
    if !pi.is_finite() {
        return Err(MomentsError::NonFinite("nearest consistent inertia".into()));
    }
    let m = pi.mass();
    let m0 = if m > 0.0 {
        m
    } else {
        pi.0.iter().map(|x| x.abs()).fold(0.0, f64::max).max(1.0)
    };
    let l = length_scale(pi, opts)?;
    if !(opts.eps.is_finite() && opts.eps >= 0.0) {
        return Err(MomentsError::InvalidOption {
            option: "eps",
            value: opts.eps,
        });
    }
    // in units of m₀ and L, where the metric is the plain Frobenius norm
    // and every number of the problem is of order one
    let unit = rescaled(pi, 1.0 / m0, 1.0 / l);
    let within = opts
        .within
        .iter()
        .map(|e| Ellipsoid::with_rotation(e.center / l, e.semi_axes / l, e.rotation))
        .collect::<Result<Vec<_>, _>>()?;
    let j0 = unit.pseudo_inertia();
    let mut p = Problem::new();
    let b = BodyVars::new(&mut p, "pi");
    let j = b.pseudo_inertia();
    p.add_psd_eps(&j, opts.eps)?;
    add_within(&mut p, &b, &within, opts.eps)?;
    if opts.keep_mass && m > 0.0 {
        p.add_eq(b.mass(), 1.0)?;
    }
    p.add_frobenius(
        1.0,
        j - MatExpr::constant(&DMatrix::from_fn(4, 4, |r, c| j0[(r, c)])),
    );
    let sol = p.solve(&Settings::default().tol_gap_rel(1e-10).tol_gap_abs(1e-12))?;
    if !sol.status.is_solved() {
        return Err(MomentsError::Solver {
            status: sol.status,
            task: "finding the nearest consistent inertia".into(),
        });
    }
    let found = b.value(&sol)?;
    let distance = (found.pseudo_inertia() - j0).norm();
    let mut params = rescaled(&found, m0, l);
    if opts.keep_mass && m > 0.0 {
        params.0[0] = m;
    }
    Ok(Nearest {
        params,
        distance,
        length_scale: l,
    })
}

/// The metric's length scale: the option's, else the largest semi-axis of
/// the ellipsoids, else the body's radius of gyration, else 0.1 m; an error
/// if it is not positive and finite.
fn length_scale(pi: &InertialParams, opts: &NearestOptions) -> Result<f64, MomentsError> {
    let m = pi.mass();
    let l = opts.length_scale.unwrap_or_else(|| {
        if !opts.within.is_empty() {
            return opts
                .within
                .iter()
                .map(|e| e.semi_axes.max())
                .fold(0.0, f64::max);
        }
        let g = if m > 0.0 {
            (pi.inertia_com().trace() / (2.0 * m)).sqrt()
        } else {
            f64::NAN
        };
        if g.is_finite() && g > 0.0 { g } else { 0.1 }
    });
    if !(l.is_finite() && l > 0.0) {
        return Err(MomentsError::InvalidOption {
            option: "length_scale",
            value: l,
        });
    }
    Ok(l)
}
