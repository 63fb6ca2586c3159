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
//! optionally, `tr(J(π′) Q) ≥ 0` for a bounding ellipsoid. By default the
//! mass is kept (CAD masses come from weighing; inertias are the usual
//! culprits).

use super::ellipsoid::Ellipsoid;
use super::error::MomentsError;
use super::lmi::BodyVars;
use super::params::InertialParams;
use crate::conic::{MatExpr, Problem, Settings};
use nalgebra::DMatrix;

/// Options of [`nearest_consistent`].
#[derive(Clone, Debug, PartialEq)]
pub struct NearestOptions {
    /// Relative margin ε of the strict LMI (default 1e-6).
    pub eps: f64,
    /// Also require density realizability in this ellipsoid.
    pub ellipsoid: Option<Ellipsoid>,
    /// Keep the mass unchanged when it is positive (default true).
    pub keep_mass: bool,
    /// Length scale L (m); default: the ellipsoid's largest semi-axis, else
    /// the radius of gyration `√(tr Ī_C / 2m)`, else 0.1 m.
    pub length_scale: Option<f64>,
}

impl Default for NearestOptions {
    fn default() -> Self {
        Self {
            eps: 1e-6,
            ellipsoid: None,
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
    let l = opts.length_scale.unwrap_or_else(|| {
        if let Some(e) = &opts.ellipsoid {
            return e.semi_axes.max();
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
    if !(opts.eps.is_finite() && opts.eps >= 0.0) {
        return Err(MomentsError::InvalidOption {
            option: "eps",
            value: opts.eps,
        });
    }
    let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![
        1.0 / l,
        1.0 / l,
        1.0 / l,
        1.0,
    ]));
    let j0 = pi.pseudo_inertia();
    let j0d = DMatrix::from_fn(4, 4, |i, k| j0[(i, k)] * d[(i, i)] * d[(k, k)] / m0);
    let mut p = Problem::new();
    let b = BodyVars::new(&mut p, "pi");
    let jd = b.pseudo_inertia().congruence(&d)?.scaled(1.0 / m0);
    p.add_psd_eps(&jd, opts.eps)?;
    if let Some(e) = &opts.ellipsoid {
        p.add_ge(b.trace_jq(e), 0.0)?;
    }
    if opts.keep_mass && m > 0.0 {
        p.add_eq(b.mass(), m)?;
    }
    p.add_frobenius(1.0, jd - MatExpr::constant(&j0d));
    let sol = p.solve(&Settings::default().tol_gap_rel(1e-10).tol_gap_abs(1e-12))?;
    if !sol.status.is_solved() {
        return Err(MomentsError::Solver {
            status: sol.status,
            task: "finding the nearest consistent inertia".into(),
        });
    }
    let params = b.value(&sol)?;
    let jn = params.pseudo_inertia();
    let mut dist2 = 0.0;
    for i in 0..4 {
        for k in 0..4 {
            dist2 += ((jn[(i, k)] - j0[(i, k)]) * d[(i, i)] * d[(k, k)] / m0).powi(2);
        }
    }
    Ok(Nearest {
        params,
        distance: dist2.sqrt(),
        length_scale: l,
    })
}
