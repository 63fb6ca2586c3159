//! The sidecar (TOML): what a URDF cannot say about a robot. Every field is
//! optional and unknown keys are errors; `docs/robots.md` shows a whole file.
//!
//! Two kinds of entries:
//! - kinematics, read while the model is built from the URDF
//!   ([`super::urdf`]): `gravity`, `lock`, `[[rotor]]`;
//! - the robot description ([`super::RobotDescription`]), read the same way
//!   for a URDF robot and for the built-in leg (whose own sidecar is
//!   `src/dynamics/cheetah3-leg.toml`): `[tool]`, `[[joint]]` (nominal
//!   friction, limits, rate and effort limits), `[[body]]` (CAD prior, bounding ellipsoids, an
//!   identification level), `[excitation]`, `[effects]` (default effect
//!   magnitudes), `[identify]` (known total mass, bodies forced equal, the
//!   masses' extra weight toward the prior).

use super::error::{DynamicsError, read_text};
use super::leg_kinematics::Shell;
use crate::moments::{Ellipsoid, Level, rpy_rotation};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The sidecar file.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sidecar {
    /// Gravity in the base frame (m/s²); default (0, 0, −9.81).
    #[serde(default, deserialize_with = "exact::opt")]
    pub gravity: Option<[f64; 3]>,
    /// Movable joints to lock at 0 and merge like fixed joints.
    #[serde(default)]
    pub lock: Vec<String>,
    /// The Stribeck velocity v_s (rad/s) of the joints' `stribeck` friction
    /// (default [`crate::dynamics::DEFAULT_STRIBECK_VELOCITY`]).
    pub stribeck_velocity: Option<f64>,
    /// Rotors.
    #[serde(default, rename = "rotor")]
    pub rotors: Vec<SidecarRotor>,
    /// The tool (payload) point.
    pub tool: Option<SidecarTool>,
    /// Per-joint facts: nominal friction, limits.
    #[serde(default, rename = "joint")]
    pub joints: Vec<SidecarJoint>,
    /// Per-body facts: CAD prior, bounding ellipsoids.
    #[serde(default, rename = "body")]
    pub bodies: Vec<SidecarBody>,
    /// The default excitation of `simulate`.
    pub excitation: Option<Excitation>,
    /// Default effect magnitudes of `simulate`, by parameter name (over the
    /// effects' nominal values; the names are checked against an effect
    /// library, [`crate::effects::Library::check_defaults`]).
    pub effects: Option<BTreeMap<String, f64>>,
    /// Known facts the identification must respect.
    pub identify: Option<SidecarIdentify>,
    /// How this robot's logs are read.
    pub data: Option<SidecarData>,
    /// The robot's root is free (a legged robot, a drone): the CLI loads it
    /// as a floating base (as `--floating-base`), and standing simulations
    /// put these feet on force plates in this stance.
    pub floating_base: Option<SidecarFloating>,
}

/// `[floating_base]`: the root link is a free-flyer base
/// (docs/floating-base.md).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidecarFloating {
    /// Contact frames (URDF links) that stand on force plates in
    /// `simulate --contacts standing`.
    #[serde(default)]
    pub feet: Vec<String>,
    /// The standing posture: joint positions (rad, m) by joint name; joints
    /// not named are at 0.
    #[serde(default)]
    pub stance: BTreeMap<String, f64>,
}

/// `[data]`: how this robot's logs are read.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidecarData {
    /// The default column mapping (a TOML file, relative to the sidecar;
    /// docs/inputs.md, "Column mappings").
    pub mapping: Option<String>,
}

/// `[identify]`: constraints the identification adds for this robot, and
/// how firmly it holds the prior's masses.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidecarIdentify {
    /// The robot's total mass (kg): the sum over every body, links and rotors.
    pub total_mass: Option<f64>,
    /// Pairs of bodies with the same parameters (each in its own frame).
    #[serde(default, deserialize_with = "exact::vec")]
    pub equal: Vec<[String; 2]>,
    /// The extra weight keeping every body's mass at the prior's (the
    /// identification's `prior_mass_weight`, used with the Euclidean prior
    /// on unless the caller sets one): for CAD masses trusted more than the
    /// rest of the prior (weighed parts).
    pub prior_mass_weight: Option<f64>,
}

/// One rotor.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidecarRotor {
    /// The driven joint.
    pub joint: String,
    /// Rotor name (default `<joint>_rotor`).
    pub name: Option<String>,
    /// Gear ratio N (default: the joint's `<transmission>` reduction).
    pub gear_ratio: Option<f64>,
    /// Rotor frame origin in the joint's parent body frame (default: the joint frame's).
    #[serde(default, deserialize_with = "exact::opt")]
    pub xyz: Option<[f64; 3]>,
    /// Rotor frame orientation, roll-pitch-yaw (default: the joint frame's).
    #[serde(default, deserialize_with = "exact::opt")]
    pub rpy: Option<[f64; 3]>,
    /// Spin axis in the rotor frame (default: the joint axis).
    #[serde(default, deserialize_with = "exact::opt")]
    pub axis: Option<[f64; 3]>,
    /// Inertial parameters in the paper's order, rotor frame.
    #[serde(default, deserialize_with = "exact::opt")]
    pub params: Option<[f64; 10]>,
    /// Or: mass (kg) …
    pub mass: Option<f64>,
    /// … CoM in the rotor frame (m) …
    #[serde(default, deserialize_with = "exact::opt")]
    pub com: Option<[f64; 3]>,
    /// … and inertia about the CoM `[ixx, ixy, ixz, iyy, iyz, izz]` (kg·m²).
    #[serde(default, deserialize_with = "exact::opt")]
    pub inertia: Option<[f64; 6]>,
}

/// The tool point: where a payload sits.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidecarTool {
    /// A frame of the model: a URDF link name (merged links included) or a
    /// body name.
    pub frame: String,
    /// The point in that frame (m); default its origin.
    #[serde(default, deserialize_with = "exact::array")]
    pub xyz: [f64; 3],
}

/// One joint's facts.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SidecarJoint {
    /// The joint.
    pub name: String,
    /// Nominal Coulomb friction B_c (N·m or N).
    pub coulomb: Option<f64>,
    /// Nominal viscous friction B (N·m·s/rad or N·s/m).
    pub viscous: Option<f64>,
    /// Nominal torque offset c (N·m or N; either sign).
    pub offset: Option<f64>,
    /// Nominal Coulomb asymmetry a (N·m or N; either sign).
    pub asymmetric: Option<f64>,
    /// Nominal load-friction coefficient μ (per N·m of the rigid torque).
    pub load: Option<f64>,
    /// Nominal Stribeck peak F_s (N·m or N; either sign), at the sidecar's
    /// `stribeck_velocity`.
    pub stribeck: Option<f64>,
    /// Position limits `[lower, upper]` (rad or m), replacing the URDF's; they
    /// bound the default excitation.
    #[serde(default, deserialize_with = "exact::opt")]
    pub limits: Option<[f64; 2]>,
    /// Largest |q̇| (rad/s or m/s), replacing the URDF's `<limit velocity>`.
    pub max_velocity: Option<f64>,
    /// Largest |q̈| (rad/s² or m/s²); a URDF has none.
    pub max_acceleration: Option<f64>,
    /// Largest |τ| (N·m or N), replacing the URDF's `<limit effort>`.
    pub max_effort: Option<f64>,
}

/// One body's facts (a link by its URDF link name, or a rotor by its name).
#[derive(Clone, Debug, Deserialize)]
#[serde(try_from = "RawBody")]
pub struct SidecarBody {
    /// The body.
    pub name: String,
    /// The CAD prior (default: the model's own parameters).
    pub prior: Option<PriorSpec>,
    /// Bounding ellipsoids in the body frame (several: their union).
    pub bounding: Vec<EllipsoidSpec>,
    /// This body's identification constraint level, instead of the one
    /// asked for all bodies (read from `none`, `semi`, `consistent`,
    /// `ellipsoid`: any other name is an error naming the body).
    pub level: Option<Level>,
}

/// A `[[body]]` as written, its level a name.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBody {
    name: String,
    prior: Option<PriorSpec>,
    #[serde(default)]
    bounding: Vec<EllipsoidSpec>,
    level: Option<String>,
}

impl TryFrom<RawBody> for SidecarBody {
    type Error = String;

    /// The body with its level parsed (the error names the body and the
    /// accepted levels; the sidecar reader adds the file and the line).
    fn try_from(b: RawBody) -> Result<Self, String> {
        let level = b
            .level
            .map(|l| {
                l.parse::<Level>()
                    .map_err(|e| format!("[[body]] '{}': level {e}", b.name))
            })
            .transpose()?;
        Ok(Self {
            name: b.name,
            prior: b.prior,
            bounding: b.bounding,
            level,
        })
    }
}

/// A prior in one of three forms: `params` (the paper's order, body frame);
/// or `mass` + `com` + `inertia` (about the CoM, body axes,
/// `[ixx, ixy, ixz, iyy, iyz, izz]`); or `mass` + `com` + `box` (a solid box
/// with those side lengths, centred at the CoM, body axes).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PriorSpec {
    /// π in the paper's order (kg, kg·m, kg·m²).
    #[serde(default, deserialize_with = "exact::opt")]
    pub params: Option<[f64; 10]>,
    /// Mass (kg).
    pub mass: Option<f64>,
    /// CoM in the body frame (m); default the origin.
    #[serde(default, deserialize_with = "exact::opt")]
    pub com: Option<[f64; 3]>,
    /// Inertia about the CoM (kg·m²).
    #[serde(default, deserialize_with = "exact::opt")]
    pub inertia: Option<[f64; 6]>,
    /// Side lengths of a solid box (m).
    #[serde(default, rename = "box", deserialize_with = "exact::opt")]
    pub box_sides: Option<[f64; 3]>,
}

/// An ellipsoid `{ center, semi_axes, rpy }` in the body frame (m, rad).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EllipsoidSpec {
    /// Centre (m); default the origin.
    #[serde(default, deserialize_with = "exact::array")]
    pub center: [f64; 3],
    /// Semi-axes (m), > 0.
    #[serde(deserialize_with = "exact::array")]
    pub semi_axes: [f64; 3],
    /// Orientation of the axes, roll-pitch-yaw (rad); default aligned.
    #[serde(default, deserialize_with = "exact::array")]
    pub rpy: [f64; 3],
}

impl SidecarBody {
    /// Its bounding ellipsoids (`[]` without any); the error names the body.
    pub fn ellipsoids(&self) -> Result<Vec<Ellipsoid>, DynamicsError> {
        self.bounding
            .iter()
            .map(|e| e.ellipsoid())
            .collect::<Result<_, _>>()
            .map_err(|source| DynamicsError::Bounding {
                body: self.name.clone(),
                source,
            })
    }
}

impl EllipsoidSpec {
    /// The ellipsoid (an error when a semi-axis is not positive or a number
    /// not finite).
    pub fn ellipsoid(&self) -> Result<Ellipsoid, crate::moments::MomentsError> {
        Ellipsoid::with_rotation(
            Vector3::from(self.center),
            Vector3::from(self.semi_axes),
            rpy_rotation(self.rpy),
        )
    }
}

/// The default excitation of `simulate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Excitation {
    /// A random multi-sine per joint inside its limits (any robot).
    MultiSine(MultiSine),
    /// The paper's foot-on-an-ellipsoidal-shell motion through the
    /// `cheetah3-leg`'s inverse kinematics (that leg's kinematics only).
    LegShell(Shell),
}

/// `qⱼ(t) = cⱼ + Σₖ aⱼₖ sin(k ω t) + bⱼₖ cos(k ω t)` with random
/// coefficients (per seed) scaled to a fraction of each joint's range.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MultiSine {
    /// Number of harmonics.
    pub harmonics: usize,
    /// Base frequency ω/2π (Hz).
    pub base_hz: f64,
    /// The motion stays inside this fraction of each joint's range (±1 rad
    /// about 0 for an unlimited joint), in (0, 1].
    pub range_fraction: f64,
}

impl Default for MultiSine {
    fn default() -> Self {
        Self {
            harmonics: 5,
            base_hz: 0.2,
            range_fraction: 0.9,
        }
    }
}

impl Default for Excitation {
    fn default() -> Self {
        Excitation::MultiSine(MultiSine::default())
    }
}

impl Sidecar {
    /// Parses sidecar text; `path` names it in errors.
    pub fn parse(text: &str, path: &str) -> Result<Self, DynamicsError> {
        toml::from_str(text).map_err(|e| DynamicsError::File {
            path: path.to_string(),
            message: format!("invalid sidecar: {e}"),
        })
    }

    /// Reads a sidecar file.
    pub fn read(path: &Path) -> Result<Self, DynamicsError> {
        Self::parse(&read_text(path)?, &path.display().to_string())
    }

    /// The `[data] mapping` file, resolved against the folder of the
    /// sidecar at `path` (where it was read from, if anywhere).
    pub fn mapping_path(&self, path: Option<&Path>) -> Option<std::path::PathBuf> {
        let m = self.data.as_ref()?.mapping.as_ref()?;
        Some(
            path.and_then(Path::parent)
                .map_or_else(|| m.into(), |dir| dir.join(m)),
        )
    }
}

/// Fixed-length arrays read exactly: TOML `[1, 2, 3]` for a pair is an
/// error ("expected 2 values, found 3"), not a silently dropped third value.
mod exact {
    use serde::de::{Deserialize, Deserializer, Error};

    fn exact<T, E: Error, const N: usize>(v: Vec<T>) -> Result<[T; N], E> {
        let n = v.len();
        v.try_into()
            .map_err(|_| E::custom(format!("expected {N} values, found {n}")))
    }

    /// `[T; N]`.
    pub fn array<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
        d: D,
    ) -> Result<[T; N], D::Error> {
        exact(Vec::deserialize(d)?)
    }

    /// `Option<[T; N]>`.
    pub fn opt<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
        d: D,
    ) -> Result<Option<[T; N]>, D::Error> {
        Option::<Vec<T>>::deserialize(d)?.map(exact).transpose()
    }

    /// `Vec<[T; N]>`.
    pub fn vec<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
        d: D,
    ) -> Result<Vec<[T; N]>, D::Error> {
        Vec::<Vec<T>>::deserialize(d)?
            .into_iter()
            .map(exact)
            .collect()
    }
}
