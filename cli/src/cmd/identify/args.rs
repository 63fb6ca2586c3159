//! `identify`'s options ([`IdentifyArgs`], declared once for clap and the
//! command), their defaults and parsing, and the errors' wording with the
//! option each concerns.

use super::super::args::{FloatingArgs, ReadArgs, RobotArgs};
use super::super::export::ExportOutArgs;
use momentlmi::identify::{IdentifyError, IdentifyWarning, JointWeighting, Level, Regularizer};
use std::path::PathBuf;

/// `momentlmi identify`'s options, declared once: clap parses them and the
/// command reads them (the robot's sidecar resolved first,
/// [`RobotArgs::resolve`](super::super::args::RobotArgs::resolve)).
#[derive(clap::Args, Debug, Clone)]
pub struct IdentifyArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Training data: a CSV, NumPy .npz/.npy or ROS 2 .mcap log (repeatable: each file is a
    /// segment that no filter crosses).
    #[arg(long, required = true)]
    pub data: Vec<PathBuf>,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Constraint level per body: none, semi, consistent, ellipsoid.
    #[arg(long, default_value = "consistent")]
    pub constraints: String,
    /// Prior π̂: cad (the description's prior: the sidecar's, else the URDF's
    /// own inertias; the default), true, or a parameter file.
    #[arg(long)]
    pub prior: Option<String>,
    /// Regularisation weight w_π toward the prior (0 turns it off), or auto: chosen by
    /// cross-validation on the training data (each --data file, or piece between gaps,
    /// held out in turn; one piece: 5 blocks in time) — with the friction law in the same
    /// pass when the law is chosen too (a Euclidean prior: 1e-6 … 1 in half-decades), else
    /// by the fits of 1e-6, 1e-5, …, 1 (weight_choice in the report and JSON); the
    /// strongest prior within the noise of the lowest held-out RMS. [default: auto when
    /// the friction law is chosen from the data (no --friction, or --friction auto), else
    /// 1e-6]
    #[arg(long, allow_hyphen_values = true, value_name = "W|auto")]
    pub weight: Option<String>,
    /// How the prior enters the objective: euclidean (w‖π − π̂‖²), entropic
    /// (w Σ d(J‖Ĵ), the log-det divergence of each body's pseudo-inertia: unit and
    /// frame invariant, no body collapses; needs a strictly consistent prior and
    /// --weight > 0, typically 1e-3 to 1e-1) or pullback (the divergence's
    /// second-order term at the prior: a quadratic, as fast as euclidean). [default:
    /// entropic when the weight is chosen from the data (no --weight, the law chosen),
    /// the level constrains (not none) and every prior body is strictly consistent,
    /// else euclidean]
    #[arg(long, value_enum)]
    pub regularizer: Option<Regularizer>,
    /// Extra weight w_m Σ (m − m̂)² keeping the bodies' masses at the prior's
    /// [default: the sidecar's [identify] prior_mass_weight with the Euclidean prior on
    /// (--weight > 0), else 0; 0: off]. For masses known better than the rest (weighed
    /// links): a fixed-base arm's torques see no link mass alone, so the data's
    /// corrections go to the first moments and inertias instead (e.g. 1e-2 with --weight
    /// 1e-6; a weight under 100 × --weight holds nothing and is warned about).
    #[arg(long, allow_hyphen_values = true)]
    pub prior_mass_weight: Option<f64>,
    /// Friction terms identified per joint, comma-separated: viscous, coulomb, offset (a
    /// torque sensor's bias, either sign), asymmetric (Coulomb stronger one way), load
    /// (Coulomb ∝ |τ| of the rigid model: a harmonic drive's), stribeck (breakaway
    /// friction near rest, exp(−(q̇/v_s)²) sign(q̇)), or none (links and rotors only); or
    /// auto (the default): viscous + Coulomb with or without offset, load and Stribeck
    /// (v_s 0.02–0.2 rad/s), the law chosen by cross-validation on the training data
    /// (the fewest terms within the noise of the best), the table in the report and JSON
    /// (model_selection). With neither --friction nor --weight given, too few training
    /// samples to score the laws, or training files over 64 MiB (the choice reads them
    /// whole), leave viscous + Coulomb at 1e-6, with a warning. A list at a set weight
    /// streams prepared CSV logs as before the choice existed. A floating base
    /// (--floating-base) fits its model's own law at 1e-6 (auto is refused there).
    /// (docs/identification.md, "Friction terms")
    #[arg(long, value_name = "LIST|auto")]
    pub friction: Option<String>,
    /// How each joint's rows weigh in the fit: equal (least squares) or noise (weighted
    /// least squares: fitted once equally, then each joint by 1/σ̂², σ̂ its residual RMS;
    /// for arms whose joints' torque noise differs).
    #[arg(long, value_enum, default_value_t = JointWeighting::Equal)]
    pub joint_weighting: JointWeighting,
    /// The Stribeck velocity v_s of the stribeck term (rad/s).
    #[arg(long, value_name = "RAD_PER_S", allow_hyphen_values = true,
          default_value_t = momentlmi::dynamics::DEFAULT_STRIBECK_VELOCITY)]
    pub stribeck_velocity: f64,
    /// Held-out validation data (repeatable, like --data).
    #[arg(long)]
    pub validate: Vec<PathBuf>,
    /// A diagnosis' model file (`diagnose --model-out`) whose fitted effects (a gain, a
    /// delay, a ripple, …) are held at their values: their torques are taken off the
    /// training and validation torques before the fit, and the identified model file
    /// carries them, so that predict and diagnose apply them.
    #[arg(long, value_name = "FILE")]
    pub with_effects: Option<PathBuf>,
    /// Print one JSON object (a model file for predict/diagnose/--prior).
    #[arg(long)]
    pub json: bool,
    /// One body's level instead of --constraints, BODY=LEVEL (repeatable).
    #[arg(long = "level", value_name = "BODY=LEVEL")]
    pub levels: Vec<String>,
    /// The known total mass of every body, links and rotors (kg).
    #[arg(long, allow_hyphen_values = true)]
    pub total_mass: Option<f64>,
    /// Two bodies with the same parameters, A,B (repeatable).
    #[arg(long = "equal", value_name = "A,B")]
    pub equal: Vec<String>,
    /// The memory identification may plan for (GiB); a larger problem is refused before it starts.
    #[arg(long, default_value_t = 8.0, allow_hyphen_values = true)]
    pub max_memory_gib: f64,
    /// Each parameter's range (minimum and maximum) over every model that satisfies the
    /// constraints and fits the data with a residual norm at most (1 + DELTA) × the
    /// estimate's: pinned by the data, by the physics, or unknown. DELTA: a number, or auto
    /// (the default): each parameter's own 95 % interval, (1 + δ)² = 1 + χ²₁(0.95) / (rows −
    /// rank). Two conic problems per parameter, solved in parallel.
    #[arg(long, value_name = "DELTA", num_args = 0..=1, default_missing_value = "auto",
          allow_hyphen_values = true)]
    pub bounds: Option<String>,
    /// The directions the data do not excite, one per line (else one summary line).
    #[arg(long)]
    pub verbose: bool,
    /// The identified model exported too (as `momentlmi export` would).
    #[command(flatten)]
    pub export: ExportOutArgs,
    #[command(flatten)]
    pub floating: FloatingArgs,
    /// A floating base's rows fitted: base (the contact wrenches balance the whole robot;
    /// no joint torque needed), joints, or all [default: all when every log has joint
    /// torques, else base].
    #[arg(long, value_enum)]
    pub rows: Option<momentlmi::identify::Rows>,
}

/// The weight when `--friction` names a law and `--weight` is not given.
pub(super) const LISTED_LAW_WEIGHT: f64 = 1e-6;

/// The most bytes of training files the default's choice of the friction
/// law reads whole (it needs every fold's samples); larger ones are
/// streamed with viscous + Coulomb, so that memory does not grow with the
/// logs by default.
pub(super) const CHOICE_MAX_BYTES: u64 = 64 << 20;

/// `a` as it is, or, when neither `--friction` nor `--weight` is given and
/// the training files exceed [`CHOICE_MAX_BYTES`], with viscous + Coulomb
/// at [`LISTED_LAW_WEIGHT`] listed, and the warning that says so.
pub(super) fn streamed_default(a: &IdentifyArgs) -> (IdentifyArgs, Option<IdentifyWarning>) {
    if a.friction.as_deref().is_some() || a.weight.as_deref().is_some() {
        return (a.clone(), None);
    }
    let sizes = a.data.iter().filter_map(|p| std::fs::metadata(p).ok());
    let bytes: u64 = sizes.map(|m| m.len()).sum();
    if bytes <= CHOICE_MAX_BYTES {
        return (a.clone(), None);
    }
    let warning = IdentifyWarning::LawNotChosen {
        reason: format!(
            "the training files hold {} MiB, over the {} MiB the choice reads whole; give --friction auto to choose anyway",
            bytes >> 20,
            CHOICE_MAX_BYTES >> 20
        ),
        terms: vec!["viscous".into(), "coulomb".into()],
        weight: LISTED_LAW_WEIGHT,
    };
    let listed = IdentifyArgs {
        friction: Some("viscous,coulomb".into()),
        weight: Some("1e-6".into()),
        ..a.clone()
    };
    (listed, Some(warning))
}

impl IdentifyArgs {
    /// The friction law is chosen from the data: `--friction auto`, or no
    /// `--friction` (the default).
    pub(super) fn friction_auto(&self) -> bool {
        self.friction.as_deref().is_none_or(|f| f.trim() == "auto")
    }

    /// The prior's weight, or None when it is chosen (`--weight auto`, or
    /// no `--weight` with the friction law chosen from the data; a listed
    /// law without `--weight`: [`LISTED_LAW_WEIGHT`]).
    pub(super) fn weight(&self) -> Result<Option<f64>, String> {
        match self.weight.as_deref() {
            Some(s) => parse_weight(s),
            None if self.friction_auto() => Ok(None),
            None => Ok(Some(LISTED_LAW_WEIGHT)),
        }
    }
}

pub(super) fn parse_level(s: &str, what: &str) -> Result<Level, String> {
    Level::parse(s)
        .ok_or_else(|| format!("{what}: '{s}' is not one of none, semi, consistent, ellipsoid"))
}

/// `--bounds`: a number ≥ 0, or `auto` (the 95 % confidence region).
pub(super) fn parse_delta(s: &str, rank: usize, rows: usize) -> Result<f64, String> {
    let margin = momentlmi::identify::Margin::parse(s)
        .ok_or_else(|| format!("--bounds: '{s}' is neither a number ≥ 0 nor auto"))?;
    margin
        .delta(rank, rows)
        .map_err(|e| format!("--bounds auto: {e}"))
}

/// `--weight`: a number, or `auto` (None).
pub(super) fn parse_weight(s: &str) -> Result<Option<f64>, String> {
    if s.trim() == "auto" {
        return Ok(None);
    }
    s.trim()
        .parse()
        .map(Some)
        .map_err(|_| format!("--weight: '{s}' is neither a number nor auto"))
}

/// An identification error, with the option it concerns and what to do.
pub(super) fn explain(e: IdentifyError) -> String {
    match e {
        IdentifyError::NoEllipsoid { .. } | IdentifyError::EllipsoidCount { .. } => {
            format!("--constraints ellipsoid: {e}")
        }
        IdentifyError::PriorNotConsistent { .. } => format!(
            "--prior / --regularizer: {e}\nhint: repair a URDF's inertias with `momentlmi check --repair`, correct that body in a parameter file, or use --regularizer euclidean"
        ),
        IdentifyError::PriorLength { .. }
        | IdentifyError::PriorNotFinite { .. }
        | IdentifyError::NoPrior { .. }
        | IdentifyError::Prior { .. } => format!("--prior / --regularizer: {e}"),
        IdentifyError::TooLarge { .. } => format!("{e}\nhint: --max-memory-gib raises the limit"),
        IdentifyError::Fold {
            weight,
            fold,
            source,
        } => format!(
            "--weight auto: the fit at weight {weight:e} on fold {fold} failed: {}",
            explain(*source)
        ),
        e => e.to_string(),
    }
}
