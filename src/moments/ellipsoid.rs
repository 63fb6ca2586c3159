//! Ellipsoids `S = {x : (x − c)ᵀ R A⁻² Rᵀ (x − c) ≤ 1}` and their 4×4 form Q.

use super::error::MomentsError;
use nalgebra::{Matrix3, Matrix4, Rotation3, SymmetricEigen, Vector3};

/// An ellipsoid in a body frame: centre c (m), semi-axes a (m, all > 0) along
/// the columns of the rotation R.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Centre (m).
    pub center: Vector3<f64>,
    /// Semi-axis lengths (m).
    pub semi_axes: Vector3<f64>,
    /// Rotation whose columns are the axis directions.
    pub rotation: Matrix3<f64>,
}

impl Ellipsoid {
    /// Axis-aligned ellipsoid; semi-axes must be positive and finite.
    pub fn new(center: Vector3<f64>, semi_axes: Vector3<f64>) -> Result<Self, MomentsError> {
        Self::with_rotation(center, semi_axes, Matrix3::identity())
    }

    /// Ellipsoid with axes along the columns of `rotation` (must be a rotation).
    pub fn with_rotation(
        center: Vector3<f64>,
        semi_axes: Vector3<f64>,
        rotation: Matrix3<f64>,
    ) -> Result<Self, MomentsError> {
        if !(semi_axes.iter().all(|a| a.is_finite() && *a > 0.0)
            && center.iter().all(|c| c.is_finite()))
        {
            return Err(MomentsError::InvalidEllipsoid(format!(
                "semi-axes must be positive and finite and the centre finite, got semi-axes {:?}, centre {:?}",
                semi_axes.as_slice(),
                center.as_slice()
            )));
        }
        let orth = (rotation.transpose() * rotation - Matrix3::identity())
            .abs()
            .max();
        if !(orth < 1e-9 && rotation.determinant() > 0.0) {
            return Err(MomentsError::InvalidEllipsoid(
                "the axes matrix is not a rotation".into(),
            ));
        }
        Ok(Self {
            center,
            semi_axes,
            rotation,
        })
    }

    /// A sphere of radius r.
    pub fn sphere(center: Vector3<f64>, r: f64) -> Result<Self, MomentsError> {
        Self::new(center, Vector3::repeat(r))
    }

    /// The shape matrix `P = R A⁻² Rᵀ` (m⁻²).
    pub fn shape_inverse(&self) -> Matrix3<f64> {
        let d = Matrix3::from_diagonal(&self.semi_axes.map(|a| 1.0 / (a * a)));
        self.rotation * d * self.rotation.transpose()
    }

    /// `Q_s = R A² Rᵀ` (m²), the matrix of (21): `(x − c)ᵀ Q_s⁻¹ (x − c) ≤ 1`.
    pub fn shape(&self) -> Matrix3<f64> {
        let d = Matrix3::from_diagonal(&self.semi_axes.map(|a| a * a));
        self.rotation * d * self.rotation.transpose()
    }

    /// The 4×4 Q of Theorem 4: `S = {x : [x; 1]ᵀ Q [x; 1] ≥ 0}`,
    /// `Q = [[−P, P c], [cᵀ P, 1 − cᵀ P c]]`.
    pub fn q_matrix(&self) -> Matrix4<f64> {
        let p = self.shape_inverse();
        let pc = p * self.center;
        let mut q = Matrix4::zeros();
        q.fixed_view_mut::<3, 3>(0, 0).copy_from(&(-p));
        for k in 0..3 {
            q[(k, 3)] = pc[k];
            q[(3, k)] = pc[k];
        }
        q[(3, 3)] = 1.0 - self.center.dot(&pc);
        q
    }

    /// Back from a Q (any positive multiple of [`Ellipsoid::q_matrix`]).
    pub fn from_q_matrix(q: &Matrix4<f64>) -> Result<Self, MomentsError> {
        let q = 0.5 * (q + q.transpose());
        let ps = -q.fixed_view::<3, 3>(0, 0).into_owned();
        let chol = ps.cholesky().ok_or_else(|| {
            MomentsError::InvalidEllipsoid(
                "the upper-left 3×3 block of Q must be negative definite".into(),
            )
        })?;
        let qv = Vector3::new(q[(0, 3)], q[(1, 3)], q[(2, 3)]);
        let c = chol.solve(&qv);
        let s = q[(3, 3)] + c.dot(&qv);
        if !(s > 0.0) {
            return Err(MomentsError::InvalidEllipsoid(
                "Q describes an empty set".into(),
            ));
        }
        Self::from_shape(c, &(ps / s))
    }

    /// The ellipsoid `(x − c)ᵀ P (x − c) ≤ 1` of a symmetric positive
    /// definite `P` (m⁻²): semi-axes `1/√λᵢ(P)` along its eigenvectors.
    pub fn from_shape(c: Vector3<f64>, p: &Matrix3<f64>) -> Result<Self, MomentsError> {
        let eig = SymmetricEigen::new(*p);
        let mut r = eig.eigenvectors;
        if r.determinant() < 0.0 {
            r.set_column(2, &(-r.column(2)));
        }
        Self::with_rotation(c, eig.eigenvalues.map(|l| 1.0 / l.sqrt()), r)
    }

    /// `[x; 1]ᵀ Q [x; 1] = 1 − (x − c)ᵀ P (x − c)`: ≥ 0 inside.
    pub fn level(&self, x: &Vector3<f64>) -> f64 {
        let d = x - self.center;
        1.0 - d.dot(&(self.shape_inverse() * d))
    }

    /// Whether x lies in the ellipsoid (with a relative slack `tol`).
    pub fn contains(&self, x: &Vector3<f64>, tol: f64) -> bool {
        self.level(x) >= -tol
    }

    /// Volume `4/3 π a₁a₂a₃` (m³).
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * self.semi_axes.product()
    }

    /// The same ellipsoid seen from a frame where `x_new = R x + p`.
    pub fn transformed(&self, r: &Matrix3<f64>, p: &Vector3<f64>) -> Self {
        Self {
            center: r * self.center + p,
            semi_axes: self.semi_axes,
            rotation: r * self.rotation,
        }
    }

    /// Smallest ellipsoid containing a solid box with side lengths `sides`
    /// centred at the origin: semi-axes `(√3/2) sides`.
    pub fn bounding_box(sides: Vector3<f64>) -> Result<Self, MomentsError> {
        Self::new(Vector3::zeros(), sides * (3f64.sqrt() / 2.0))
    }

    /// Smallest ellipsoid containing a solid cylinder (radius r, length l,
    /// axis z, centred): semi-axes `(√1.5 r, √1.5 r, (√3/2) l)`.
    pub fn bounding_cylinder(r: f64, l: f64) -> Result<Self, MomentsError> {
        Self::new(
            Vector3::zeros(),
            Vector3::new(1.5f64.sqrt() * r, 1.5f64.sqrt() * r, 3f64.sqrt() / 2.0 * l),
        )
    }

    /// An ellipsoid containing a capsule (cylinder of radius r and length l
    /// along z, with hemispherical caps): the bounding ellipsoid of the
    /// cylinder of length `l + 2r`.
    pub fn bounding_capsule(r: f64, l: f64) -> Result<Self, MomentsError> {
        Self::bounding_cylinder(r, l + 2.0 * r)
    }

    /// A sphere of radius r at the origin.
    pub fn bounding_sphere(r: f64) -> Result<Self, MomentsError> {
        Self::sphere(Vector3::zeros(), r)
    }
}

/// URDF-style pose: translation and roll-pitch-yaw (R = Rz(y) Ry(p) Rx(r)).
pub fn rpy_rotation(rpy: [f64; 3]) -> Matrix3<f64> {
    Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]).into_inner()
}
