//! LMI building blocks for the [`conic`](crate::conic) layer: the paper's
//! matrices as affine expressions of a 10-vector of decision variables in
//! the paper's order.
//!
//! ```
//! use momentlmi::conic::{Problem, Settings};
//! use momentlmi::moments::{lmi, Ellipsoid};
//! use nalgebra::Vector3;
//! // the lightest body whose CoM is at x = 0.3 m, realizable in a 0.5 m sphere
//! let mut p = Problem::new();
//! let pi = lmi::BodyVars::new(&mut p, "body");
//! let s = Ellipsoid::sphere(Vector3::zeros(), 0.5).unwrap();
//! p.add_psd(&pi.pseudo_inertia()).unwrap();
//! p.add_ge(pi.trace_jq(&s), 0.0).unwrap();
//! p.add_eq(pi.h()[0].clone(), pi.mass() * 0.3).unwrap();
//! p.add_eq(pi.mass(), 2.0).unwrap();
//! let sol = p.solve(&Settings::default()).unwrap();
//! assert!(sol.status.is_solved());
//! ```

use super::ellipsoid::Ellipsoid;
use super::params::InertialParams;
use crate::conic::{AffExpr, ConicError, MatExpr, Problem, Solution, Var};
use nalgebra::DMatrix;

/// Ten affine expressions π(x) in the paper's order.
#[derive(Clone, Debug)]
pub struct BodyVars {
    /// `[m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz]`.
    pub pi: [AffExpr; 10],
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

    /// The mass expression.
    pub fn mass(&self) -> AffExpr {
        self.pi[0].clone()
    }

    /// The first moment h.
    pub fn h(&self) -> [AffExpr; 3] {
        [self.pi[1].clone(), self.pi[2].clone(), self.pi[3].clone()]
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
                let mut e = i.get(r, c).cloned().unwrap_or_default() * -1.0;
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
            (true, true) => i.get(r, c).cloned().unwrap_or_default(),
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
        self.pseudo_inertia().dot(&qd).unwrap_or_default()
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

    /// The value of π at a solution.
    pub fn value(&self, sol: &Solution) -> InertialParams {
        InertialParams(std::array::from_fn(|k| sol.eval(&self.pi[k])))
    }
}
