//! LMI building blocks for the [`conic`](crate::conic) layer: a rigid body's
//! ten inertial parameters π as affine expressions ([`BodyVars`]), the
//! paper's matrices of them, and the paper's constraints in one call each.
//!
//! ```
//! use momentlmi::conic::{Problem, Settings};
//! use momentlmi::moments::{lmi::BodyVars, Ellipsoid};
//! use nalgebra::Vector3;
//! // the lightest body whose CoM is at x = 0.3 m, realizable in a 0.5 m sphere
//! let mut p = Problem::new();
//! let body = BodyVars::new(&mut p, "body");
//! body.add_realizable(&mut p, &Ellipsoid::sphere(Vector3::zeros(), 0.5).unwrap()).unwrap();
//! body.add_com(&mut p, Vector3::new(0.3, 0.0, 0.0)).unwrap();
//! p.add_eq(body.mass(), 2.0).unwrap();
//! let sol = p.solve(&Settings::default()).unwrap().solved().unwrap();
//! assert!((body.value(&sol).unwrap().com().x - 0.3).abs() < 1e-6);
//! ```

use super::ellipsoid::Ellipsoid;
use super::params::InertialParams;
use crate::conic::{AffExpr, ConicError, ConstraintId, MatExpr, Problem, Solution, Var};
use nalgebra::{DMatrix, Vector3};

/// A rigid body's ten inertial parameters π(x) as affine expressions, in the
/// paper's order `[m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz]` (h = m·c,
/// Ī about the body frame's origin; SI units).
#[derive(Clone, Debug)]
pub struct BodyVars {
    pi: [AffExpr; 10],
}

impl BodyVars {
    /// Ten new free variables named `name.m`, `name.hx`, ….
    pub fn new(p: &mut Problem, name: &str) -> Self {
        const N: [&str; 10] = [
            "m", "hx", "hy", "hz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz",
        ];
        Self {
            pi: std::array::from_fn(|k| AffExpr::from(p.scalar(&format!("{name}.{}", N[k])))),
        }
    }

    /// From ten existing variables.
    pub fn from_vars(v: &[Var]) -> Result<Self, ConicError> {
        if v.len() != 10 {
            return Err(ConicError::DimensionMismatch {
                what: "inertial parameter variables".into(),
                expected: "10".into(),
                found: v.len().to_string(),
            });
        }
        Ok(Self {
            pi: std::array::from_fn(|k| AffExpr::from(v[k])),
        })
    }

    /// From ten affine expressions.
    pub fn from_exprs(pi: [AffExpr; 10]) -> Self {
        Self { pi }
    }

    /// The ten expressions in the paper's order.
    pub fn params(&self) -> &[AffExpr; 10] {
        &self.pi
    }

    /// Mass m (kg).
    pub fn mass(&self) -> AffExpr {
        self.pi[0].clone()
    }

    /// The first moment h = m·c (kg·m).
    pub fn h(&self) -> [AffExpr; 3] {
        [self.pi[1].clone(), self.pi[2].clone(), self.pi[3].clone()]
    }

    /// Ixx about the frame origin (kg·m²).
    pub fn ixx(&self) -> AffExpr {
        self.pi[4].clone()
    }

    /// Ixy (kg·m²).
    pub fn ixy(&self) -> AffExpr {
        self.pi[5].clone()
    }

    /// Ixz (kg·m²).
    pub fn ixz(&self) -> AffExpr {
        self.pi[6].clone()
    }

    /// Iyy (kg·m²).
    pub fn iyy(&self) -> AffExpr {
        self.pi[7].clone()
    }

    /// Iyz (kg·m²).
    pub fn iyz(&self) -> AffExpr {
        self.pi[8].clone()
    }

    /// Izz (kg·m²).
    pub fn izz(&self) -> AffExpr {
        self.pi[9].clone()
    }

    /// Ī as a 3×3 expression.
    pub fn inertia(&self) -> MatExpr {
        const IDX: [[usize; 3]; 3] = [[4, 5, 6], [5, 7, 8], [6, 8, 9]];
        MatExpr::from_fn(3, 3, |i, j| self.pi[IDX[i][j]].clone())
    }

    /// The pseudo-inertia `J(π) = [[½tr(Ī)1 − Ī, h], [hᵀ, m]]` (4×4). The LMI
    /// `J(π) ⪰ εI` is full physical consistency (Theorem 3).
    pub fn pseudo_inertia(&self) -> MatExpr {
        let i = self.inertia();
        let half_tr = (self.pi[4].clone() + &self.pi[7] + &self.pi[9]) * 0.5;
        MatExpr::from_fn(4, 4, |r, c| match (r, c) {
            (3, 3) => self.pi[0].clone(),
            (3, k) | (k, 3) => self.pi[1 + k].clone(),
            (r, c) => {
                let mut e = i[(r, c)].clone() * -1.0;
                if r == c {
                    e += &half_tr;
                }
                e
            }
        })
    }

    /// The 6×6 spatial inertia `[[Ī, S(h)], [S(h)ᵀ, m1]]`. The LMI
    /// `I(π) ⪰ εI` is physical semi-consistency (Theorem 1).
    pub fn spatial_inertia(&self) -> MatExpr {
        let [hx, hy, hz] = self.h();
        let z = AffExpr::zero;
        let s = [
            [z(), -hz.clone(), hy.clone()],
            [hz, z(), -hx.clone()],
            [-hy, hx, z()],
        ];
        let i = self.inertia();
        let m = self.mass();
        MatExpr::from_fn(6, 6, |r, c| match (r < 3, c < 3) {
            (true, true) => i[(r, c)].clone(),
            (true, false) => s[r][c - 3].clone(),
            (false, true) => s[c][r - 3].clone(),
            (false, false) => {
                if r == c {
                    m.clone()
                } else {
                    AffExpr::zero()
                }
            }
        })
    }

    /// `tr(J(π) Q)` for the ellipsoid's Q; `≥ 0` together with `J ⪰ 0` is
    /// density realizability in the ellipsoid (Theorem 4).
    pub fn trace_jq(&self, s: &Ellipsoid) -> AffExpr {
        let q = s.q_matrix();
        let qd = DMatrix::from_fn(4, 4, |i, j| q[(i, j)]);
        self.pseudo_inertia().dot(&qd)
    }

    /// The CoM-in-ellipsoid LMI (22): `[[m, hᵀ − m cₛᵀ], [h − m cₛ, m Qₛ]] ⪰ 0`.
    pub fn com_lmi(&self, s: &Ellipsoid) -> MatExpr {
        let m = self.mass();
        let h = self.h();
        let qs = s.shape();
        MatExpr::from_fn(4, 4, |r, c| match (r, c) {
            (0, 0) => m.clone(),
            (0, k) | (k, 0) => h[k - 1].clone() - m.clone() * s.center[k - 1],
            (r, c) => m.clone() * qs[(r - 1, c - 1)],
        })
    }

    /// `J(π) ⪰ 0`: physically consistent (Theorem 3).
    pub fn add_consistent(&self, p: &mut Problem) -> Result<ConstraintId, ConicError> {
        p.add_psd(&self.pseudo_inertia())
    }

    /// `J(π) ⪰ εI`, strictly consistent with margin ε.
    pub fn add_consistent_eps(
        &self,
        p: &mut Problem,
        eps: f64,
    ) -> Result<ConstraintId, ConicError> {
        p.add_psd_eps(&self.pseudo_inertia(), eps)
    }

    /// `J(π) ⪰ 0` and `tr(J(π) Q) ≥ 0`: density realizable in the ellipsoid
    /// (Theorem 4). Returns the two constraints.
    pub fn add_realizable(
        &self,
        p: &mut Problem,
        e: &Ellipsoid,
    ) -> Result<[ConstraintId; 2], ConicError> {
        Ok([self.add_consistent(p)?, p.add_ge(self.trace_jq(e), 0.0)?])
    }

    /// The CoM at `c` (m): `h − m c = 0` (linear; three rows).
    pub fn add_com(&self, p: &mut Problem, c: Vector3<f64>) -> Result<ConstraintId, ConicError> {
        let h = self.h();
        p.add_zeros((0..3).map(|k| h[k].clone() - self.mass() * c[k]))
    }

    /// The CoM inside the ellipsoid: the LMI (22).
    pub fn add_com_in(&self, p: &mut Problem, e: &Ellipsoid) -> Result<ConstraintId, ConicError> {
        p.add_psd(&self.com_lmi(e))
    }

    /// `π = π'` (ten rows): two bodies with the same parameters, in their
    /// own frames.
    pub fn add_equal(&self, p: &mut Problem, other: &BodyVars) -> Result<ConstraintId, ConicError> {
        p.add_zeros((0..10).map(|k| self.pi[k].clone() - &other.pi[k]))
    }

    /// The value of π at a solution.
    pub fn value(&self, sol: &Solution) -> Result<InertialParams, ConicError> {
        let v = sol.eval_all(&self.pi)?;
        Ok(InertialParams(std::array::from_fn(|k| v[k])))
    }
}
