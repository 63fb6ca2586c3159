//! The robot description: everything known about a robot besides its
//! kinematics and inertias, in one value, built by one function
//! ([`RobotDescription::new`]) from a model and a sidecar — for a URDF robot
//! and for the built-in leg alike.

use super::bounding::Bounding;
use super::error::DynamicsError;
use super::friction::{Friction, FrictionTerm};
use super::model::Model;
use super::params_file::{FittedEffect, ParamsFile};
use super::sidecar::{Excitation, PriorSpec, Sidecar, SidecarBody, SidecarJoint};
use super::warning::DescriptionWarning;
use crate::moments::{Ellipsoid, InertialParams, Level};
use crate::urdf::mesh::MeshPaths;
use nalgebra::{Matrix3, Vector3};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::PathBuf;
use std::str::FromStr;

/// Placeholder nominal Coulomb friction (N·m or N) of a joint that neither
/// the sidecar nor the URDF describes (reported in [`RobotDescription::warnings`]).
pub const PLACEHOLDER_COULOMB: f64 = 0.5;
/// Placeholder nominal viscous friction (N·m·s/rad or N·s/m), likewise.
pub const PLACEHOLDER_VISCOUS: f64 = 0.1;

/// A robot: its model (kinematics, rotors, its own inertias, frames, tool
/// point, joint limits) and what else is known about it.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotDescription {
    /// Where it came from (a built-in name or the URDF path).
    pub source: String,
    /// The sidecar file it was described with, if any (a URDF robot's).
    pub sidecar: Option<String>,
    /// The model with its own parameters (the built-in's identified values,
    /// a URDF's inertias).
    pub model: Model,
    /// The CAD prior per body (a free-flying base, links, then rotors; body frames): the
    /// sidecar's, else the model's own.
    pub prior: Vec<InertialParams>,
    /// Bounding ellipsoids per body, the geometry's computed when first
    /// needed ([`Self::bounding`]).
    pub bounds: Bounding,
    /// Nominal friction per joint (what the simulator's `coulomb` and
    /// `viscous` effects apply, and `--params true` includes).
    pub friction: Friction,
    /// The default excitation of the simulator.
    pub excitation: Excitation,
    /// Default effect magnitudes by parameter name (the sidecar's
    /// `[effects]`; an effect library checks the names,
    /// [`crate::effects::Library::check_defaults`]).
    pub effects: BTreeMap<String, f64>,
    /// What the identification must respect (the sidecar's `[identify]` and
    /// per-body levels).
    pub identification: IdentificationFacts,
    /// What the description had to fill in (placeholder friction, …).
    pub warnings: Vec<DescriptionWarning>,
    /// The default column mapping of its logs (the sidecar's `[data]
    /// mapping`, resolved against the sidecar's folder).
    pub data_mapping: Option<PathBuf>,
    /// Per joint, its rate and effort limits ([`Self::rates`]).
    pub(super) rates: Vec<super::rates::JointRates>,
}

/// Known facts for the identification: per-body levels (as named in the
/// sidecar; `identify` checks them), a total mass, bodies forced equal.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IdentificationFacts {
    /// Per body (a free-flying base, links, then rotors): its level's name, if the sidecar sets one.
    pub levels: Vec<Option<Level>>,
    /// The total mass of every body (kg).
    pub total_mass: Option<f64>,
    /// Pairs of bodies with the same parameters.
    pub equal: Vec<(String, String)>,
    /// The extra weight `w_m Σ (m − m̂)²` keeping the bodies' masses at the
    /// prior's when the prior is on (≥ 0; `None`: 0), for masses known better
    /// than the rest of the prior.
    pub prior_mass_weight: Option<f64>,
}

/// Which parameters a model gets (`--params`, `--prior`, `--nominal`).
#[derive(Clone, Debug, PartialEq)]
pub enum ParamChoice {
    /// The model's own parameters, no friction.
    Own,
    /// The model's own parameters and the nominal friction (the simulated
    /// robot's truth).
    True,
    /// The CAD prior, no friction.
    Cad,
    /// A parameter file (JSON, [`ParamsFile`]).
    File(PathBuf),
}

impl FromStr for ParamChoice {
    type Err = std::convert::Infallible;

    /// `true`, `cad`, or a path.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s {
            "true" => ParamChoice::True,
            "cad" => ParamChoice::Cad,
            path => ParamChoice::File(PathBuf::from(path)),
        })
    }
}

impl RobotDescription {
    /// The files it was read from, for messages: `source`, or `source
    /// (sidecar PATH)`.
    pub fn origin(&self) -> String {
        match &self.sidecar {
            Some(s) => format!("{} (sidecar {s})", self.source),
            None => self.source.clone(),
        }
    }

    /// Applies a sidecar's description entries to `model` (whose kinematic
    /// entries — gravity, locks, rotors — were applied when it was built);
    /// `urdf` gives `<dynamics>` friction where the sidecar gives none.
    /// `source` names the robot in errors.
    pub fn new(
        source: &str,
        model: Model,
        sidecar: &Sidecar,
        urdf: Option<&crate::urdf::Robot>,
    ) -> Result<Self, DynamicsError> {
        let err = |message: String| DynamicsError::Description {
            source_name: source.to_string(),
            message,
        };
        let model = with_limits(model, sidecar, &err)?;
        let model = match &sidecar.tool {
            Some(t) => model
                .with_tool(&t.frame, t.xyz)
                .map_err(|e| err(format!("[tool]: {e}")))?,
            None => model,
        };
        let (friction, mut warnings) = nominal_friction(&model, sidecar, urdf);
        let model = with_sidecar_law(model, sidecar, &err)?;
        let geometry = urdf.map(crate::urdf::geometry_warnings).unwrap_or_default();
        warnings.extend(geometry.into_iter().map(DescriptionWarning::Geometry));
        warnings.extend(urdf.map(|r| mimic_warnings(&model, r)).unwrap_or_default());
        let bodies = body_entries(&model, &sidecar.bodies, &err)?;
        let prior = bodies
            .iter()
            .enumerate()
            .map(|(k, b)| prior_of(&model, k, *b, &err))
            .collect::<Result<_, _>>()?;
        let bounding = bodies
            .iter()
            .map(|b| bounding_of(*b, &err))
            .collect::<Result<_, _>>()?;
        let excitation = sidecar.excitation.clone().unwrap_or_default();
        check_excitation(&model, &excitation, &err)?;
        let effects = sidecar.effects.clone().unwrap_or_default();
        if let Some((k, v)) = effects.iter().find(|(_, v)| !v.is_finite()) {
            return Err(err(format!("[effects]: '{k}' = {v} is not finite")));
        }
        let identification = identification_facts(&model, sidecar, &bodies, &err)?;
        let rates = super::rates::joint_rates(&model, sidecar, urdf, &err)?;
        Ok(Self {
            source: source.to_string(),
            sidecar: None,
            model,
            prior,
            bounds: Bounding::given(bounding),
            friction,
            excitation,
            effects,
            identification,
            warnings,
            data_mapping: None,
            rates,
        })
    }

    /// Joint `j`'s rate and effort limits: the sidecar's, else the URDF's
    /// (all `None` past the last joint).
    pub fn rates(&self, j: usize) -> super::rates::JointRates {
        self.rates.get(j).copied().unwrap_or_default()
    }

    /// Bounds, from the URDF's geometry, every link body the sidecar gives
    /// no bounding ellipsoid: the one ellipsoid enclosing the bounding
    /// ellipsoids of the shapes of every URDF link merged into the body, in
    /// the body's frame (collision shapes, visual ones where a link has none
    /// or where a collision mesh cannot be used:
    /// [`crate::moments::geometry::geometry_ellipsoids`]). Computed when
    /// first needed ([`Self::bounding`]), meshes found through `paths`.
    pub fn with_urdf_geometry(mut self, robot: &crate::urdf::Robot, paths: MeshPaths) -> Self {
        self.bounds = self.bounds.with_urdf(robot.clone(), paths);
        self
    }

    /// The URDF geometry's bounding ellipsoids are kept in, and taken
    /// from, `cache` across runs ([`crate::moments::cache`]: keyed by the
    /// meshes' and shapes' content).
    pub fn with_bounding_cache(mut self, cache: crate::moments::cache::SolveCache) -> Self {
        self.bounds = self.bounds.with_cache(cache);
        self
    }

    /// Bounding ellipsoids per body (a free-flying base, links, then rotors; body frames;
    /// several: their union; none: unknown): the sidecar's, and the URDF
    /// geometry's, computed on the first call (meshes read, minimum-volume
    /// ellipsoids solved; [`Self::bounding_warnings`] says what could not be
    /// used).
    pub fn bounding(&self) -> &[Vec<Ellipsoid>] {
        self.bounds.get(&self.model)
    }

    /// What the URDF's geometry could not give for [`Self::bounding`] (a
    /// mesh that could not be used, a body with no ellipsoid); computes
    /// the bounding volumes if not yet done.
    pub fn bounding_warnings(&self) -> &[DescriptionWarning] {
        self.bounds.warnings(&self.model)
    }

    /// The prior as one vector (10 per body, a free-flying base, links, then rotors).
    pub fn prior_vector(&self) -> Vec<f64> {
        self.prior.iter().flat_map(|p| p.0).collect()
    }

    /// One bounding ellipsoid per body (the ellipsoid constraint level), or
    /// an error naming the first body that has none or several.
    pub fn single_ellipsoids(&self) -> Result<Vec<Ellipsoid>, DynamicsError> {
        let names = self.model.body_names();
        self.bounding()
            .iter()
            .zip(&names)
            .map(|(b, name)| match b.as_slice() {
                [e] => Ok(*e),
                [] => Err(DynamicsError::Description {
                    source_name: self.source.clone(),
                    message: format!(
                        "body '{name}' has no bounding ellipsoid (give one in the sidecar's [[body]] bounding)"
                    ),
                }),
                many => Err(DynamicsError::Description {
                    source_name: self.source.clone(),
                    message: format!(
                        "body '{name}' has {} bounding ellipsoids; this needs exactly one",
                        many.len()
                    ),
                }),
            })
            .collect()
    }

    /// The model and friction for a parameter choice; a parameter file
    /// with fitted effects (a diagnosis' model) is an error naming them:
    /// a caller that can use them asks [`Self::parameters_with_effects`].
    pub fn parameters(&self, choice: &ParamChoice) -> Result<(Model, Friction), DynamicsError> {
        let (model, friction, effects) = self.parameters_with_effects(choice)?;
        match (effects.is_empty(), choice) {
            (false, ParamChoice::File(path)) => Err(DynamicsError::File {
                path: path.display().to_string(),
                message: format!(
                    "it holds fitted effects ({}) that this use of it cannot apply",
                    FittedEffect::names(&effects)
                ),
            }),
            _ => Ok((model, friction)),
        }
    }

    /// The model, friction and fitted effects (a diagnosis' model file
    /// records them; none otherwise) for a parameter choice.
    pub fn parameters_with_effects(
        &self,
        choice: &ParamChoice,
    ) -> Result<(Model, Friction, Vec<FittedEffect>), DynamicsError> {
        let n = self.model.dof();
        let mut model = self.model.clone();
        let (friction, effects) = match choice {
            ParamChoice::Own => (Friction::zeros(n), vec![]),
            ParamChoice::True => (self.friction.clone(), vec![]),
            ParamChoice::Cad => {
                model.set_params(&self.prior_vector())?;
                (Friction::zeros(n), vec![])
            }
            ParamChoice::File(path) => {
                let file = ParamsFile::read(path)?;
                let f = file.apply(&mut model, &path.display().to_string())?;
                (f, file.effects)
            }
        };
        Ok((model, friction, effects))
    }
}

/// Replaces the limits the sidecar's `[[joint]]` entries give.
fn with_limits(
    mut model: Model,
    sidecar: &Sidecar,
    err: &dyn Fn(String) -> DynamicsError,
) -> Result<Model, DynamicsError> {
    let index: HashMap<&str, usize> = model
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| (j.name.as_str(), i))
        .collect();
    let mut seen = HashSet::new();
    let mut limits = Vec::new();
    for j in &sidecar.joints {
        if !seen.insert(j.name.as_str()) {
            return Err(err(format!("[[joint]] '{}' is given twice", j.name)));
        }
        let i = index.get(j.name.as_str()).copied().ok_or_else(|| {
            err(format!(
                "[[joint]] '{}' is not a moving joint of the model (joints: {})",
                j.name,
                model.joint_names().join(", ")
            ))
        })?;
        for (term, v) in sidecar_friction(j) {
            let lowest = if term.signed() { -1e6 } else { 0.0 };
            if let Some(x) = v
                && !(x.is_finite() && (lowest..=1e6).contains(&x))
            {
                let sign = if term.signed() { "≥ -1e6" } else { "≥ 0" };
                return Err(err(format!(
                    "[[joint]] '{}': {} = {} must be finite, {sign} and ≤ 1e6",
                    j.name,
                    term.name(),
                    crate::numfmt::short(x)
                )));
            }
        }
        if let Some([lo, hi]) = j.limits {
            super::model::check_limits(&j.name, (lo, hi))
                .map_err(|m| err(format!("[[joint]] {m}")))?;
            limits.push((i, (lo, hi)));
        }
    }
    for (i, l) in limits {
        model.joints[i].limits = l;
    }
    Ok(model)
}

/// A warning per moving joint of the model that the URDF couples to another
/// (`<mimic>`): the model has no such coupling, so it moves, is simulated
/// and is identified as a joint of its own.
fn mimic_warnings(model: &Model, urdf: &crate::urdf::Robot) -> Vec<DescriptionWarning> {
    urdf.joints
        .iter()
        .filter_map(|j| Some((j.name.as_str(), j.mimic.as_ref()?.joint.as_str())))
        .filter(|(name, _)| model.joints.iter().any(|m| m.name == *name))
        .map(|(name, leader)| DescriptionWarning::Mimic {
            joint: name.to_string(),
            leader: leader.to_string(),
        })
        .collect()
}

/// Nominal friction per joint: the sidecar's, else the URDF's `<dynamics>`
/// when positive, else a placeholder (with a warning).
fn nominal_friction(
    model: &Model,
    sidecar: &Sidecar,
    urdf: Option<&crate::urdf::Robot>,
) -> (Friction, Vec<DescriptionWarning>) {
    let mut f = Friction::zeros(model.dof());
    let mut placeholders = vec![];
    let side_by_name: HashMap<&str, _> = sidecar
        .joints
        .iter()
        .map(|j| (j.name.as_str(), j))
        .collect();
    let urdf_by_name: HashMap<&str, _> = urdf
        .map(|r| r.joints.iter().map(|j| (j.name.as_str(), j)).collect())
        .unwrap_or_default();
    for (i, joint) in model.joints.iter().enumerate() {
        let side = side_by_name.get(joint.name.as_str());
        let dynamics = urdf_by_name
            .get(joint.name.as_str())
            .and_then(|j| j.dynamics);
        // a zero in a URDF's <dynamics> is commonly "not given": it counts as absent
        let pick = |s: Option<f64>, u: Option<f64>, placeholder: f64| match (s, u) {
            (Some(v), _) => (v, false),
            (None, Some(v)) if v > 0.0 => (v, false),
            _ => (placeholder, true),
        };
        let (c, pc) = pick(
            side.and_then(|j| j.coulomb),
            dynamics.and_then(|d| d.friction),
            PLACEHOLDER_COULOMB,
        );
        let (v, pv) = pick(
            side.and_then(|j| j.viscous),
            dynamics.and_then(|d| d.damping),
            PLACEHOLDER_VISCOUS,
        );
        f.coulomb[i] = c;
        f.viscous[i] = v;
        if pc || pv {
            placeholders.push(joint.name.as_str());
        }
    }
    // the terms beyond viscous and Coulomb that the sidecar gives (zero on
    // the joints it leaves out), at its Stribeck velocity
    for (k, term) in FrictionTerm::ALL.iter().enumerate().skip(2) {
        let given = |j: &SidecarJoint| sidecar_friction(j)[k].1;
        if sidecar.joints.iter().any(|j| given(j).is_some()) {
            *f.coefficients_mut(*term) = (model.joints.iter())
                .map(|m| {
                    side_by_name
                        .get(m.name.as_str())
                        .and_then(|j| given(j))
                        .unwrap_or(0.0)
                })
                .collect();
        }
    }
    f.stribeck_velocity = sidecar.stribeck_velocity;
    let warnings = if placeholders.is_empty() {
        vec![]
    } else {
        vec![DescriptionWarning::PlaceholderFriction {
            joints: placeholders.iter().map(|s| s.to_string()).collect(),
            coulomb: PLACEHOLDER_COULOMB,
            viscous: PLACEHOLDER_VISCOUS,
        }]
    };
    (f, warnings)
}

/// The sidecar's `[[body]]` entry of each body (a free-flying base, links, then rotors), checking
/// that every entry names a body and none is given twice.
fn body_entries<'s>(
    model: &Model,
    bodies: &'s [SidecarBody],
    err: &dyn Fn(String) -> DynamicsError,
) -> Result<Vec<Option<&'s SidecarBody>>, DynamicsError> {
    let names = model.body_names();
    let known: HashSet<&str> = names.iter().map(String::as_str).collect();
    let mut by_name: HashMap<&str, &SidecarBody> = HashMap::new();
    for b in bodies {
        if !known.contains(b.name.as_str()) {
            return Err(err(format!(
                "[[body]] '{}' is not a body of the model (bodies: {})",
                b.name,
                names.join(", ")
            )));
        }
        if by_name.insert(b.name.as_str(), b).is_some() {
            return Err(err(format!("[[body]] '{}' is given twice", b.name)));
        }
    }
    Ok(names
        .iter()
        .map(|n| by_name.get(n.as_str()).copied())
        .collect())
}

/// Body k's prior: the sidecar's, else the model's own.
fn prior_of(
    model: &Model,
    k: usize,
    entry: Option<&SidecarBody>,
    err: &dyn Fn(String) -> DynamicsError,
) -> Result<InertialParams, DynamicsError> {
    let own = InertialParams(std::array::from_fn(|i| model.params()[10 * k + i]));
    let Some((name, spec)) = entry.and_then(|b| b.prior.as_ref().map(|p| (&b.name, p))) else {
        return Ok(own);
    };
    let pi = prior_from_spec(spec).map_err(|m| err(format!("[[body]] '{name}': prior: {m}")))?;
    pi.validate()
        .map_err(|m| err(format!("[[body]] '{name}': prior: {m}")))?;
    Ok(pi)
}

fn prior_from_spec(spec: &PriorSpec) -> Result<InertialParams, String> {
    let com = Vector3::from(spec.com.unwrap_or([0.0; 3]));
    match (spec.params, spec.mass, spec.inertia, spec.box_sides) {
        (Some(p), None, None, None) if spec.com.is_none() => Ok(InertialParams(p)),
        (None, Some(m), Some(i), None) => Ok(InertialParams::from_urdf(m, com.into(), [0.0; 3], i)),
        (None, Some(m), None, Some(s)) => {
            // a solid box about its centre: I = m/12 diag(b² + c², a² + c², a² + b²)
            let s2 = Vector3::from(s).map(|x| x * x);
            let ic = Matrix3::from_diagonal(&Vector3::new(s2.y + s2.z, s2.x + s2.z, s2.x + s2.y))
                * (m / 12.0);
            Ok(InertialParams::from_mass_com_inertia(m, com, ic))
        }
        _ => Err("give exactly one of: params; mass + inertia (+ com); mass + box (+ com)".into()),
    }
}

/// Body's bounding ellipsoids from its sidecar entry.
fn bounding_of(
    entry: Option<&SidecarBody>,
    err: &dyn Fn(String) -> DynamicsError,
) -> Result<Vec<Ellipsoid>, DynamicsError> {
    entry.map_or(Ok(vec![]), |b| {
        b.ellipsoids().map_err(|e| err(e.to_string()))
    })
}

/// Why `m` (kg) cannot be the total mass of `model`, if it cannot: it
/// must be at least a millionth of the mass `model` describes (below that
/// the equality is lost in the solver's tolerance: no robot is left) and at
/// most [`MAX_ABS_PARAM`](crate::moments::MAX_ABS_PARAM) (10⁶ kg, the bound
/// of every inertial parameter; beyond it the SDP's scaling fails). Written
/// `= 1e300: …` for the caller to prefix its name.
pub fn total_mass_refusal(m: f64, model: &Model) -> Option<String> {
    let max = crate::moments::MAX_ABS_PARAM;
    let described: f64 = model.params().iter().step_by(10).sum();
    let min = 1e-6 * described.max(0.0);
    (!(m > min && m > 0.0 && m <= max)).then(|| {
        format!(
            "= {}: must be above a millionth of the robot's described mass ({} kg) and at most {} kg (the bound of every inertial parameter)",
            crate::numfmt::short(m),
            crate::numfmt::sig4(described),
            crate::numfmt::short(max)
        )
    })
}

/// The sidecar's `[identify]` and per-body levels, with the bodies checked.
fn identification_facts(
    model: &Model,
    sidecar: &Sidecar,
    bodies: &[Option<&SidecarBody>],
    err: &dyn Fn(String) -> DynamicsError,
) -> Result<IdentificationFacts, DynamicsError> {
    let names = model.body_names();
    let spec = sidecar.identify.clone().unwrap_or_default();
    if let Some(why) = spec.total_mass.and_then(|m| total_mass_refusal(m, model)) {
        return Err(err(format!("[identify] total_mass {why}")));
    }
    if let Some(w) = spec.prior_mass_weight
        && !(w >= 0.0 && w.is_finite())
    {
        return Err(err(format!(
            "[identify] prior_mass_weight = {w}: must be ≥ 0 and finite"
        )));
    }
    for [a, b] in &spec.equal {
        if a == b {
            return Err(err(format!(
                "[identify] equal: '{a}' with itself says nothing"
            )));
        }
        for n in [a, b] {
            if !names.contains(n) {
                return Err(err(format!(
                    "[identify] equal: '{n}' is not a body of the model (bodies: {})",
                    names.join(", ")
                )));
            }
        }
    }
    Ok(IdentificationFacts {
        levels: bodies.iter().map(|b| b.and_then(|b| b.level)).collect(),
        total_mass: spec.total_mass,
        prior_mass_weight: spec.prior_mass_weight,
        equal: spec
            .equal
            .iter()
            .map(|[a, b]| (a.clone(), b.clone()))
            .collect(),
    })
}

fn check_excitation(
    model: &Model,
    e: &Excitation,
    err: &dyn Fn(String) -> DynamicsError,
) -> Result<(), DynamicsError> {
    match e {
        Excitation::MultiSine(m) => {
            if !(m.harmonics > 0
                && m.harmonics <= 100
                && m.base_hz > 0.0
                && m.base_hz.is_finite()
                && m.range_fraction > 0.0
                && m.range_fraction <= 1.0)
            {
                return Err(err(format!(
                    "[excitation] multi_sine: need 1 ≤ harmonics ≤ 100, base_hz > 0 and 0 < range_fraction ≤ 1, got {m:?}"
                )));
            }
        }
        Excitation::LegShell(_) => {
            if !super::leg_kinematics::has_leg_kinematics(model) {
                return Err(err(format!(
                    "[excitation] leg_shell moves the foot of the built-in {} through its inverse kinematics; this model does not have that leg's joints",
                    super::leg_kinematics::NAME
                )));
            }
        }
    }
    Ok(())
}

/// A sidecar joint's friction coefficients in [`FrictionTerm::ALL`]'s
/// order (`None`: not given).
fn sidecar_friction(j: &SidecarJoint) -> [(FrictionTerm, Option<f64>); 6] {
    let [v, c, o, a, l, s] = FrictionTerm::ALL;
    [
        (v, j.viscous),
        (c, j.coulomb),
        (o, j.offset),
        (a, j.asymmetric),
        (l, j.load),
        (s, j.stribeck),
    ]
}

/// `model` with the friction terms the sidecar gives beyond viscous and
/// Coulomb (on any joint) identified too, at the sidecar's Stribeck
/// velocity: the law a written sidecar carries is the law loaded.
fn with_sidecar_law(
    model: Model,
    sidecar: &Sidecar,
    err: &impl Fn(String) -> DynamicsError,
) -> Result<Model, DynamicsError> {
    let given: Vec<FrictionTerm> = (2..FrictionTerm::ALL.len())
        .filter(|&k| {
            sidecar
                .joints
                .iter()
                .any(|j| sidecar_friction(j)[k].1.is_some())
        })
        .map(|k| FrictionTerm::ALL[k])
        .collect();
    let model = match given.is_empty() {
        true => model,
        false => model.with_friction_terms(&[&FrictionTerm::DEFAULT[..], &given].concat()),
    };
    match sidecar.stribeck_velocity {
        Some(v) => model
            .with_stribeck_velocity(v)
            .map_err(|e| err(format!("stribeck_velocity: {e}"))),
        None => Ok(model),
    }
}
