//! The minimum-volume ellipsoid covering a union of ellipsoids, exactly: one
//! small SDP through [`conic`](crate::conic) (the S-procedure; Boyd &
//! Vandenberghe, *Convex Optimization*, §8.4.1).
//!
//! With `E = {x : ‖A x + b‖ ≤ 1}` and each part
//! `Eᵢ = {x : xᵀ Pᵢ x + 2 bᵢᵀ x + cᵢ ≤ 0}`, `E ⊇ Eᵢ` iff some `τᵢ ≥ 0` makes
//!
//! ```text
//! [[τᵢPᵢ − Ã,     τᵢbᵢ − b̃,   0 ],
//!  [(τᵢbᵢ − b̃)ᵀ,  1 + τᵢcᵢ,  −b̃ᵀ],
//!  [0,            −b̃,         Ã ]]  ⪰ 0
//! ```
//!
//! in `Ã = A²`, `b̃ = A b`, and the volume is least when `log det Ã` is
//! largest. E's shape matrix is Ã and its centre `−Ã⁻¹ b̃`.

use super::ellipsoid::Ellipsoid;
use super::error::MomentsError;
use crate::conic::{AffExpr, MatExpr, Problem, Settings};
use nalgebra::{Matrix3, Vector3};

impl Ellipsoid {
    /// The minimum-volume ellipsoid containing all of `parts` (a body whose
    /// shapes are several; the part itself when there is one), exactly:
    /// [`covering`].
    pub fn enclosing(parts: &[Ellipsoid]) -> Result<Self, MomentsError> {
        covering(parts)
    }
}

/// The minimum-volume ellipsoid containing every one of `parts` (the part
/// itself when there is one). Solved in coordinates centred on the parts
/// and scaled by their size; the result is enlarged by 10⁻⁶ of its
/// semi-axes, above the solver's tolerance, so that it contains the parts.
pub fn covering(parts: &[Ellipsoid]) -> Result<Ellipsoid, MomentsError> {
    match parts {
        [] => Err(MomentsError::InvalidEllipsoid("no parts to enclose".into())),
        [e] => Ok(*e),
        many => {
            let c0: Vector3<f64> =
                many.iter().map(|e| e.center).sum::<Vector3<f64>>() / many.len() as f64;
            let l = many
                .iter()
                .map(|e| (e.center - c0).norm() + e.semi_axes.max())
                .fold(0.0, f64::max);
            let scaled: Vec<Ellipsoid> = many
                .iter()
                .map(|e| Ellipsoid::with_rotation((e.center - c0) / l, e.semi_axes / l, e.rotation))
                .collect::<Result<_, _>>()?;
            let (shape, centre) = solve(&scaled)?;
            // back to metres, enlarged by 1e-6 of each semi-axis
            let grow = l * (1.0 + 1e-6);
            Ellipsoid::from_shape(c0 + l * centre, &(shape / (grow * grow)))
        }
    }
}

/// The SDP of the module's doc; returns Ã and the centre.
fn solve(parts: &[Ellipsoid]) -> Result<(Matrix3<f64>, Vector3<f64>), MomentsError> {
    let mut p = Problem::new();
    let a = p.symmetric("A²", 3);
    let b = p.vector("Ab", 3);
    let t = p.scalar("log det A²");
    for (k, e) in parts.iter().enumerate() {
        let tau = p.scalar(&format!("τ{k}"));
        p.add_nonneg(vec![AffExpr::from(tau)])?;
        let pm = e.shape_inverse();
        let bi = -(pm * e.center);
        let ci = e.center.dot(&(pm * e.center)) - 1.0;
        let av = |i: usize, j: usize| AffExpr::from(a.var(i.min(j), i.max(j)).expect("3×3"));
        let block = MatExpr::from_fn(7, 7, |r, c| match (r, c) {
            (0..3, 0..3) => AffExpr::from(tau) * pm[(r, c)] - av(r, c),
            (0..3, 3) => AffExpr::from(tau) * bi[r] - b[r],
            (3, 0..3) => AffExpr::from(tau) * bi[c] - b[c],
            (3, 3) => AffExpr::from(tau) * ci + 1.0,
            (3, 4..7) => -AffExpr::from(b[c - 4]),
            (4..7, 3) => -AffExpr::from(b[r - 4]),
            (4..7, 4..7) => av(r - 4, c - 4),
            _ => AffExpr::zero(),
        });
        p.add_psd(block)?;
    }
    p.add_logdet_ge(&a, t)?;
    p.maximize(t);
    let sol = p.solve(&Settings::default())?;
    if !sol.status.is_solved() {
        return Err(MomentsError::Solver {
            status: sol.status,
            task: "the minimum-volume ellipsoid covering a body's shapes".into(),
        });
    }
    let shape = Matrix3::from_fn(|i, j| {
        let v = a.var(i.min(j), i.max(j)).expect("3×3");
        sol.value(v).unwrap_or(f64::NAN)
    });
    let bt = Vector3::from_fn(|i, _| sol.value(b[i]).unwrap_or(f64::NAN));
    let centre = -shape
        .try_inverse()
        .ok_or_else(|| MomentsError::InvalidEllipsoid("a flat covering ellipsoid".into()))?
        * bt;
    Ok((shape, centre))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit spheres at ±d on x: the covering ellipsoid is a spheroid
    /// about x that touches both (tight) and that no smaller spheroid
    /// replaces (minimal).
    #[test]
    fn two_spheres_are_covered_tightly() {
        let d = 2.0;
        let parts = [
            Ellipsoid::sphere(Vector3::new(d, 0.0, 0.0), 1.0).unwrap(),
            Ellipsoid::sphere(Vector3::new(-d, 0.0, 0.0), 1.0).unwrap(),
        ];
        let e = covering(&parts).unwrap();
        assert!(e.center.norm() < 1e-6);
        // every point of each sphere is inside (dense sample)
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let mut worst: f64 = 1.0;
        for s in &parts {
            for k in 0..2000 {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / 2000.0;
                let r = (1.0 - z * z).sqrt();
                let u = Vector3::new(
                    r * (golden * k as f64).cos(),
                    r * (golden * k as f64).sin(),
                    z,
                );
                worst = worst.min(e.level(&(s.center + u)));
            }
        }
        assert!(worst >= 0.0, "a point outside: level {worst}");
        assert!(
            worst < 1e-4,
            "not tight: every point is deep inside ({worst})"
        );
        // minimal: no spheroid about x with 99 % of its volume contains both
        let mut a: Vec<f64> = e.semi_axes.iter().copied().collect();
        a.sort_by(f64::total_cmp);
        assert!((a[0] - a[1]).abs() < 1e-4 * a[1], "{a:?}");
        let v = a[0] * a[1] * a[2];
        for k in 0..200 {
            let big = a[2] * (0.9 + 0.2 * k as f64 / 200.0);
            let small = (0.99 * v / big).sqrt();
            // contains both spheres iff every sphere point is inside
            let inside = (0..400).all(|i| {
                let th = std::f64::consts::PI * i as f64 / 400.0;
                let (x, y) = (d + th.cos(), th.sin());
                (x / big).powi(2) + (y / small).powi(2) <= 1.0
            });
            assert!(
                !inside,
                "a spheroid of 99 % volume ({big}, {small}) contains both"
            );
        }
    }

    #[test]
    fn one_part_is_itself() {
        let e = Ellipsoid::new(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.1, 0.2, 0.3)).unwrap();
        assert_eq!(covering(&[e]).unwrap(), e);
        assert!(covering(&[]).is_err());
    }
}
