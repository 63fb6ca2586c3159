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
//! | `offset` | 1 | c | N·m (N) |
//! | `asymmetric` | \|sign(q̇)\| | a | N·m (N) |
//! | `load` | \|τ_rigid,i\| sign(q̇) | μ | 1 (N·m per N·m) |
//! | `stribeck` | exp(−(q̇/v_s)²) sign(q̇) | F_s | N·m (N) |
//!
//! The Stribeck velocity v_s is one number of the law (rad/s, default
//! [`DEFAULT_STRIBECK_VELOCITY`]), not identified: the term is linear in
//! F_s only. F_s > 0 is friction that breaks away above its sliding
//! level; the sign is left free.
//! The coefficients of viscous, Coulomb and load friction are ≥ 0; an
//! offset (a torque sensor's bias, a cable's preload) and an asymmetry
//! (Coulomb friction stronger one way: B_c ± a) have either sign. The
//! offset and the asymmetry differ only at rest (q̇ = 0): on data that never
//! rest they are one column. Load friction is a harmonic drive's:
//! Coulomb friction growing with the torque the joint transmits, here the
//! rigid model's torque τ_rigid,i (links and rotors, before friction) in
//! `predict` and the simulator; `identify`, which does not know τ_rigid
//! before it solves, first scales the column by the measured torque
//! ([`crate::dynamics::Data::load`]), then by the previous solution's rigid
//! torque until that settles (docs/identification.md). A model
//! identifies the terms [`crate::dynamics::Model::friction_terms`] lists
//! ([`FrictionTerm::DEFAULT`]: viscous and Coulomb): the regressor's
//! friction columns are those terms in that order, one column per joint
//! each ([`crate::dynamics::regressor`]); the model file has one array per
//! term (`"friction": {"viscous": […], "coulomb": […], "offset": […]}`, the
//! offset left out when it is zero). A new friction law is one more
//! [`FrictionTerm`] here (its name, basis, unit and sign) and one more
//! field of [`Friction`].

use super::error::DynamicsError;
use serde::{Deserialize, Serialize};

/// One term of the friction law.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FrictionTerm {
    /// Viscous friction `B q̇`.
    Viscous,
    /// Coulomb friction `B_c sign(q̇)`.
    Coulomb,
    /// A constant torque `c` (a torque sensor's offset).
    Offset,
    /// Asymmetric Coulomb friction `a |sign(q̇)|` (with Coulomb friction
    /// B_c: B_c + a moving forward, B_c − a backward).
    Asymmetric,
    /// Load-dependent Coulomb friction `μ |τ_rigid| sign(q̇)`.
    Load,
    /// Stribeck friction `F_s exp(−(q̇/v_s)²) sign(q̇)`.
    Stribeck,
}

impl FrictionTerm {
    /// Every term, in the order a list of terms is kept in.
    pub const ALL: [FrictionTerm; 6] = [
        FrictionTerm::Viscous,
        FrictionTerm::Coulomb,
        FrictionTerm::Offset,
        FrictionTerm::Asymmetric,
        FrictionTerm::Load,
        FrictionTerm::Stribeck,
    ];

    /// The terms a model identifies unless told otherwise.
    pub const DEFAULT: [FrictionTerm; 2] = [FrictionTerm::Viscous, FrictionTerm::Coulomb];

    /// The name in files and parameter names (`viscous.<joint>`).
    pub fn name(self) -> &'static str {
        match self {
            FrictionTerm::Viscous => "viscous",
            FrictionTerm::Coulomb => "coulomb",
            FrictionTerm::Offset => "offset",
            FrictionTerm::Asymmetric => "asymmetric",
            FrictionTerm::Load => "load",
            FrictionTerm::Stribeck => "stribeck",
        }
    }

    /// The term named `name` ([`Self::name`]).
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Terms from a comma-separated list of names (`none`: no term), kept
    /// in [`Self::ALL`]'s order; an unknown or repeated name is an error
    /// naming it.
    pub fn parse_list(list: &str) -> Result<Vec<Self>, DynamicsError> {
        if list.trim() == "none" {
            return Ok(vec![]);
        }
        let mut terms = vec![];
        for name in list.split(',').map(str::trim) {
            let t = Self::parse(name).ok_or_else(|| DynamicsError::UnknownName {
                what: "friction term",
                name: name.to_string(),
                valid: Self::ALL.map(|t| t.name()).join(", ") + ", or none",
            })?;
            if terms.contains(&t) {
                return Err(DynamicsError::Repeated {
                    what: "friction term",
                    name: name.to_string(),
                });
            }
            terms.push(t);
        }
        terms.sort();
        Ok(terms)
    }

    /// Whether its coefficient may have either sign (else it is ≥ 0).
    pub fn signed(self) -> bool {
        matches!(
            self,
            FrictionTerm::Offset | FrictionTerm::Asymmetric | FrictionTerm::Stribeck
        )
    }

    /// The coefficient's unit for a revolute joint (a prismatic joint's:
    /// rad → m, N·m → N).
    pub fn unit(self) -> &'static str {
        match self {
            FrictionTerm::Viscous => "N·m·s/rad",
            FrictionTerm::Coulomb
            | FrictionTerm::Offset
            | FrictionTerm::Asymmetric
            | FrictionTerm::Stribeck => "N·m",
            FrictionTerm::Load => "1",
        }
    }

    /// The basis function φ its coefficient multiplies, at joint velocity
    /// `qd`, joint load `load` (the torque the joint transmits, N·m; only
    /// [`FrictionTerm::Load`] reads it) and Stribeck velocity
    /// `stribeck_velocity` (rad/s; only [`FrictionTerm::Stribeck`] reads
    /// it).
    #[inline]
    pub fn basis(self, qd: f64, load: f64, stribeck_velocity: f64) -> f64 {
        match self {
            FrictionTerm::Viscous => qd,
            FrictionTerm::Coulomb => sign(qd),
            FrictionTerm::Offset => 1.0,
            FrictionTerm::Asymmetric => sign(qd).abs(),
            FrictionTerm::Load => load.abs() * sign(qd),
            FrictionTerm::Stribeck => (-(qd / stribeck_velocity).powi(2)).exp() * sign(qd),
        }
    }

    /// Whether files and models from before the term existed may leave it
    /// out (its coefficients then count as zeros).
    fn optional(self) -> bool {
        !Self::DEFAULT.contains(&self)
    }
}

/// The Stribeck velocity v_s (rad/s) a law has unless told otherwise: a
/// harmonic drive's breakaway region is a few hundredths of a rad/s wide.
pub const DEFAULT_STRIBECK_VELOCITY: f64 = 0.05;

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
    /// Torque offsets c (N·m); empty (a file without them) counts as zeros.
    #[serde(default, skip_serializing_if = "all_zero")]
    pub offset: Vec<f64>,
    /// Coulomb asymmetries a (N·m); empty counts as zeros.
    #[serde(default, skip_serializing_if = "all_zero")]
    pub asymmetric: Vec<f64>,
    /// Load-friction coefficients μ (N·m per N·m of load); empty counts as
    /// zeros.
    #[serde(default, skip_serializing_if = "all_zero")]
    pub load: Vec<f64>,
    /// Stribeck peaks F_s (N·m); empty counts as zeros.
    #[serde(default, skip_serializing_if = "all_zero")]
    pub stribeck: Vec<f64>,
    /// The Stribeck velocity v_s (rad/s); absent:
    /// [`DEFAULT_STRIBECK_VELOCITY`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stribeck_velocity: Option<f64>,
}

fn all_zero(v: &[f64]) -> bool {
    v.iter().all(|&x| x == 0.0)
}

impl Friction {
    /// No friction on `n` joints.
    pub fn zeros(n: usize) -> Self {
        Self {
            viscous: vec![0.0; n],
            coulomb: vec![0.0; n],
            offset: vec![0.0; n],
            asymmetric: vec![0.0; n],
            load: vec![0.0; n],
            stribeck: vec![0.0; n],
            stribeck_velocity: None,
        }
    }

    /// The coefficients of one term, per joint.
    pub fn coefficients(&self, term: FrictionTerm) -> &[f64] {
        match term {
            FrictionTerm::Viscous => &self.viscous,
            FrictionTerm::Coulomb => &self.coulomb,
            FrictionTerm::Offset => &self.offset,
            FrictionTerm::Asymmetric => &self.asymmetric,
            FrictionTerm::Load => &self.load,
            FrictionTerm::Stribeck => &self.stribeck,
        }
    }

    /// The coefficients of one term, to change.
    pub fn coefficients_mut(&mut self, term: FrictionTerm) -> &mut Vec<f64> {
        match term {
            FrictionTerm::Viscous => &mut self.viscous,
            FrictionTerm::Coulomb => &mut self.coulomb,
            FrictionTerm::Offset => &mut self.offset,
            FrictionTerm::Asymmetric => &mut self.asymmetric,
            FrictionTerm::Load => &mut self.load,
            FrictionTerm::Stribeck => &mut self.stribeck,
        }
    }

    /// From one vector of coefficients per term of `terms` (the layout of
    /// identified parameters: `θ[k·n + i]` for the k-th term); the other
    /// terms are zero. With a Stribeck term the law's Stribeck velocity is
    /// `stribeck_velocity`.
    pub fn from_terms(
        n: usize,
        (terms, stribeck_velocity): (&[FrictionTerm], f64),
        value: impl Fn(usize, usize) -> f64,
    ) -> Self {
        let mut f = Self::zeros(n);
        f.stribeck_velocity = terms
            .contains(&FrictionTerm::Stribeck)
            .then_some(stribeck_velocity);
        for (k, &t) in terms.iter().enumerate() {
            for (i, c) in f.coefficients_mut(t).iter_mut().enumerate() {
                *c = value(k, i);
            }
        }
        f
    }

    /// Checks that every term has one coefficient per joint of `n` (a
    /// term beyond [`FrictionTerm::DEFAULT`] may also have none).
    pub fn check_joints(&self, n: usize) -> Result<(), DynamicsError> {
        for t in FrictionTerm::ALL {
            let found = self.coefficients(t).len();
            if found != n && !(t.optional() && found == 0) {
                return Err(DynamicsError::Dimension {
                    what: format!("{} friction coefficients", t.name()),
                    expected: n,
                    found,
                });
            }
        }
        Ok(())
    }

    /// The rigid model's torque `tau` of joint i plus the joint's friction
    /// at velocity `qd` (its load: |tau|).
    #[inline]
    pub fn add_to(&self, tau: f64, i: usize, qd: f64) -> f64 {
        tau + self.torque(i, qd, tau)
    }

    /// Joint i's friction torque at velocity `qd` and load `load` (the
    /// rigid model's torque of the joint, N·m), the terms added one after
    /// the other in [`FrictionTerm::ALL`]'s order.
    #[inline]
    pub fn torque(&self, i: usize, qd: f64, load: f64) -> f64 {
        let vs = self.stribeck_velocity();
        FrictionTerm::ALL.iter().fold(0.0, |t, &term| {
            // a term beyond the default may be absent (empty)
            self.coefficients(term)
                .get(i)
                .map_or(t, |c| t + c * term.basis(qd, load, vs))
        })
    }

    /// The law's Stribeck velocity v_s (rad/s).
    pub fn stribeck_velocity(&self) -> f64 {
        self.stribeck_velocity.unwrap_or(DEFAULT_STRIBECK_VELOCITY)
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
            offset: vec![],
            asymmetric: vec![],
            load: vec![],
            stribeck: vec![],
            stribeck_velocity: None,
        };
        assert_eq!(f.add_to(1.0, 0, -2.0), 1.0 + 0.5 * -2.0 + 3.0 * -1.0);
        assert_eq!(f.add_to(0.0, 1, 0.0), 0.0);
        let terms = FrictionTerm::DEFAULT;
        let g = Friction::from_terms(2, (&terms, 1.0), |k, i| f.coefficients(terms[k])[i]);
        assert_eq!(g.viscous, f.viscous);
        assert_eq!((g.coulomb, g.offset), (f.coulomb.clone(), vec![0.0; 2]));
        let o = Friction {
            offset: vec![-0.25, 0.0],
            ..f.clone()
        };
        assert_eq!(o.add_to(1.0, 0, -2.0), f.add_to(1.0, 0, -2.0) - 0.25);
        assert!(o.check_joints(2).is_ok());
        let list = FrictionTerm::parse_list("offset, viscous").unwrap();
        assert_eq!(list, vec![FrictionTerm::Viscous, FrictionTerm::Offset]);
        assert!(FrictionTerm::parse_list("none").unwrap().is_empty());
        let e = FrictionTerm::parse_list("viscous,stiction")
            .unwrap_err()
            .to_string();
        assert!(e.contains("'stiction'") && e.contains("offset"), "{e}");
        assert!(FrictionTerm::parse_list("coulomb,coulomb").is_err());
        assert_eq!(sign(-0.0), 0.0);
        assert!(f.check_joints(2).is_ok());
        let e = f.check_joints(3).unwrap_err().to_string();
        assert!(e.contains("viscous"), "{e}");
    }
}
