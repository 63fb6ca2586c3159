//! The joint friction model: one law, used by the simulator's true robot,
//! the regressor's friction columns (and so `identify`), `predict`, the
//! model-parameter file and the diagnosis' friction candidates.
//!
//! Per joint i, with q̇ᵢ in rad/s (m/s for a prismatic joint) and
//! `sign(0) = 0`:
//!
//! ```text
//! τ_f,i = Σ_t c_t,i φ_t(q̇ᵢ)          (over the terms t, in the order below)
//! ```
//!
//! | term | basis φ(q̇) | coefficient c | unit |
//! |---|---|---|---|
//! | `viscous` | q̇ | B | N·m·s/rad (N·s/m) |
//! | `coulomb` | sign(q̇) | B_c | N·m (N) |
//!
//! Every coefficient is ≥ 0. The regressor's friction columns are the
//! terms in this order, one column per joint each
//! ([`crate::dynamics::regressor`]); the model file has one array per term
//! (`"friction": {"viscous": […], "coulomb": […]}`). A new friction law is
//! one more [`FrictionTerm`] here (its name, basis and unit) and one more
//! field of [`Friction`]: every user above takes the terms from
//! [`FrictionTerm::ALL`].

use super::error::DynamicsError;
use serde::{Deserialize, Serialize};

/// One term of the friction law.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FrictionTerm {
    /// Viscous friction `B q̇`.
    Viscous,
    /// Coulomb friction `B_c sign(q̇)`.
    Coulomb,
}

impl FrictionTerm {
    /// Every term, in the order of the regressor's columns and of the
    /// identified parameters.
    pub const ALL: [FrictionTerm; 2] = [FrictionTerm::Viscous, FrictionTerm::Coulomb];

    /// The name in files and parameter names (`viscous.<joint>`).
    pub fn name(self) -> &'static str {
        match self {
            FrictionTerm::Viscous => "viscous",
            FrictionTerm::Coulomb => "coulomb",
        }
    }

    /// The coefficient's unit for a revolute joint (a prismatic joint's:
    /// rad → m, N·m → N).
    pub fn unit(self) -> &'static str {
        match self {
            FrictionTerm::Viscous => "N·m·s/rad",
            FrictionTerm::Coulomb => "N·m",
        }
    }

    /// The basis function φ(q̇) its coefficient multiplies.
    #[inline]
    pub fn basis(self, qd: f64) -> f64 {
        match self {
            FrictionTerm::Viscous => qd,
            FrictionTerm::Coulomb => sign(qd),
        }
    }

    /// Its position in [`Self::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// `sign(x)` with `sign(0) = 0`.
#[inline]
pub fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Per-joint coefficients of the friction law (one number per joint and
/// term, in the model's joint order).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Friction {
    /// Viscous coefficients B (N·m·s/rad).
    pub viscous: Vec<f64>,
    /// Coulomb coefficients B_c (N·m).
    pub coulomb: Vec<f64>,
}

impl Friction {
    /// No friction on `n` joints.
    pub fn zeros(n: usize) -> Self {
        Self {
            viscous: vec![0.0; n],
            coulomb: vec![0.0; n],
        }
    }

    /// The coefficients of one term, per joint.
    pub fn coefficients(&self, term: FrictionTerm) -> &[f64] {
        match term {
            FrictionTerm::Viscous => &self.viscous,
            FrictionTerm::Coulomb => &self.coulomb,
        }
    }

    /// The coefficients of one term, to change.
    pub fn coefficients_mut(&mut self, term: FrictionTerm) -> &mut Vec<f64> {
        match term {
            FrictionTerm::Viscous => &mut self.viscous,
            FrictionTerm::Coulomb => &mut self.coulomb,
        }
    }

    /// From one vector of coefficients per term, in [`FrictionTerm::ALL`]'s
    /// order (the layout of identified parameters: `θ[t·n + i]`).
    pub fn from_terms(n: usize, value: impl Fn(FrictionTerm, usize) -> f64) -> Self {
        let mut f = Self::zeros(n);
        for t in FrictionTerm::ALL {
            for (i, c) in f.coefficients_mut(t).iter_mut().enumerate() {
                *c = value(t, i);
            }
        }
        f
    }

    /// Checks that every term has one coefficient per joint of `n`.
    pub fn check_joints(&self, n: usize) -> Result<(), DynamicsError> {
        for t in FrictionTerm::ALL {
            let found = self.coefficients(t).len();
            if found != n {
                return Err(DynamicsError::Dimension {
                    what: format!("{} friction coefficients", t.name()),
                    expected: n,
                    found,
                });
            }
        }
        Ok(())
    }

    /// `tau` plus joint i's friction at velocity `qd`, the terms added one
    /// after the other in [`FrictionTerm::ALL`]'s order.
    #[inline]
    pub fn add_to(&self, tau: f64, i: usize, qd: f64) -> f64 {
        FrictionTerm::ALL.iter().fold(tau, |t, &term| {
            t + self.coefficients(term)[i] * term.basis(qd)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{Friction, FrictionTerm, sign};

    /// The law adds B q̇ then B_c sign(q̇), and the layout helpers agree
    /// with the fields.
    #[test]
    fn the_law_and_its_layout() {
        let f = Friction {
            viscous: vec![0.5, 2.0],
            coulomb: vec![3.0, 0.0],
        };
        assert_eq!(f.add_to(1.0, 0, -2.0), 1.0 + 0.5 * -2.0 + 3.0 * -1.0);
        assert_eq!(f.add_to(0.0, 1, 0.0), 0.0);
        let g = Friction::from_terms(2, |t, i| f.coefficients(t)[i]);
        assert_eq!(g, f);
        assert_eq!(FrictionTerm::Coulomb.index(), 1);
        assert_eq!(sign(-0.0), 0.0);
        assert!(f.check_joints(2).is_ok());
        let e = f.check_joints(3).unwrap_err().to_string();
        assert!(e.contains("viscous"), "{e}");
    }
}
