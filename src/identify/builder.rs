//! Assembling the identification problem (25): a builder open to the
//! caller's constraints: per-body levels and ellipsoids, the prior, solver settings,
//! and hooks that receive the `conic` problem and every body's, joint's
//! friction variables before the solve.
//!
//! ```
//! use momentlmi::dynamics::cheetah3;
//! use momentlmi::identify::{Identification, Level, reduce_samples};
//! use momentlmi::sim::{Effects, SimConfig};
//! use momentlmi::effects::simulate;
//! let leg = cheetah3::description();
//! let fx = Effects::parse("rotor_inertia,coulomb,viscous", &[])?;
//! let d = simulate(&leg, &SimConfig::for_robot(&leg, 3.0, fx, 1), |_, _| {})?;
//! let red = reduce_samples(&leg.model, &d.q, &d.qd, &d.qdd, &d.tau, 1024)?;
//! let solved = Identification::for_robot(&leg, Level::Consistent, 1e-6)?
//!     .level("knee", Level::Ellipsoid)?                 // the ellipsoid level on the knee only
//!     .constrain(|p, v| {
//!         let m = v.total_mass();
//!         p.add_eq(m, 5.2)?;                             // a known total mass (kg)
//!         v.body("hip_rotor")?.add_equal(p, v.body("knee_rotor")?)?; // two identical rotors
//!         Ok(())
//!     })
//!     .solve(&red)?;
//! let knee = solved.body("knee")?;
//! assert!(knee.mass() > 0.0);
//! let (viscous, coulomb) = solved.friction("hip")?;
//! assert!(viscous >= 0.0 && coulomb >= 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::error::{IdentifyError, unknown};
use super::options::{
    CHECK_TOL, IdentifyOptions, Level, MassWeight, Regularizer, default_settings,
};
use super::warning::IdentifyWarning;
use crate::conic::{AffExpr, Problem, Settings};
use crate::dynamics::{FrictionTerm, Model};
use crate::moments::{Ellipsoid, InertialParams, lmi::BodyVars};

/// A hook: adds constraints to the problem, given every body's and joint's
/// variables.
pub(super) type Hook<'h> = Box<dyn Fn(&mut Problem, &Vars) -> Result<(), IdentifyError> + 'h>;

/// The variables a hook sees: every body's π (a free-flying base, links, then rotors, by name)
/// and every joint's friction coefficients. θ is scaled internally; these
/// expressions are in the user's units.
pub struct Vars {
    pub(super) bodies: Vec<(String, BodyVars)>,
    pub(super) joints: Vec<String>,
    /// Friction coefficients, `friction[k·n + i]`: the k-th term of
    /// `terms`, joint i.
    pub(super) friction: Vec<AffExpr>,
    /// The friction terms identified.
    pub(super) terms: Vec<FrictionTerm>,
}

impl Vars {
    /// The body named `name` (a link by its body name or a rotor).
    pub fn body(&self, name: &str) -> Result<&BodyVars, IdentifyError> {
        self.bodies
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, b)| b)
            .ok_or_else(|| unknown("body", name, self.bodies.iter().map(|b| b.0.as_str())))
    }

    /// Every body, in parameter order.
    pub fn bodies(&self) -> impl Iterator<Item = (&str, &BodyVars)> {
        self.bodies.iter().map(|(n, b)| (n.as_str(), b))
    }

    /// Joint `joint`'s coefficient of the friction term `term`
    /// ([`FrictionTerm::unit`]); an error for a term the model does not
    /// identify.
    pub fn friction(&self, term: FrictionTerm, joint: &str) -> Result<AffExpr, IdentifyError> {
        let i = self
            .joints
            .iter()
            .position(|n| n == joint)
            .ok_or_else(|| unknown("joint", joint, self.joints.iter().map(String::as_str)))?;
        let names = self.terms.iter().map(|t| t.name());
        let k = (self.terms.iter().position(|&t| t == term))
            .ok_or_else(|| unknown("identified friction term", term.name(), names))?;
        Ok(self.friction[k * self.joints.len() + i].clone())
    }

    /// Joint `joint`'s viscous coefficient B (N·m·s/rad).
    pub fn viscous(&self, joint: &str) -> Result<AffExpr, IdentifyError> {
        self.friction(FrictionTerm::Viscous, joint)
    }

    /// Joint `joint`'s Coulomb coefficient B_c (N·m).
    pub fn coulomb(&self, joint: &str) -> Result<AffExpr, IdentifyError> {
        self.friction(FrictionTerm::Coulomb, joint)
    }

    /// The sum of every body's mass (a free-flying base, links and rotors), kg.
    pub fn total_mass(&self) -> AffExpr {
        self.bodies.iter().map(|(_, b)| b.mass()).sum()
    }
}

/// One body's constraint set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct BodySpec {
    pub(super) level: Level,
    pub(super) ellipsoid: Option<Ellipsoid>,
}

/// The identification problem (25) of one model, to be solved on reduced
/// data: per-body constraint levels (default: consistent), bounding
/// ellipsoids, a prior, solver settings and the caller's constraints.
pub struct Identification<'m> {
    pub(super) model: &'m Model,
    /// The regressor's columns by name and rows per sample (the model's,
    /// or a free-flyer's: [`Identification::for_free_flyer`]).
    pub(super) layout: crate::dynamics::ParamLayout,
    pub(super) common: Level,
    pub(super) bodies: Vec<BodySpec>,
    pub(super) weight: f64,
    pub(super) mass_weight: MassWeight,
    pub(super) prior: Vec<f64>,
    pub(super) regularizer: Regularizer,
    pub(super) joint_weighting: super::JointWeighting,
    pub(super) com_lmi: bool,
    pub(super) eps: f64,
    pub(super) settings: Settings,
    pub(super) max_memory: u64,
    pub(super) hooks: Vec<Hook<'m>>,
    /// The robot whose bounding volumes fill in the bodies that need one
    /// ([`Identification::for_robot`]): computed only then.
    pub(super) robot: Option<&'m crate::dynamics::RobotDescription>,
    /// The model's structural rank, computed at the first fit and kept
    /// for the others (the weight's folds, a load term's passes).
    pub(super) structural_rank: std::sync::OnceLock<Option<usize>>,
}

impl<'m> Identification<'m> {
    /// Every body consistent, no prior, default solver settings.
    pub fn new(model: &'m Model) -> Self {
        Self {
            model,
            layout: model.layout(),
            common: Level::Consistent,
            bodies: vec![
                BodySpec {
                    level: Level::Consistent,
                    ellipsoid: None,
                };
                model.num_bodies()
            ],
            weight: 0.0,
            mass_weight: MassWeight::default(),
            prior: vec![],
            regularizer: Regularizer::Euclidean,
            joint_weighting: super::JointWeighting::Equal,
            com_lmi: false,
            eps: 0.0,
            settings: default_settings(),
            max_memory: crate::identify::reduce::DEFAULT_MAX_MEMORY_BYTES,
            hooks: vec![],
            robot: None,
            structural_rank: std::sync::OnceLock::new(),
        }
    }

    /// A floating-base robot's problem: its base and tree bodies (every one
    /// consistent), fitted on the `rows` of its dynamics, on data reduced by
    /// [`reduce_floating`](super::floating::reduce_floating) with the same
    /// rows ([`Self::rows`] of [`Self::new`]).
    pub fn for_free_flyer(ff: &'m Model, rows: super::Rows) -> Self {
        Self::new(ff).rows(rows)
    }

    /// The set-up fitted on the `rows` of a free flyer's dynamics (its
    /// base rows, joint rows or both; a fixed base's model is left as it
    /// is). On the base rows alone no friction acts: the friction
    /// coefficients are pinned to 0 rather than left arbitrary.
    pub fn rows(mut self, rows: super::Rows) -> Self {
        if !self.model.is_floating() {
            return self;
        }
        self.layout = self.model.layout_of_rows(rows.range(self.model.dof()));
        if rows == super::Rows::Base {
            self = self.constrain(|p, v| {
                if !v.friction.is_empty() {
                    p.add_zeros(v.friction.iter().cloned())?;
                }
                Ok(())
            });
        }
        self
    }

    /// The set-up of [`IdentifyOptions`] (one level for every body).
    pub fn from_options(model: &'m Model, opts: &IdentifyOptions) -> Result<Self, IdentifyError> {
        let nb = model.num_bodies();
        let mut s = Self::new(model).level_all(opts.level);
        if let Some(e) = &opts.ellipsoids {
            if e.len() != nb {
                return Err(IdentifyError::EllipsoidCount {
                    found: e.len(),
                    bodies: nb,
                });
            }
            for (b, e) in s.bodies.iter_mut().zip(e) {
                b.ellipsoid = Some(*e);
            }
        }
        s.weight = opts.weight;
        s.mass_weight = opts.mass_weight;
        s.prior = opts.prior.clone();
        s.regularizer = opts.regularizer;
        s.com_lmi = opts.com_lmi;
        s.eps = opts.eps;
        s.settings = opts.settings.clone();
        Ok(s)
    }

    /// The constraint level of every body.
    pub fn level_all(mut self, level: Level) -> Self {
        self.common = level;
        self.bodies.iter_mut().for_each(|b| b.level = level);
        self.resolve_ellipsoids();
        self
    }

    /// Gives each body that needs a bounding ellipsoid (its level is the
    /// ellipsoid one, or the CoM LMI is on) and has none the robot's, when
    /// it has exactly one: the robot's bounding volumes are computed on
    /// the first such need only.
    pub(super) fn resolve_ellipsoids(&mut self) {
        let Some(robot) = self.robot else { return };
        let com = self.com_lmi;
        let needs = |b: &BodySpec| {
            b.ellipsoid.is_none()
                && (b.level == Level::Ellipsoid || (com && b.level != Level::None))
        };
        if !self.bodies.iter().any(needs) {
            return;
        }
        for (b, e) in self.bodies.iter_mut().zip(robot.bounding()) {
            if let (true, [e]) = (b.ellipsoid.is_none(), e.as_slice()) {
                b.ellipsoid = Some(*e);
            }
        }
    }

    /// The model.
    pub fn model(&self) -> &'m Model {
        self.model
    }

    /// The level set for all bodies (before per-body changes).
    pub fn common_level(&self) -> Level {
        self.common
    }

    /// The regularisation weight.
    pub fn weight(&self) -> f64 {
        self.weight
    }

    /// Body `b`'s level and ellipsoid.
    pub fn body_spec(&self, b: usize) -> (Level, Option<Ellipsoid>) {
        (self.bodies[b].level, self.bodies[b].ellipsoid)
    }

    fn body_index(&self, body: &str) -> Result<usize, IdentifyError> {
        let names = self.layout.bodies.clone();
        names
            .iter()
            .position(|n| n == body)
            .ok_or_else(|| unknown("body", body, names.iter().map(String::as_str)))
    }

    /// The constraint level of one body (by name).
    pub fn level(mut self, body: &str, level: Level) -> Result<Self, IdentifyError> {
        let k = self.body_index(body)?;
        self.bodies[k].level = level;
        self.resolve_ellipsoids();
        Ok(self)
    }

    /// One body's bounding ellipsoid (its frame).
    pub fn ellipsoid(mut self, body: &str, e: Ellipsoid) -> Result<Self, IdentifyError> {
        let k = self.body_index(body)?;
        self.bodies[k].ellipsoid = Some(e);
        Ok(self)
    }

    /// Regularisation `w R(π, π̂)` toward `prior` (10 per body, links then
    /// rotors; R the [`Regularizer`], Euclidean by default); `w` ≥ 0 and
    /// finite (0: off), the prior finite.
    pub fn prior(mut self, weight: f64, prior: Vec<f64>) -> Result<Self, IdentifyError> {
        let o = IdentifyOptions::new(Level::None).with_prior(weight, prior)?;
        let nb = self.layout.num_bodies();
        if o.weight > 0.0 && o.prior.len() != 10 * nb {
            return Err(IdentifyError::PriorLength {
                found: o.prior.len(),
                bodies: nb,
                weight,
                mass_weight: 0.0,
            });
        }
        self.weight = o.weight;
        self.prior = o.prior;
        Ok(self)
    }

    /// The regularisation weight alone, the prior kept (a weight chosen
    /// from the data: [`Self::choose_model`]); ≥ 0 and finite.
    pub fn with_weight(mut self, weight: f64) -> Result<Self, IdentifyError> {
        self.weight = super::options::nonnegative("weight", weight)?;
        Ok(self)
    }

    /// An extra `w_m Σ_b (m_b − m̂_b)²` toward the prior's masses, every
    /// body's (a free-flying base, links and rotors), added to the regulariser of either kind;
    /// `w_m` in the units of `weight`, ≥ 0 and finite (0, the default: off;
    /// [`Self::for_robot`] takes the sidecar's `[identify]
    /// prior_mass_weight`); needs the prior. For masses known
    /// better than the rest of π (weighed links, CAD mass properties): no
    /// joint torque of a fixed-base chain sees a link mass alone (each
    /// regroups into its parent's first moment and inertia), so without it
    /// the data's combinations move the masses whichever way the
    /// regulariser prefers; with `w_m` ≫ `weight` they stay at the prior
    /// and the first moments and inertias take the correction.
    pub fn prior_mass_weight(mut self, mass_weight: f64) -> Result<Self, IdentifyError> {
        self.mass_weight.explicit = Some(super::options::nonnegative(
            "prior_mass_weight",
            mass_weight,
        )?);
        Ok(self)
    }

    /// The extra weight on the prior's masses in effect: the caller's
    /// ([`Self::prior_mass_weight`]), else the robot's with the Euclidean
    /// prior on, else 0.
    pub fn mass_weight(&self) -> f64 {
        self.mass_weight.resolve(self.weight, self.regularizer)
    }

    /// Sets the robot's own masses' weight (its sidecar's), used unless the
    /// caller sets one.
    pub(crate) fn robot_mass_weight(mut self, w: Option<f64>) -> Self {
        self.mass_weight.robot = w;
        self
    }

    /// A warning when the masses' weight is on but not ≫ the Euclidean
    /// prior's weight, so it does not hold the masses it is meant to.
    pub(crate) fn mass_weight_warning(&self) -> Option<IdentifyWarning> {
        let (w_m, w) = (self.mass_weight(), self.weight);
        (w_m > 0.0 && self.regularizer == Regularizer::Euclidean && w_m < 100.0 * w).then_some(
            IdentifyWarning::MassWeightLow {
                mass_weight: w_m,
                weight: w,
            },
        )
    }

    /// A warning naming the bodies at the ellipsoid level whose prior is
    /// consistent but not density realizable in their bounding ellipsoid
    /// (`tr(J(π̂) Q) < 0`): the fit cannot stay at the prior there.
    pub(crate) fn prior_outside_warning(&self) -> Option<IdentifyWarning> {
        if !(self.weight > 0.0 || self.mass_weight() > 0.0)
            || self.prior.len() != 10 * self.bodies.len()
        {
            return None;
        }
        let names = self.layout.bodies.clone();
        let outside: Vec<String> = (self.bodies.iter().zip(self.prior.chunks_exact(10)))
            .zip(&names)
            .filter_map(|((b, p), name)| {
                let e = b.ellipsoid.filter(|_| b.level == Level::Ellipsoid)?;
                let pi = InertialParams(std::array::from_fn(|k| p[k]));
                let r = crate::moments::check_realizable(&pi, &e, CHECK_TOL);
                (r.consistent && !r.realizable).then(|| name.clone())
            })
            .collect();
        (!outside.is_empty()).then_some(IdentifyWarning::PriorOutsideEllipsoid { bodies: outside })
    }

    /// How the prior enters the objective (default [`Regularizer::Euclidean`];
    /// [`Regularizer::Entropic`] and [`Regularizer::Pullback`] need every
    /// prior body strictly consistent).
    pub fn regularizer(mut self, r: Regularizer) -> Self {
        self.regularizer = r;
        self
    }

    /// The regulariser set.
    pub fn regularizer_kind(&self) -> Regularizer {
        self.regularizer
    }

    /// How the joints' rows are weighted in the fit (default
    /// [`JointWeighting::Equal`](super::JointWeighting::Equal); `Noise`:
    /// weighted least squares, [`super::weighting`]).
    pub fn joint_weighting(mut self, w: super::JointWeighting) -> Self {
        self.joint_weighting = w;
        self
    }

    /// Body `b`'s prior π̂, when the regulariser is on (`weight > 0`).
    pub fn prior_body(&self, b: usize) -> Option<InertialParams> {
        (self.weight > 0.0 && self.prior.len() >= 10 * (b + 1))
            .then(|| InertialParams(std::array::from_fn(|k| self.prior[10 * b + k])))
    }

    /// The pullback prior's factors ([`super::pullback::factors`]) when it
    /// is in the objective; a prior body not strictly consistent is an
    /// error naming it.
    pub(super) fn pullback_factors(
        &self,
    ) -> Result<Option<Vec<nalgebra::SMatrix<f64, 10, 10>>>, IdentifyError> {
        match self.weight > 0.0 && self.regularizer == Regularizer::Pullback {
            true => super::pullback::factors(&self.prior, &self.layout.bodies).map(Some),
            false => Ok(None),
        }
    }

    /// Whether the entropic divergence is in the objective.
    pub(super) fn entropic(&self) -> bool {
        self.weight > 0.0 && self.regularizer == Regularizer::Entropic
    }

    /// Adds the CoM-in-ellipsoid LMI (22) to every constrained body with an ellipsoid.
    pub fn com_lmi(mut self, on: bool) -> Self {
        self.com_lmi = on;
        self.resolve_ellipsoids();
        self
    }

    /// Margin ε of the strict LMIs `⪰ εI` (≥ 0, finite).
    pub fn eps(mut self, eps: f64) -> Result<Self, IdentifyError> {
        self.eps = IdentifyOptions::new(Level::None).with_eps(eps)?.eps;
        Ok(self)
    }

    /// The solver settings of the SDP (validated).
    pub fn settings(mut self, settings: Settings) -> Result<Self, IdentifyError> {
        settings.validate()?;
        self.settings = settings;
        Ok(self)
    }

    /// The memory [`Identification::identify`] may plan for (bytes,
    /// default 8 GiB): a robot and data whose [`crate::identify::cost`] is
    /// beyond it are refused before anything is allocated.
    pub fn max_memory(mut self, bytes: u64) -> Self {
        self.max_memory = bytes;
        self
    }

    /// The memory limit (bytes).
    pub fn memory_limit(&self) -> u64 {
        self.max_memory
    }

    /// Adds the caller's constraints: `f(problem, vars)` runs after the
    /// levels' LMIs and the friction bounds, before the solve.
    pub fn constrain(
        mut self,
        f: impl Fn(&mut Problem, &Vars) -> Result<(), IdentifyError> + 'm,
    ) -> Self {
        self.hooks.push(Box::new(f));
        self
    }

    /// An error naming `what` if this set-up is a free-flyer's (whose
    /// columns are not its tree model's).
    pub(super) fn fixed_base(&self, what: &'static str) -> Result<(), IdentifyError> {
        if !self.model.is_floating() && self.layout == self.model.layout() {
            Ok(())
        } else {
            Err(IdentifyError::FreeFlyerSetUp { what })
        }
    }

    /// The prior fits the model and every body that needs an ellipsoid has one.
    pub(super) fn check(&self) -> Result<(), IdentifyError> {
        let names = self.layout.bodies.clone();
        let nb = names.len();
        let w_m = self.mass_weight();
        if (self.weight > 0.0 || w_m > 0.0) && self.prior.len() != 10 * nb {
            return Err(IdentifyError::PriorLength {
                found: self.prior.len(),
                bodies: nb,
                weight: self.weight,
                mass_weight: w_m,
            });
        }
        for (b, name) in self.bodies.iter().zip(&names) {
            let needs = b.level == Level::Ellipsoid || (self.com_lmi && b.level != Level::None);
            if needs && b.ellipsoid.is_none() {
                return Err(IdentifyError::NoEllipsoid {
                    body: name.clone(),
                    level: b.level,
                });
            }
        }
        Ok(())
    }
}
