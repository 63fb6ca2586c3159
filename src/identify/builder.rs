//! The identification problem (25) as a builder open to the caller's
//! constraints: per-body levels and ellipsoids, the prior, solver settings,
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

use super::error::IdentifyError;
use super::problem::{
    IdentifyOptions, Level, MassWeight, Regularizer, Solved, default_settings, parameter_names,
};
use super::reduce::Reduced;
use crate::conic::{AffExpr, Problem, Settings, Status};
use crate::dynamics::{FrictionTerm, Model, RobotDescription};
use crate::moments::{
    Ellipsoid, InertialParams, MomentsError, add_entropic_divergence, lmi::BodyVars,
};
use faer::Mat;

/// A hook: adds constraints to the problem, given every body's and joint's
/// variables.
type Hook<'h> = Box<dyn Fn(&mut Problem, &Vars) -> Result<(), IdentifyError> + 'h>;

/// The variables a hook sees: every body's π (links then rotors, by name)
/// and every joint's friction coefficients. θ is scaled internally; these
/// expressions are in the user's units.
pub struct Vars {
    bodies: Vec<(String, BodyVars)>,
    joints: Vec<String>,
    /// Friction coefficients, `friction[t·n + i]`: term t, joint i.
    friction: Vec<AffExpr>,
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
    /// ([`FrictionTerm::unit`]).
    pub fn friction(&self, term: FrictionTerm, joint: &str) -> Result<AffExpr, IdentifyError> {
        let i = self
            .joints
            .iter()
            .position(|n| n == joint)
            .ok_or_else(|| unknown("joint", joint, self.joints.iter().map(String::as_str)))?;
        Ok(self.friction[term.index() * self.joints.len() + i].clone())
    }

    /// Joint `joint`'s viscous coefficient B (N·m·s/rad).
    pub fn viscous(&self, joint: &str) -> Result<AffExpr, IdentifyError> {
        self.friction(FrictionTerm::Viscous, joint)
    }

    /// Joint `joint`'s Coulomb coefficient B_c (N·m).
    pub fn coulomb(&self, joint: &str) -> Result<AffExpr, IdentifyError> {
        self.friction(FrictionTerm::Coulomb, joint)
    }

    /// The sum of every body's mass (links and rotors), kg.
    pub fn total_mass(&self) -> AffExpr {
        self.bodies.iter().map(|(_, b)| b.mass()).sum()
    }
}

pub(super) fn unknown<'a>(
    what: &'static str,
    name: &str,
    valid: impl Iterator<Item = &'a str>,
) -> IdentifyError {
    IdentifyError::UnknownName {
        what,
        name: name.to_string(),
        valid: valid.collect::<Vec<_>>().join(", "),
    }
}

/// One body's constraint set.
#[derive(Clone, Copy, Debug, PartialEq)]
struct BodySpec {
    level: Level,
    ellipsoid: Option<Ellipsoid>,
}

/// The identification problem (25) of one model, to be solved on reduced
/// data: per-body constraint levels (default: consistent), bounding
/// ellipsoids, a prior, solver settings and the caller's constraints.
pub struct Identification<'m> {
    model: &'m Model,
    common: Level,
    bodies: Vec<BodySpec>,
    weight: f64,
    mass_weight: MassWeight,
    prior: Vec<f64>,
    regularizer: Regularizer,
    com_lmi: bool,
    eps: f64,
    settings: Settings,
    max_memory: u64,
    hooks: Vec<Hook<'m>>,
}

impl<'m> Identification<'m> {
    /// Every body consistent, no prior, default solver settings.
    pub fn new(model: &'m Model) -> Self {
        Self {
            model,
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
            com_lmi: false,
            eps: 0.0,
            settings: default_settings(),
            max_memory: crate::identify::reduce::DEFAULT_MAX_MEMORY_BYTES,
            hooks: vec![],
        }
    }

    /// The set-up of [`IdentifyOptions`] (one level for every body).
    pub fn from_options(model: &'m Model, opts: &IdentifyOptions) -> Result<Self, IdentifyError> {
        let nb = model.num_bodies();
        let mut s = Self::new(model).level_all(opts.level);
        if let Some(e) = &opts.ellipsoids {
            if e.len() != nb {
                return Err(IdentifyError::Option {
                    option: "ellipsoids",
                    message: format!(
                        "{} bounding ellipsoids for {nb} bodies; give one per body",
                        e.len()
                    ),
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

    /// A robot's set-up: `level` for every body, its CAD prior with weight
    /// `weight`, its bounding ellipsoids where it has exactly one per body,
    /// and the per-body levels, constraints and masses' extra weight of its
    /// sidecar (the last used with the Euclidean prior on, [`Self::mass_weight`]).
    pub fn for_robot(
        robot: &'m RobotDescription,
        level: Level,
        weight: f64,
    ) -> Result<Self, IdentifyError> {
        let model = &robot.model;
        let mut s = Self::new(model)
            .level_all(level)
            .prior(weight, robot.prior_vector())?;
        for (b, e) in s.bodies.iter_mut().zip(&robot.bounding) {
            if let [e] = e.as_slice() {
                b.ellipsoid = Some(*e);
            }
        }
        super::robot_facts::apply(s, robot)
    }

    /// The constraint level of every body.
    pub fn level_all(mut self, level: Level) -> Self {
        self.common = level;
        self.bodies.iter_mut().for_each(|b| b.level = level);
        self
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
        let names = self.model.body_names();
        names
            .iter()
            .position(|n| n == body)
            .ok_or_else(|| unknown("body", body, names.iter().map(String::as_str)))
    }

    /// The constraint level of one body (by name).
    pub fn level(mut self, body: &str, level: Level) -> Result<Self, IdentifyError> {
        let k = self.body_index(body)?;
        self.bodies[k].level = level;
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
        let nb = self.model.num_bodies();
        if o.weight > 0.0 && o.prior.len() != 10 * nb {
            return Err(IdentifyError::Option {
                option: "prior",
                message: format!(
                    "{} numbers for {nb} bodies (10 per body) with weight {weight}",
                    o.prior.len()
                ),
            });
        }
        self.weight = o.weight;
        self.prior = o.prior;
        Ok(self)
    }

    /// An extra `w_m Σ_b (m_b − m̂_b)²` toward the prior's masses, every
    /// body's (links and rotors), added to the regulariser of either kind;
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
        self.mass_weight.explicit = Some(super::problem::nonnegative(
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
    pub(crate) fn mass_weight_warning(&self) -> Option<String> {
        let (w_m, w) = (self.mass_weight(), self.weight);
        (w_m > 0.0 && self.regularizer == Regularizer::Euclidean && w_m < 100.0 * w).then(|| {
            format!(
                "the masses' extra weight {w_m:e} is not ≫ the prior's weight {w:e} (ratio {}, \
                 under 100): the masses are not held at the prior's",
                (w_m / w * 1e3).round() / 1e3
            )
        })
    }

    /// A warning naming the bodies at the ellipsoid level whose prior is
    /// consistent but not density realizable in their bounding ellipsoid
    /// (`tr(J(π̂) Q) < 0`): the fit cannot stay at the prior there.
    pub(crate) fn prior_outside_warning(&self) -> Option<String> {
        if !(self.weight > 0.0 || self.mass_weight() > 0.0)
            || self.prior.len() != 10 * self.bodies.len()
        {
            return None;
        }
        let names = self.model.body_names();
        let outside: Vec<&str> = (self.bodies.iter().zip(self.prior.chunks_exact(10)))
            .zip(&names)
            .filter_map(|((b, p), name)| {
                let e = b.ellipsoid.filter(|_| b.level == Level::Ellipsoid)?;
                let pi = InertialParams(std::array::from_fn(|k| p[k]));
                let r = crate::moments::check_realizable(&pi, &e, super::result::CHECK_TOL);
                (r.consistent && !r.realizable).then_some(name.as_str())
            })
            .collect();
        (!outside.is_empty()).then(|| {
            format!(
                "the prior is not density realizable in the bounding ellipsoid of {} \
                 (tr(J(π̂) Q) < 0): the identified bodies cannot stay at the prior there \
                 (`momentlmi check` shows the CAD inertias against the geometry)",
                outside.join(", ")
            )
        })
    }

    /// How the prior enters the objective (default [`Regularizer::Euclidean`];
    /// [`Regularizer::Entropic`] needs every prior body strictly consistent).
    pub fn regularizer(mut self, r: Regularizer) -> Self {
        self.regularizer = r;
        self
    }

    /// The regulariser set.
    pub fn regularizer_kind(&self) -> Regularizer {
        self.regularizer
    }

    /// Body `b`'s prior π̂, when the regulariser is on (`weight > 0`).
    pub fn prior_body(&self, b: usize) -> Option<InertialParams> {
        (self.weight > 0.0 && self.prior.len() >= 10 * (b + 1))
            .then(|| InertialParams(std::array::from_fn(|k| self.prior[10 * b + k])))
    }

    /// Whether the entropic divergence is in the objective.
    fn entropic(&self) -> bool {
        self.weight > 0.0 && self.regularizer == Regularizer::Entropic
    }

    /// Adds the CoM-in-ellipsoid LMI (22) to every constrained body with an ellipsoid.
    pub fn com_lmi(mut self, on: bool) -> Self {
        self.com_lmi = on;
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

    /// The prior fits the model and every body that needs an ellipsoid has one.
    fn check(&self) -> Result<(), IdentifyError> {
        let names = self.model.body_names();
        let nb = names.len();
        let w_m = self.mass_weight();
        if (self.weight > 0.0 || w_m > 0.0) && self.prior.len() != 10 * nb {
            return Err(IdentifyError::Option {
                option: "prior",
                message: format!(
                    "{} numbers for {nb} bodies (10 per body) with weight {}{}",
                    self.prior.len(),
                    self.weight,
                    if w_m > 0.0 {
                        format!(" and prior mass weight {w_m}")
                    } else {
                        String::new()
                    }
                ),
            });
        }
        for (b, name) in self.bodies.iter().zip(&names) {
            let needs = b.level == Level::Ellipsoid || (self.com_lmi && b.level != Level::None);
            if needs && b.ellipsoid.is_none() {
                return Err(IdentifyError::Option {
                    option: "ellipsoids",
                    message: format!(
                        "body '{name}' has no bounding ellipsoid for its {} level",
                        b.level.as_str()
                    ),
                });
            }
        }
        Ok(())
    }

    /// Solves on reduced data.
    pub fn solve(&self, red: &Reduced) -> Result<Solved, IdentifyError> {
        let model = self.model;
        let nb = model.num_bodies();
        let p = crate::dynamics::regressor_columns(model);
        if red.p != p {
            return Err(IdentifyError::Columns {
                expected: p,
                found: red.p,
            });
        }
        if red.samples == 0 {
            return Err(IdentifyError::NoTrainingData {
                samples: 0,
                torques: 0,
            });
        }
        self.check()?;
        let (r, d) = red.r_d()?;
        let (rank, unidentifiable) = identifiability(&r, &parameter_names(model))?;
        let ns = red.samples as f64;
        let t0 = std::time::Instant::now();
        let reg = Prior {
            weight: self.weight,
            mass_weight: self.mass_weight(),
            values: self.prior.as_slice(),
        };
        let direct = self.hooks.is_empty() && !self.entropic();
        if direct && self.bodies.iter().all(|b| b.level == Level::None) {
            return Ok(Solved {
                theta: solve_direct(&r, &d, ns, reg, nb)?,
                bodies: model.body_names(),
                joints: model.joint_names().iter().map(|s| s.to_string()).collect(),
                status: Status::Solved,
                iterations: 0,
                solve_time_s: t0.elapsed().as_secs_f64(),
                unidentifiable,
                rank,
            });
        }
        let (mut prob, theta) = scaled_problem(&r, &d, ns, reg, nb, !self.entropic())?;
        let vars = self.vars(&theta);
        let bodies: Vec<BodyVars> = vars.bodies.iter().map(|(_, b)| b.clone()).collect();
        self.add_body_constraints(&mut prob, &bodies, &model.body_names())?;
        if self.entropic() {
            self.add_entropic(&mut prob, &bodies, &model.body_names())?;
        }
        prob.add_nonneg(theta[10 * nb..].to_vec())?; // every friction coefficient ≥ 0
        for h in &self.hooks {
            h(&mut prob, &vars)?;
        }
        let sol = prob.solve(&self.settings)?;
        match sol.status {
            s if s.is_solved() => Ok(Solved {
                theta: sol.eval_all(&theta)?,
                bodies: model.body_names(),
                joints: model.joint_names().iter().map(|s| s.to_string()).collect(),
                status: sol.status,
                iterations: sol.iterations,
                solve_time_s: sol.setup_time_s + sol.solve_time_s,
                unidentifiable,
                rank,
            }),
            s if s.is_primal_infeasible() => Err(self.explain_infeasible(s)?),
            s => Err(IdentifyError::Solver(s)),
        }
    }

    /// The hook's view of θ.
    fn vars(&self, theta: &[AffExpr]) -> Vars {
        let model = self.model;
        let nb = model.num_bodies();
        Vars {
            bodies: model
                .body_names()
                .into_iter()
                .enumerate()
                .map(|(b, name)| {
                    (
                        name,
                        BodyVars::from_exprs(std::array::from_fn(|k| theta[10 * b + k].clone())),
                    )
                })
                .collect(),
            joints: model.joint_names().iter().map(|j| j.to_string()).collect(),
            friction: theta[10 * nb..].to_vec(),
        }
    }

    /// Each body's level: `I ⪰ εI`, `J ⪰ εI`, and `tr(JQ) ≥ 0` (+ the CoM LMI).
    fn add_body_constraints(
        &self,
        prob: &mut Problem,
        bodies: &[BodyVars],
        names: &[String],
    ) -> Result<(), IdentifyError> {
        for ((spec, body), name) in self.bodies.iter().zip(bodies).zip(names) {
            let id = match spec.level {
                Level::None => continue,
                Level::Semi => prob.add_psd_eps(&body.spatial_inertia(), self.eps)?,
                Level::Consistent | Level::Ellipsoid => body.add_consistent_eps(prob, self.eps)?,
            };
            prob.set_name(id, &format!("{} LMI of body '{name}'", spec.level.as_str()))?;
            if let Some(e) = spec.ellipsoid {
                if spec.level == Level::Ellipsoid {
                    let c = prob.add_ge(body.trace_jq(&e), 0.0)?;
                    prob.set_name(c, &format!("tr(JQ) ≥ 0 of body '{name}'"))?;
                }
                if self.com_lmi {
                    body.add_com_in(prob, &e)?;
                }
            }
        }
        Ok(())
    }

    /// The objective's `w Σ_b d(J_b ‖ Ĵ_b)`; a prior body that is not
    /// strictly consistent is an error naming it.
    fn add_entropic(
        &self,
        prob: &mut Problem,
        bodies: &[BodyVars],
        names: &[String],
    ) -> Result<(), IdentifyError> {
        let mut total = AffExpr::zero();
        for (b, (body, name)) in bodies.iter().zip(names).enumerate() {
            // `check` has matched the prior to the bodies when the weight is on
            let prior = self.prior_body(b).ok_or_else(|| IdentifyError::Option {
                option: "prior",
                message: format!("body '{name}' has no prior for the entropic regulariser"),
            })?;
            let term = add_entropic_divergence(prob, body, &prior).map_err(|e| match e {
                MomentsError::NotPositiveSemidefinite { min_eig } => IdentifyError::Option {
                    option: "prior",
                    message: format!(
                        "body '{name}': its prior pseudo-inertia is not positive definite (smallest eigenvalue {min_eig:.3e}); the entropic regulariser needs a strictly consistent prior (a URDF's inertias: `momentlmi check --repair`; a parameter file: correct that body), or use --regularizer euclidean"
                    ),
                },
                MomentsError::Conic(e) => IdentifyError::Conic(e),
                e => IdentifyError::Option {
                    option: "prior",
                    message: format!("body '{name}': {e}"),
                },
            })?;
            total += term.divergence * self.weight;
        }
        prob.minimize(total);
        Ok(())
    }

    /// After an infeasible solve: the first body whose own constraint set is
    /// empty, else the status itself (the caller's constraints conflict).
    fn explain_infeasible(&self, status: Status) -> Result<IdentifyError, IdentifyError> {
        for (b, name) in self.model.body_names().iter().enumerate() {
            let mut q = Problem::new();
            let v = BodyVars::new(&mut q, name);
            let alone = Identification {
                model: self.model,
                common: self.common,
                bodies: vec![self.bodies[b]],
                weight: 0.0,
                mass_weight: MassWeight::default(),
                prior: vec![],
                regularizer: Regularizer::Euclidean,
                com_lmi: self.com_lmi,
                eps: self.eps,
                settings: self.settings.clone(),
                max_memory: self.max_memory,
                hooks: vec![],
            };
            alone.add_body_constraints(&mut q, &[v], std::slice::from_ref(name))?;
            if q.solve(&self.settings)?.status.is_primal_infeasible() {
                return Ok(IdentifyError::InfeasibleBody { body: name.clone() });
            }
        }
        Ok(IdentifyError::Solver(status))
    }
}

/// Rank and unexcited directions of R (columns scaled to unit norm).
fn identifiability(r: &Mat<f64>, names: &[String]) -> Result<(usize, Vec<String>), IdentifyError> {
    let p = r.ncols();
    let scale: Vec<f64> = (0..p)
        .map(|j| {
            (0..r.nrows())
                .map(|i| r[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    let mut rs = Mat::<f64>::zeros(r.nrows().max(p), p);
    for j in 0..p {
        let s = if scale[j] > 0.0 { 1.0 / scale[j] } else { 0.0 };
        for i in 0..r.nrows() {
            rs[(i, j)] = r[(i, j)] * s;
        }
    }
    let svd = rs.svd().map_err(|_| IdentifyError::Factorisation {
        what: "SVD of the reduced regressor (identifiability)",
    })?;
    let s = svd.S().column_vector();
    let smax = (0..s.nrows()).map(|i| s[i]).fold(0.0, f64::max);
    let tol = 1e-8 * smax.max(f64::MIN_POSITIVE);
    let rank = (0..s.nrows()).filter(|&i| s[i] > tol).count();
    let v = svd.V();
    let mut dirs = Vec::new();
    for k in 0..p {
        if k < s.nrows() && s[k] > tol {
            continue;
        }
        let mut comp: Vec<(usize, f64)> = (0..p).map(|j| (j, v[(j, k)])).collect();
        comp.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        let terms: Vec<String> = comp
            .iter()
            .take(3)
            .filter(|c| c.1.abs() > 0.05)
            .map(|&(j, c)| format!("{c:+.2}·{}", names[j]))
            .collect();
        dirs.push(terms.join(" "));
    }
    Ok((rank, dirs))
}

/// The prior's terms of the objective: `w ‖π − π̂‖²` (Euclidean) and the
/// masses' `w_m Σ_b (m_b − m̂_b)²`.
#[derive(Clone, Copy)]
struct Prior<'a> {
    weight: f64,
    mass_weight: f64,
    values: &'a [f64],
}

impl Prior<'_> {
    /// Whether any term is on.
    fn on(&self) -> bool {
        self.weight > 0.0 || self.mass_weight > 0.0
    }

    /// The weight of `(π_k − π̂_k)²` in the objective (k over 10 per body,
    /// the mass first): the masses' extra weight, plus `weight` when the
    /// regulariser is the Euclidean one.
    fn weight_of(&self, k: usize, euclidean: bool) -> f64 {
        let mass = if k % 10 == 0 { self.mass_weight } else { 0.0 };
        mass + if euclidean { self.weight } else { 0.0 }
    }
}

/// The unconstrained level: `min ‖[R/√ns; √W E] θ − [d/√ns; √W π̂]‖²`
/// (`W` the [`Prior`]'s weights), minimum norm, by SVD (so noise-free data
/// are fitted to round-off).
fn solve_direct(
    r: &Mat<f64>,
    d: &[f64],
    ns: f64,
    reg: Prior,
    nb: usize,
) -> Result<Vec<f64>, IdentifyError> {
    let (p, prior) = (r.ncols(), reg.values);
    let extra = if reg.on() { 10 * nb } else { 0 };
    let rows = r.nrows() + extra;
    let mut a = Mat::<f64>::zeros(rows.max(p), p);
    let mut b = Mat::<f64>::zeros(rows.max(p), 1);
    for i in 0..r.nrows() {
        for j in 0..p {
            a[(i, j)] = r[(i, j)] / ns.sqrt();
        }
        b[(i, 0)] = d[i] / ns.sqrt();
    }
    for k in 0..extra {
        let w = reg.weight_of(k, true).sqrt();
        a[(r.nrows() + k, k)] = w;
        b[(r.nrows() + k, 0)] = w * prior[k];
    }
    let svd = a.svd().map_err(|_| IdentifyError::Factorisation {
        what: "SVD of the least-squares problem",
    })?;
    let s = svd.S().column_vector();
    let smax = (0..s.nrows()).map(|i| s[i]).fold(0.0, f64::max);
    let u = svd.U();
    let v = svd.V();
    let mut theta = vec![0.0; p];
    for k in 0..s.nrows() {
        if s[k] <= 1e-13 * smax {
            continue;
        }
        let c: f64 = (0..a.nrows()).map(|i| u[(i, k)] * b[(i, 0)]).sum::<f64>() / s[k];
        for j in 0..p {
            theta[j] += c * v[(j, k)];
        }
    }
    Ok(theta)
}

/// The constrained levels' SDP in scaled variables θ = D z (D = 1 / the
/// column norms of R, 1 for unexcited columns), with its objective (the
/// Euclidean prior's squares when `prior_squares`); returns the problem and
/// θ as expressions of z.
fn scaled_problem(
    r: &Mat<f64>,
    d: &[f64],
    ns: f64,
    reg: Prior,
    nb: usize,
    prior_squares: bool,
) -> Result<(Problem, Vec<AffExpr>), IdentifyError> {
    let prior = reg.values;
    let p = r.ncols();
    let dscale: Vec<f64> = (0..p)
        .map(|j| {
            let c = (0..r.nrows())
                .map(|i| r[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt()
                / ns.sqrt();
            if c > 1e-12 { 1.0 / c } else { 1.0 }
        })
        .collect();
    let mut prob = Problem::new();
    let z = prob.vector("z", p);
    let theta: Vec<AffExpr> = (0..p).map(|j| AffExpr::term(z[j], dscale[j])).collect();
    let residual_rows: Vec<AffExpr> = (0..r.nrows())
        .map(|i| {
            let mut e = AffExpr::constant(-d[i]);
            for j in 0..p {
                if r[(i, j)] != 0.0 {
                    e.add_term(z[j], r[(i, j)] * dscale[j]);
                }
            }
            e
        })
        .collect();
    if reg.on() {
        prob.add_squares(1.0 / ns, residual_rows);
        for k in 0..10 * nb {
            let w = reg.weight_of(k, prior_squares);
            if w > 0.0 {
                prob.add_square(w, theta[k].clone() - prior[k]);
            }
        }
    } else {
        // Without regularisation, minimise the residual norm itself (same
        // minimiser): the solver's gap tolerance then bounds ‖r‖, not ‖r‖²,
        // so noise-free data are fitted to ~1e-9 instead of ~1e-5.
        let t = prob.scalar("residual_norm");
        prob.add_soc(
            t,
            residual_rows
                .into_iter()
                .map(|e| e * (1.0 / ns.sqrt()))
                .collect(),
        )?;
        prob.minimize(t);
    }
    Ok((prob, theta))
}
