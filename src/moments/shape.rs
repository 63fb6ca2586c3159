//! A body's mass distribution as a shape: whether it has collapsed to a
//! point, a rod or a plate, measured against a length.
//!
//! The covariance ellipsoid's semi-axes `σᵢ = √(μᵢ/m)` (μᵢ the eigenvalues
//! of the second moment about the CoM, Σ_C) are the body's spread along its
//! principal axes. Against a length `L` the body should have (its prior's
//! or its bounding volume's size), a semi-axis below `tol·L` is collapsed:
//! three collapsed is a point mass, two a rod, one a plate. Such bodies
//! satisfy `J ⪰ 0` (they are physically consistent, on the boundary of the
//! cone) but no real link is one; identification reaches them when the data
//! do not determine a body's spread and nothing else holds it.

use super::params::InertialParams;
use serde::Serialize;

/// The default relative size under which a semi-axis counts as collapsed.
pub const DEGENERATE_TOL: f64 = 1e-2;

/// A collapsed mass distribution.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DegenerateShape {
    /// All three semi-axes collapsed.
    Point,
    /// Two collapsed: mass along a line.
    Rod,
    /// One collapsed: mass in a plane.
    Plate,
}

impl DegenerateShape {
    /// `point mass`, `rod` or `plate`.
    pub fn as_str(self) -> &'static str {
        match self {
            DegenerateShape::Point => "point mass",
            DegenerateShape::Rod => "rod",
            DegenerateShape::Plate => "plate",
        }
    }
}

/// The body's shape if it is degenerate against the length `length` (m,
/// positive) at relative tolerance `tol`, with its semi-axes (m); `None`
/// for a body with spread in every direction, or one with no positive mass
/// or no covariance ellipsoid (not semi-consistent: see its consistency).
pub fn degenerate_shape(
    pi: &InertialParams,
    length: f64,
    tol: f64,
) -> Option<(DegenerateShape, [f64; 3])> {
    if !(pi.mass() > 0.0 && length > 0.0) {
        return None;
    }
    let sigma: [f64; 3] = pi.covariance_ellipsoid().semi_axes.into();
    if sigma.iter().any(|s| !s.is_finite()) {
        return None;
    }
    let collapsed = sigma.iter().filter(|s| **s < tol * length).count();
    let shape = match collapsed {
        3 => DegenerateShape::Point,
        2 => DegenerateShape::Rod,
        1 => DegenerateShape::Plate,
        _ => return None,
    };
    Some((shape, sigma))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    fn body(m: f64, spread: [f64; 3]) -> InertialParams {
        // a solid box of half-sides a: Σ_C = m a²/3 on the diagonal
        let s = Matrix3::from_diagonal(&Vector3::from(spread.map(|a| m * a * a / 3.0)));
        let i = Matrix3::identity() * s.trace() - s;
        InertialParams::from_mass_com_inertia(m, Vector3::new(0.1, 0.0, 0.0), i)
    }

    #[test]
    fn points_rods_and_plates_are_told_apart_and_real_links_are_not_flagged() {
        let l = 0.2;
        assert_eq!(
            degenerate_shape(&body(2.0, [0.1, 0.05, 0.04]), l, 1e-2),
            None
        );
        let cases = [
            ([1e-5, 1e-5, 1e-5], DegenerateShape::Point),
            ([0.1, 1e-5, 1e-5], DegenerateShape::Rod),
            ([0.1, 0.05, 1e-5], DegenerateShape::Plate),
        ];
        for (spread, want) in cases {
            let (got, sigma) = degenerate_shape(&body(2.0, spread), l, 1e-2).unwrap();
            assert_eq!(got, want, "{spread:?}");
            assert!(sigma.iter().all(|s| *s >= 0.0));
        }
        // the tolerance is relative to the length given
        assert_eq!(
            degenerate_shape(&body(2.0, [0.1, 0.05, 1e-2]), l, 1e-2),
            None
        );
        assert_eq!(
            degenerate_shape(&body(2.0, [0.1, 0.05, 1e-2]), l, 1e-1).map(|d| d.0),
            Some(DegenerateShape::Plate)
        );
        // no positive mass: nothing to say here
        assert_eq!(degenerate_shape(&InertialParams([0.0; 10]), l, 1e-2), None);
    }
}
