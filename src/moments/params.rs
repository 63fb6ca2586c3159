//! The 10 inertial parameters of a rigid body and their conversions.
//!
//! The order is stated here once, for the whole crate (the paper's, Wensing
//! et al. 2017, eq. after (2)):
//!
//! ```text
//! π = [m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz]
//! ```
//!
//! with m the mass (kg), h = m c the first mass moment (kg·m, c the centre of
//! mass in the body frame, m) and Ī the rotational inertia about the body
//! frame's origin (kg·m², matrix entries, so `Ixy = −∫ x y ρ`). Other orders
//! are converted at the boundary: [`InertialParams::from_pinocchio`],
//! [`InertialParams::from_spatial_v2`], [`InertialParams::from_urdf`].

use nalgebra::{Matrix3, Matrix4, Matrix6, Rotation3, SymmetricEigen, Vector3};
use serde::{Deserialize, Serialize};

/// The skew matrix `S(x)` with `S(x) y = x × y`.
pub fn skew(x: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -x.z, x.y, x.z, 0.0, -x.x, -x.y, x.x, 0.0)
}

/// Eigenvalues ascending and eigenvectors as the columns of a rotation.
fn sorted_eigen(m: &Matrix3<f64>) -> (Vector3<f64>, Matrix3<f64>) {
    let eig = SymmetricEigen::new(*m);
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let mut axes = Matrix3::zeros();
    for k in 0..3 {
        axes.set_column(k, &eig.eigenvectors.column(idx[k]));
    }
    if axes.determinant() < 0.0 {
        axes.set_column(2, &(-axes.column(2)));
    }
    (Vector3::from_fn(|k, _| eig.eigenvalues[idx[k]]), axes)
}

/// Inertial parameters π ∈ ℝ¹⁰ of one rigid body, in the paper's order
/// (see the module documentation). Frame: the body frame; units SI.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct InertialParams(pub [f64; 10]);

/// Mass, centre of mass and inertia about the centre of mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassComInertia {
    /// Mass m (kg).
    pub mass: f64,
    /// Centre of mass c in the body frame (m).
    pub com: Vector3<f64>,
    /// Rotational inertia about the CoM, body-frame axes (kg·m²).
    pub inertia_com: Matrix3<f64>,
}

/// The covariance ellipsoid `E_π = {x : (x − c)ᵀ (Σ_C/m)⁻¹ (x − c) ≤ 1}`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CovarianceEllipsoid {
    /// Centre = the CoM (m).
    pub center: Vector3<f64>,
    /// Semi-axes `√(μᵢ/m)` (m), ascending; NaN where μᵢ < 0 (inconsistent π).
    pub semi_axes: Vector3<f64>,
    /// Principal axes as columns (shared with the inertia about the CoM).
    pub axes: Matrix3<f64>,
}

impl InertialParams {
    /// From the 10 numbers in the paper's order.
    pub fn new(p: [f64; 10]) -> Self {
        Self(p)
    }

    /// The 10 numbers in the paper's order.
    pub fn as_array(&self) -> [f64; 10] {
        self.0
    }

    /// Mass m (kg).
    pub fn mass(&self) -> f64 {
        self.0[0]
    }

    /// First moment h = m c (kg·m).
    pub fn h(&self) -> Vector3<f64> {
        Vector3::new(self.0[1], self.0[2], self.0[3])
    }

    /// Centre of mass c = h / m (m); non-finite when m = 0.
    pub fn com(&self) -> Vector3<f64> {
        self.h() / self.mass()
    }

    /// Rotational inertia Ī about the body origin (kg·m²).
    pub fn inertia(&self) -> Matrix3<f64> {
        let p = &self.0;
        Matrix3::new(p[4], p[5], p[6], p[5], p[7], p[8], p[6], p[8], p[9])
    }

    /// From mass, CoM and inertia about the CoM (parallel-axis theorem (8)).
    pub fn from_mass_com_inertia(mass: f64, com: Vector3<f64>, inertia_com: Matrix3<f64>) -> Self {
        let s = skew(&com);
        let i = inertia_com + mass * s * s.transpose();
        Self::from_mass_h_inertia(mass, mass * com, i)
    }

    /// From mass, first moment and inertia about the body origin.
    pub fn from_mass_h_inertia(mass: f64, h: Vector3<f64>, i: Matrix3<f64>) -> Self {
        let i = 0.5 * (i + i.transpose());
        Self([
            mass,
            h.x,
            h.y,
            h.z,
            i[(0, 0)],
            i[(0, 1)],
            i[(0, 2)],
            i[(1, 1)],
            i[(1, 2)],
            i[(2, 2)],
        ])
    }

    /// Mass, CoM and inertia about the CoM.
    pub fn to_mass_com_inertia(&self) -> MassComInertia {
        let c = self.com();
        let s = skew(&c);
        MassComInertia {
            mass: self.mass(),
            com: c,
            inertia_com: self.inertia() - self.mass() * s * s.transpose(),
        }
    }

    /// Rotational inertia about the CoM, `Ī_C = Ī − m S(c) S(c)ᵀ` (kg·m²).
    pub fn inertia_com(&self) -> Matrix3<f64> {
        let h = self.h();
        // m S(c)S(c)ᵀ = S(h)S(h)ᵀ / m
        let s = skew(&h);
        self.inertia() - s * s.transpose() / self.mass()
    }

    /// The 6×6 spatial inertia `[[Ī, S(h)], [S(h)ᵀ, m 1]]` (angular first).
    pub fn spatial(&self) -> Matrix6<f64> {
        let mut m = Matrix6::zeros();
        let s = skew(&self.h());
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.inertia());
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&s);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&s.transpose());
        m.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * self.mass()));
        m
    }

    /// From a 6×6 spatial inertia (angular first); the input is symmetrised.
    pub fn from_spatial(s: &Matrix6<f64>) -> Self {
        let s = 0.5 * (s + s.transpose());
        let m = (s[(3, 3)] + s[(4, 4)] + s[(5, 5)]) / 3.0;
        // S(h) sits in the upper-right block: S(h)[(2,1)] = hx, [(0,2)] = hy, [(1,0)] = hz
        let h = Vector3::new(s[(2, 4)], s[(0, 5)], s[(1, 3)]);
        Self::from_mass_h_inertia(m, h, s.fixed_view::<3, 3>(0, 0).into_owned())
    }

    /// Second-moment matrix `Σ = ∫ x xᵀ ρ = ½ tr(Ī) 1 − Ī` (kg·m²), eq. (17)/(19).
    pub fn second_moment(&self) -> Matrix3<f64> {
        let i = self.inertia();
        Matrix3::identity() * (0.5 * i.trace()) - i
    }

    /// Density-weighted covariance about the CoM, `Σ_C = Σ − h hᵀ / m` (kg·m²), eq. (15).
    pub fn covariance(&self) -> Matrix3<f64> {
        let h = self.h();
        self.second_moment() - h * h.transpose() / self.mass()
    }

    /// The 4×4 pseudo-inertia `J = [[Σ, h], [hᵀ, m]]` (Definition 7).
    pub fn pseudo_inertia(&self) -> Matrix4<f64> {
        let mut j = Matrix4::zeros();
        j.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&self.second_moment());
        let h = self.h();
        for k in 0..3 {
            j[(k, 3)] = h[k];
            j[(3, k)] = h[k];
        }
        j[(3, 3)] = self.mass();
        j
    }

    /// From a pseudo-inertia (symmetrised): `Ī = tr(Σ) 1 − Σ`.
    pub fn from_pseudo_inertia(j: &Matrix4<f64>) -> Self {
        let j = 0.5 * (j + j.transpose());
        let sigma = j.fixed_view::<3, 3>(0, 0).into_owned();
        let i = Matrix3::identity() * sigma.trace() - sigma;
        Self::from_mass_h_inertia(j[(3, 3)], Vector3::new(j[(0, 3)], j[(1, 3)], j[(2, 3)]), i)
    }

    /// The covariance ellipsoid (Section IV-B).
    pub fn covariance_ellipsoid(&self) -> CovarianceEllipsoid {
        let (mu, axes) = sorted_eigen(&self.covariance());
        let m = self.mass();
        let semi = mu.map(|mu| if mu >= 0.0 { (mu / m).sqrt() } else { f64::NAN });
        CovarianceEllipsoid {
            center: self.com(),
            semi_axes: semi,
            axes,
        }
    }

    /// Principal moments of the inertia about the CoM, ascending, and the
    /// principal axes (columns, right-handed).
    pub fn principal_moments(&self) -> (Vector3<f64>, Matrix3<f64>) {
        sorted_eigen(&self.inertia_com())
    }

    /// The same body expressed in another frame: `x_new = R x_old + p`
    /// (R rotates body-frame vectors into the new frame).
    pub fn transformed(&self, r: &Matrix3<f64>, p: &Vector3<f64>) -> Self {
        // y = R x + p: h' = R h + m p,
        // Ī' = R Ī Rᵀ + 2 pᵀ(Rh) 1 − (Rh)pᵀ − p(Rh)ᵀ + m(|p|² 1 − p pᵀ)
        // (no division by m, so massless entries transform too)
        let m = self.mass();
        let rh = r * self.h();
        let i = r * self.inertia() * r.transpose() + Matrix3::identity() * (2.0 * p.dot(&rh))
            - rh * p.transpose()
            - p * rh.transpose()
            + (Matrix3::identity() * p.norm_squared() - p * p.transpose()) * m;
        Self::from_mass_h_inertia(m, rh + p * m, i)
    }

    /// `self + other` (the two bodies rigidly joined, same frame).
    pub fn plus(&self, other: &Self) -> Self {
        Self(std::array::from_fn(|k| self.0[k] + other.0[k]))
    }

    /// From Pinocchio's order `[m, hx, hy, hz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
    pub fn from_pinocchio(p: [f64; 10]) -> Self {
        Self([p[0], p[1], p[2], p[3], p[4], p[5], p[7], p[6], p[8], p[9]])
    }

    /// To Pinocchio's order.
    pub fn to_pinocchio(&self) -> [f64; 10] {
        let p = &self.0;
        [p[0], p[1], p[2], p[3], p[4], p[5], p[7], p[6], p[8], p[9]]
    }

    /// From Cheetah-Software / spatial_v2 order `[m, hx, hy, hz, Ixx, Iyy, Izz, Iyz, Ixz, Ixy]`.
    pub fn from_spatial_v2(p: [f64; 10]) -> Self {
        Self([p[0], p[1], p[2], p[3], p[4], p[9], p[8], p[5], p[7], p[6]])
    }

    /// To Cheetah-Software / spatial_v2 order.
    pub fn to_spatial_v2(&self) -> [f64; 10] {
        let p = &self.0;
        [p[0], p[1], p[2], p[3], p[4], p[7], p[9], p[8], p[6], p[5]]
    }

    /// From a URDF `<inertial>`: mass, origin `xyz` (the CoM) and `rpy`, and
    /// the inertia `[ixx, ixy, ixz, iyy, iyz, izz]` about the CoM in the
    /// frame rotated by rpy (URDF: R = Rz(y) Ry(p) Rx(r)).
    pub fn from_urdf(mass: f64, xyz: [f64; 3], rpy: [f64; 3], inertia: [f64; 6]) -> Self {
        let [ixx, ixy, ixz, iyy, iyz, izz] = inertia;
        let ic = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
        let r = Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]).into_inner();
        Self::from_mass_com_inertia(mass, Vector3::from(xyz), r * ic * r.transpose())
    }

    /// To a URDF `<inertial>` with rpy = 0: `(mass, xyz, [ixx, ixy, ixz, iyy, iyz, izz])`.
    pub fn to_urdf(&self) -> (f64, [f64; 3], [f64; 6]) {
        let m = self.to_mass_com_inertia();
        let i = m.inertia_com;
        (
            m.mass,
            [m.com.x, m.com.y, m.com.z],
            [
                i[(0, 0)],
                i[(0, 1)],
                i[(0, 2)],
                i[(1, 1)],
                i[(1, 2)],
                i[(2, 2)],
            ],
        )
    }

    /// Whether all 10 numbers are finite.
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|x| x.is_finite())
    }

    /// The rule every reader of inertial parameters applies (URDF, sidecar,
    /// parameter file): all numbers finite and within ±[`MAX_ABS_PARAM`],
    /// and the mass not negative. A massless frame (all zero) passes;
    /// physical consistency is a separate question
    /// ([`crate::moments::check_consistency`]). The error names the number.
    pub fn validate(&self) -> Result<(), ParamFault> {
        const NAMES: [&str; 10] = [
            "mass", "hx", "hy", "hz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz",
        ];
        for (name, x) in NAMES.iter().zip(self.0) {
            if !x.is_finite() {
                return Err(ParamFault::NotFinite { name, value: x });
            }
            if x.abs() > MAX_ABS_PARAM {
                return Err(ParamFault::TooLarge { name, value: x });
            }
        }
        if self.0[0] < 0.0 {
            return Err(ParamFault::NegativeMass(self.0[0]));
        }
        Ok(())
    }
}

/// Why inertial parameters fail [`InertialParams::validate`].
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ParamFault {
    /// A number that is not finite.
    #[error("{name} = {value} is not finite")]
    NotFinite {
        /// Which parameter (`mass`, `hx`, …, `Izz`).
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A number beyond ±[`MAX_ABS_PARAM`].
    #[error("{name} = {} is beyond ±{}", crate::numfmt::short(*value), crate::numfmt::short(MAX_ABS_PARAM))]
    TooLarge {
        /// Which parameter.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A negative mass (kg).
    #[error("mass = {} kg is negative", crate::numfmt::sig4(*.0))]
    NegativeMass(f64),
}

/// The largest magnitude of an inertial parameter the readers accept
/// (kg, kg·m, kg·m²): a million kilograms is beyond any robot link, and
/// beyond it the identification's squares leave the range where the solver
/// is reliable.
pub const MAX_ABS_PARAM: f64 = crate::urdf::MAX_ABS_INERTIAL;
