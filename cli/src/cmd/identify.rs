//! `momentlmi identify --robot MODEL --data FILE.csv --constraints LEVEL
//! [--prior cad|true|FILE] [--weight W] [--regularizer euclidean|entropic]
//! [--prior-mass-weight W] [--validate FILE.csv] [--json]`.

use momentlmi::dynamics::RobotDescription;
use momentlmi::dynamics::{FrictionTerm, ParamChoice};
use momentlmi::identify::{
    Identification, IdentifyError, IdentifyResult, IdentifyWarning, JointWeighting, Level,
    Regularizer, WEIGHT_GRID,
};
use std::path::Path;

/// Arguments of `identify`.
#[derive(Clone, Copy)]
pub struct IdentifyArgs<'a> {
    /// Robot.
    pub robot: &'a str,
    /// Sidecar for a URDF.
    pub sidecar: Option<&'a Path>,
    /// Folders of `package://` meshes.
    pub package_paths: &'a [std::path::PathBuf],
    /// Training data (each file a segment).
    pub data: &'a [std::path::PathBuf],
    /// How the files are read.
    pub read: super::ReadChoice<'a>,
    /// Level name.
    pub constraints: &'a str,
    /// Prior: cad | true | FILE (default: cad, the description's prior: the sidecar's, else the URDF's own inertias).
    pub prior: Option<&'a str>,
    /// Weight w_π: a number or auto (None: [`IdentifyArgs::weight`]).
    pub weight: Option<&'a str>,
    /// How the prior enters the objective.
    /// None: [`regularizer`]'s default.
    pub regularizer: Option<Regularizer>,
    /// Extra weight on the masses' distance from the prior's (None: the
    /// robot's, `Identification::for_robot`).
    pub prior_mass_weight: Option<f64>,
    /// The friction terms identified, or auto (None: auto, for a floating
    /// base the model's own).
    pub friction: Option<&'a str>,
    /// How the joints' rows are weighted.
    pub joint_weighting: JointWeighting,
    /// The Stribeck term's velocity (rad/s).
    pub stribeck_velocity: f64,
    /// Validation data (each file a segment; none: no validation).
    pub validate: &'a [std::path::PathBuf],
    /// A model file whose fitted effects are held at their values.
    pub with_effects: Option<&'a Path>,
    /// JSON output.
    pub json: bool,
    /// Per-body levels `BODY=LEVEL`.
    pub levels: &'a [String],
    /// A known total mass (kg).
    pub total_mass: Option<f64>,
    /// Pairs `A,B` of equal bodies.
    pub equal: &'a [String],
    /// The memory limit (GiB).
    pub max_memory_gib: f64,
    /// Each parameter's range with this residual margin δ (a number or auto).
    pub bounds: Option<&'a str>,
    /// Every unexcited direction on its own line.
    pub verbose: bool,
    /// Where the identified model is exported.
    pub export: super::export::Outputs<'a>,
    /// `--floating-base` given.
    pub floating_base: bool,
    /// A floating base's rows (None: all with torques, else base).
    pub rows: Option<momentlmi::identify::Rows>,
}

/// The weight when `--friction` names a law and `--weight` is not given.
const LISTED_LAW_WEIGHT: f64 = 1e-6;

/// The most bytes of training files the default's choice of the friction
/// law reads whole (it needs every fold's samples); larger ones are
/// streamed with viscous + Coulomb, so that memory does not grow with the
/// logs by default.
const CHOICE_MAX_BYTES: u64 = 64 << 20;

/// `a` as it is, or, when neither `--friction` nor `--weight` is given and
/// the training files exceed [`CHOICE_MAX_BYTES`], with viscous + Coulomb
/// at [`LISTED_LAW_WEIGHT`] listed, and the warning that says so.
fn streamed_default<'a>(a: &IdentifyArgs<'a>) -> (IdentifyArgs<'a>, Option<IdentifyWarning>) {
    if a.friction.is_some() || a.weight.is_some() {
        return (*a, None);
    }
    let sizes = a.data.iter().filter_map(|p| std::fs::metadata(p).ok());
    let bytes: u64 = sizes.map(|m| m.len()).sum();
    if bytes <= CHOICE_MAX_BYTES {
        return (*a, None);
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
        friction: Some("viscous,coulomb"),
        weight: Some("1e-6"),
        ..*a
    };
    (listed, Some(warning))
}

impl IdentifyArgs<'_> {
    /// The friction law is chosen from the data: `--friction auto`, or no
    /// `--friction` (the default).
    fn friction_auto(&self) -> bool {
        self.friction.is_none_or(|f| f.trim() == "auto")
    }

    /// The prior's weight, or None when it is chosen (`--weight auto`, or
    /// no `--weight` with the friction law chosen from the data; a listed
    /// law without `--weight`: [`LISTED_LAW_WEIGHT`]).
    fn weight(&self) -> Result<Option<f64>, String> {
        match self.weight {
            Some(s) => parse_weight(s),
            None if self.friction_auto() => Ok(None),
            None => Ok(Some(LISTED_LAW_WEIGHT)),
        }
    }
}

/// Exit codes: 0 identified (constraints satisfied), 1 identified but a
/// constraint check failed, 2 bad input or solver failure.
/// A fixed base's identification ([`super::route::identify`] sends a
/// floating one to [`super::floating_identify`]).
pub fn run(a: &IdentifyArgs) -> i32 {
    let t0 = std::time::Instant::now();
    let staged = match exports_claimed(a) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let (a, large) = streamed_default(a);
    let a = &a;
    match run_inner(a) {
        Ok((mut r, robot)) => {
            r.warnings.extend(large);
            let total = t0.elapsed().as_secs_f64();
            r.total_time_s = total;
            r.timings.total_s = total;
            if a.json {
                match serde_json::to_string_pretty(&r) {
                    Ok(s) => println!("{s}"),
                    Err(e) => {
                        eprintln!("error: {e}");
                        return 2;
                    }
                }
            } else {
                print_report(&r);
            }
            for w in &r.warnings {
                eprintln!("warning: {w}");
            }
            warn_bodies(&r);
            warn_unexcited(&r.identifiability, a.verbose);
            if let Some(staged) = staged
                && let Err(e) = export(staged, &robot, &r, a)
            {
                eprintln!("error: exporting the identified model: {e}");
                return 2;
            }
            if r.constraints_satisfied { 0 } else { 1 }
        }
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

/// The export outputs claimed before the work (an input as an output, a
/// folder: refused now), or `None` when none is asked for.
fn exports_claimed(a: &IdentifyArgs) -> Result<Option<momentlmi::data::Staged>, String> {
    if !a.export.any() {
        return Ok(None);
    }
    let files: Vec<&Path> = (a.data.iter().chain(a.validate).map(|p| p.as_path()))
        .chain(a.sidecar)
        .collect();
    let specs = [a.robot, a.prior.unwrap_or("")];
    let staged = momentlmi::data::Staged::protecting(super::input_files(&files, &specs));
    a.export.claim(&staged)?;
    Ok(Some(staged))
}

/// The identified model (the result read as a parameter file) exported.
fn export(
    staged: momentlmi::data::Staged,
    robot: &momentlmi::dynamics::RobotDescription,
    r: &IdentifyResult,
    a: &IdentifyArgs,
) -> Result<(), String> {
    let json = serde_json::to_value(r).map_err(|e| e.to_string())?;
    let file: momentlmi::dynamics::params_file::ParamsFile =
        serde_json::from_value(json).map_err(|e| e.to_string())?;
    let mut model = robot.model.clone();
    let friction = file
        .apply(&mut model, "the identified model")
        .map_err(|e| e.to_string())?;
    super::export::write(
        staged,
        robot,
        (&model, &friction),
        a.export,
        a.package_paths,
    )
}

/// The bodies that are not physically consistent (whatever the level), and
/// those identified as point masses, rods or plates, with what to do.
fn warn_bodies(r: &IdentifyResult) {
    if !r.all_bodies_consistent {
        eprintln!(
            "warning: not physically consistent (J(π) is not positive semidefinite): {}; --constraints consistent or above makes every body physical",
            r.inconsistent_bodies.join(", ")
        );
    }
    for b in &r.bodies {
        if let Some(d) = &b.degenerate {
            eprintln!(
                "warning: body '{}' is identified as a {} (spread {:.1e}, {:.1e}, {:.1e} m against {:.3} m): {}",
                b.name,
                d.shape.as_str(),
                d.semi_axes[0],
                d.semi_axes[1],
                d.semi_axes[2],
                d.length,
                d.advice
            );
        }
    }
}

/// The directions the data do not excite: one summary line, or with
/// `verbose` each direction too (the JSON has them all).
fn warn_unexcited(id: &momentlmi::identify::Identifiability, verbose: bool) {
    if id.rank == id.columns && id.unidentifiable.is_empty() {
        return;
    }
    // all the structure allows: a fact of the robot, not of the data
    let kind = if id.structural_rank == Some(id.rank) {
        "note"
    } else {
        "warning"
    };
    eprintln!(
        "{kind}: {}; {}",
        id.summary(),
        if verbose {
            "the directions:"
        } else {
            "the directions with --verbose or in --json (identifiability.directions)"
        }
    );
    if verbose {
        for d in &id.directions {
            eprintln!("  {d}");
        }
    }
}

/// A warning per prior body that is not physically consistent (the
/// Euclidean prior pulls toward it regardless; the entropic one refuses it).
fn warn_inconsistent_prior(bodies: &[String], prior: &[f64]) {
    use momentlmi::moments::{InertialParams, Verdict, check_consistency};
    for (name, p) in bodies.iter().zip(prior.chunks_exact(10)) {
        let pi = InertialParams(std::array::from_fn(|k| p[k]));
        let report = check_consistency(&pi, momentlmi::identify::CHECK_TOL);
        // a placeholder (a massless frame) is not a finding
        if !report.consistent && report.verdict != Verdict::Placeholder {
            eprintln!(
                "warning: --prior: body '{name}' is not physically consistent (J(π̂) is not positive semidefinite); the prior pulls toward it"
            );
        }
    }
}

/// `--regularizer`, or its default: with the weight chosen from the data,
/// [`Regularizer::for_chosen_weight`] (entropic for a strictly consistent
/// prior at a constrained `level`), else Euclidean.
fn regularizer(a: &IdentifyArgs, prior: &[f64], level: Level) -> Result<Regularizer, String> {
    Ok(match a.regularizer {
        Some(r) => r,
        None if a.weight()?.is_none() => Regularizer::for_chosen_weight(prior, level),
        None => Regularizer::Euclidean,
    })
}

fn parse_level(s: &str, what: &str) -> Result<Level, String> {
    Level::parse(s)
        .ok_or_else(|| format!("{what}: '{s}' is not one of none, semi, consistent, ellipsoid"))
}

/// The identification with the robot's set-up and the flags' constraints.
fn identification<'r>(
    a: &'r IdentifyArgs,
    robot: &'r RobotDescription,
) -> Result<Identification<'r>, String> {
    let level = parse_level(a.constraints, "--constraints")?;
    let (prior, _) = super::parameters_without_effects_for(
        robot,
        "--prior",
        a.prior,
        ParamChoice::Cad,
        "a prior is the bodies' parameters",
    )?;
    warn_inconsistent_prior(&robot.model.body_names(), &prior.params());
    let regularizer = regularizer(a, &prior.params(), level)?;
    // auto: the grid's first weight until the choice (which needs the data)
    let weight = a.weight()?.unwrap_or(WEIGHT_GRID[0]);
    if regularizer == Regularizer::Entropic && weight <= 0.0 {
        return Err(format!(
            "--regularizer entropic needs --weight > 0 (typically 1e-3 to 1e-1, or auto), got {weight}"
        ));
    }
    let id = Identification::for_robot(robot, level, weight)
        .and_then(|id| id.prior(weight, prior.params()))
        .map_err(|e| format!("--weight / --prior: {e}"))?;
    let mut id = match a.prior_mass_weight {
        Some(w) => id
            .prior_mass_weight(w)
            .map_err(|e| format!("--prior-mass-weight: {e}"))?,
        None => id,
    }
    .regularizer(regularizer)
    .joint_weighting(a.joint_weighting);
    for l in a.levels {
        let (body, lv) = l
            .split_once('=')
            .ok_or_else(|| format!("--level '{l}': expected BODY=LEVEL"))?;
        id = id
            .level(
                body.trim(),
                parse_level(lv.trim(), &format!("--level {l}"))?,
            )
            .map_err(|e| format!("--level {l}: {e}"))?;
    }
    if let Some(m) = a.total_mass {
        if !(m > 0.0 && m.is_finite()) {
            return Err(format!("--total-mass must be positive and finite, got {m}"));
        }
        id = id.constrain(move |p, v| {
            p.add_eq(v.total_mass(), m)?;
            Ok(())
        });
    }
    for pair in a.equal {
        let (x, y) = pair
            .split_once(',')
            .ok_or_else(|| format!("--equal '{pair}': expected A,B"))?;
        let (x, y) = (x.trim().to_string(), y.trim().to_string());
        if x == y {
            return Err(format!("--equal {pair}: a body is always equal to itself"));
        }
        for n in [&x, &y] {
            if !robot.model.body_names().contains(n) {
                return Err(format!(
                    "--equal {pair}: '{n}' is not a body (bodies: {})",
                    robot.model.body_names().join(", ")
                ));
            }
        }
        id = id.constrain(move |p, v| {
            v.body(&x)?.add_equal(p, v.body(&y)?)?;
            Ok(())
        });
    }
    Ok(id)
}

fn run_inner(a: &IdentifyArgs) -> Result<(IdentifyResult, RobotDescription), String> {
    parse_level(a.constraints, "--constraints")?;
    if let Some(b) = a.bounds {
        // the form is checked before the fit (auto needs the fit's rank)
        parse_delta(b, 1, 2)?;
    }
    let mut robot = super::load_robot(a.robot, a.sidecar, a.package_paths)?;
    let auto = a.friction_auto();
    if a.friction
        .is_some_and(|f| !auto && f.split(',').any(|t| t.trim() == "auto"))
    {
        return Err(
            "--friction: auto stands alone (the law chosen from the data), not in a list of terms"
                .into(),
        );
    }
    if let Some(list) = a.friction.filter(|_| !auto) {
        let terms = FrictionTerm::parse_list(list).map_err(|e| format!("--friction: {e}"))?;
        robot.model = robot.model.with_friction_terms(&terms);
    }
    robot.model = (robot.model.clone())
        .with_stribeck_velocity(a.stribeck_velocity)
        .map_err(|e| format!("--stribeck-velocity: {e}"))?;
    let held = a.with_effects.map(|p| Held::read(&robot, p)).transpose()?;
    let ellipsoid = a.constraints == "ellipsoid"
        || a.levels.iter().any(|l| l.trim_end().ends_with("ellipsoid"));
    let names = robot.model.joint_names();
    let mut opts = a.read.options(&robot, true)?;
    let read_with = |paths: &[std::path::PathBuf], o: &momentlmi::data::ReadOptions| {
        let p: Vec<&Path> = paths.iter().map(|p| p.as_path()).collect();
        super::read_data(&p, &names, o, a.robot, a.sidecar)
    };
    let r = std::thread::scope(|s| {
        // the bounding volumes (meshes read, ellipsoids fitted) are computed
        // while the logs are read
        let bounds = ellipsoid.then(|| s.spawn(|| robot.bounding_warnings().len()));
        let train = training(a, &robot, &opts);
        if let Some(b) = bounds {
            b.join()
                .map_err(|_| "computing the bounding volumes failed")?;
            // the bounding volumes come from the geometry these warnings are about
            super::warn_robot(&robot);
            for w in robot.bounding_warnings() {
                eprintln!("warning: {}: {w}", robot.source);
            }
        }
        let (mut train, cutoff) = train?;
        // the validation files are prepared as the training ones were
        opts.cutoff_hz = cutoff.as_ref().map(|c| c.chosen_hz).or(opts.cutoff_hz);
        super::report_files("--data", train.files());
        if let (Some(h), Training::Whole(t)) = (&held, &mut train) {
            h.take_off(&mut t.data, "--data")?;
        }
        let (mut selection, not_chosen) = match (&train, auto) {
            (Training::Whole(t), true) => choose_law(a, &robot, &t.data)?,
            _ => (None, None),
        };
        let chosen_robot;
        let robot = match &selection {
            Some(c) => {
                chosen_robot = with_law(&robot, c)?;
                &chosen_robot
            }
            None => &robot,
        };
        let mut id = identification(a, robot)?.max_memory(super::gib(a.max_memory_gib)?);
        if let Some(c) = selection.as_ref().filter(|c| c.weight_chosen()) {
            id = id
                .with_weight(c.weight())
                .map_err(|e| format!("--weight auto: {e}"))?;
        }
        super::warn_cost(momentlmi::identify::cost(&robot.model, train.samples()).flops);
        let (choice, red) = match &train {
            Training::Streamed(t) => (None, t.reduced.clone()),
            Training::Whole(t) => {
                let choice = match a.weight()? {
                    Some(_) => None,
                    None if selection.as_ref().is_some_and(|c| c.weight_chosen()) => None,
                    None if not_chosen.is_some() => None,
                    None => Some(id.choose_weight(&t.data, &WEIGHT_GRID).map_err(explain)?),
                };
                let red = id.reduce_chosen(&t.data, selection.as_mut());
                (choice, red.map_err(explain)?)
            }
        };
        // the held-out files are read while the SDP is solved (on the core
        // the solver leaves idle); that thread is always joined, and a
        // held-out file that cannot be read is the error shown first (it is
        // the one a user can fix without waiting for a fit)
        let (opts, read_with) = (&opts, &read_with);
        let val = s.spawn(move || {
            (!a.validate.is_empty())
                .then(|| read_with(a.validate, opts))
                .transpose()
        });
        let fitted = match &train {
            Training::Streamed(_) => id.fit_streamed(&red),
            Training::Whole(t) => id.fit_reduced(&t.data, &red),
        }
        .map_err(explain);
        let mut val = val
            .join()
            .unwrap_or_else(|_| Err("reading the validation data failed".to_string()))?;
        if let (Some(c), Some(v)) = (&cutoff, &mut val) {
            momentlmi::identify::cutoff::mark_chosen(
                &mut v.files,
                &format!("the training logs' choice, {}", c.words()),
            );
        }
        if let (Some(h), Some(v)) = (&held, &mut val) {
            h.take_off(&mut v.data, "--validate")?;
        }
        let mut r = fitted?;
        if let Some(delta) = a.bounds {
            let rows = red.samples * robot.model.dof();
            let delta = parse_delta(delta, r.identifiability.rank, rows)?;
            let b = id.parameter_bounds(&red, &r.theta, &r.identifiability, delta);
            r.bounds = Some(b.map_err(|e| format!("--bounds: {}", explain(e)))?);
        }
        if let Some(v) = &val {
            super::report_reading("--validate", v);
            r.validate(&robot.model, &v.data).map_err(explain)?;
        }
        r.weight_choice = choice;
        r.model_selection = selection;
        r.warnings.extend(not_chosen);
        r.effects = held.map(|h| h.effects).unwrap_or_default();
        (r.timings.read_s, r.timings.filter_s, r.timings.streamed) = train.times();
        r.data_preparation = momentlmi::identify::DataPreparation {
            training: train.into_files(),
            validation: val.map(|v| v.files).unwrap_or_default(),
            cutoff_choice: cutoff,
        };
        Ok::<_, String>(r)
    })?;
    if let Some(c) = &r.model_selection {
        robot = with_law(&robot, c)?;
    }
    Ok((r, robot))
}

/// The friction law (and the weight, when it is chosen too) chosen on the
/// training data `data`. With neither `--friction` nor `--weight` given,
/// data too few to score the laws keep the model's own law at the grid's
/// first weight, with the warning returned; else that is an error.
fn choose_law(
    a: &IdentifyArgs,
    robot: &RobotDescription,
    data: &momentlmi::data::Dataset,
) -> Result<LawChoice, String> {
    use momentlmi::identify::friction_choice::LawChoice::{Chosen, Kept};
    let id = identification(a, robot)?;
    let weights = id.model_weights(a.weight()?.is_none());
    let what = match a.friction {
        Some(_) => "--friction auto",
        None => "choosing the friction law (the default; --friction LIST fits one)",
    };
    let failed = |e| format!("{what}: {}", explain(e));
    if a.friction.is_some() || a.weight.is_some() {
        return Ok((Some(id.choose_model(data, weights).map_err(failed)?), None));
    }
    Ok(
        match id.choose_model_or_keep(data, weights).map_err(failed)? {
            Chosen(c) => (Some(c), None),
            Kept(w) => (None, Some(w)),
        },
    )
}

/// The law chosen, or the warning that it could not be.
type LawChoice = (
    Option<momentlmi::identify::friction_choice::FrictionChoice>,
    Option<IdentifyWarning>,
);

/// `robot` with the friction law `c` chose.
fn with_law(
    robot: &RobotDescription,
    c: &momentlmi::identify::friction_choice::FrictionChoice,
) -> Result<RobotDescription, String> {
    let mut r = robot.clone();
    r.model = c
        .apply(r.model)
        .map_err(|e| format!("--friction auto: {e}"))?;
    Ok(r)
}

/// `--with-effects FILE`: the model file's bodies and friction (the model
/// its effects were fitted with) and its fitted effects.
struct Held {
    model: momentlmi::dynamics::Model,
    friction: momentlmi::dynamics::Friction,
    effects: Vec<momentlmi::dynamics::params_file::FittedEffect>,
}

impl Held {
    fn read(robot: &RobotDescription, path: &Path) -> Result<Self, String> {
        if !path.is_file() {
            return Err(format!(
                "--with-effects {}: not a file (a diagnosis' model file, diagnose --model-out, is needed)",
                path.display()
            ));
        }
        let value = path.to_str().unwrap_or_default();
        let (model, friction, effects) = super::parameters_with_effects_for(
            robot,
            "--with-effects",
            Some(value),
            ParamChoice::Own,
        )?;
        if effects.is_empty() {
            return Err(format!(
                "--with-effects {}: it holds no fitted effects (bodies and friction only: give it as --prior)",
                path.display()
            ));
        }
        Ok(Self {
            model,
            friction,
            effects,
        })
    }

    /// The held effects' torques taken off `data`'s (the files of `flag`).
    fn take_off(&self, data: &mut momentlmi::data::Dataset, flag: &str) -> Result<(), String> {
        let library = momentlmi::effects::Library::builtin();
        let mut fx = momentlmi::dynamics::Samples::zeros(data.len(), data.joints.len());
        momentlmi::effects::fitted::add_effects(
            &self.model,
            &self.friction,
            &self.effects,
            data,
            &library,
            &mut fx,
        )
        .map_err(|e| format!("--with-effects on the {flag} files: {e}"))?;
        let flat = data.tau.as_flat_mut();
        flat.iter_mut().zip(fx.as_flat()).for_each(|(t, x)| *t -= x);
        Ok(())
    }
}

/// The training data: reduced while read (prepared CSV logs, when neither
/// `--weight auto` nor a load friction term needs the samples again), or
/// read whole.
enum Training {
    Streamed(momentlmi::identify::StreamedLogs),
    Whole(momentlmi::data::Reading),
}

impl Training {
    fn files(&self) -> &[momentlmi::data::FileReport] {
        match self {
            Self::Streamed(t) => &t.files,
            Self::Whole(t) => &t.files,
        }
    }

    fn into_files(self) -> Vec<momentlmi::data::FileReport> {
        match self {
            Self::Streamed(t) => t.files,
            Self::Whole(t) => t.files,
        }
    }

    /// Reading's and filtering's times (s) and whether it was streamed.
    fn times(&self) -> (f64, f64, bool) {
        match self {
            Self::Streamed(t) => (t.read_s, 0.0, true),
            Self::Whole(t) => (t.read_s, t.filter_s, false),
        }
    }

    fn samples(&self) -> usize {
        match self {
            Self::Streamed(t) => t.reduced.samples,
            Self::Whole(t) => t.data.len(),
        }
    }
}

/// Reads `--data`: streamed into the reduction where it can be
/// ([`Training`]), else whole, the raw logs' cut-off chosen on them when
/// none is given ([`momentlmi::identify::cutoff::read_training`]).
fn training(
    a: &IdentifyArgs,
    robot: &RobotDescription,
    opts: &momentlmi::data::ReadOptions,
) -> Result<(Training, Option<momentlmi::identify::cutoff::CutoffCurve>), String> {
    let load = robot.model.friction_terms().contains(&FrictionTerm::Load);
    if a.weight()?.is_some() && !load && a.with_effects.is_none() && !a.friction_auto() {
        let p: Vec<&Path> = a.data.iter().map(|p| p.as_path()).collect();
        match momentlmi::identify::reduce_logs(&robot.model, &p, opts) {
            Ok(Some(t)) => return Ok((Training::Streamed(t), None)),
            Ok(None) => {}
            Err(IdentifyError::Data(e)) => {
                return Err(super::explain_data(e, a.robot, a.sidecar));
            }
            Err(e) => return Err(explain(e)),
        }
    }
    let names = robot.model.joint_names();
    let p: Vec<&Path> = a.data.iter().map(|p| p.as_path()).collect();
    match momentlmi::identify::cutoff::read_training(&p, &names, opts, &robot.model) {
        Ok((r, c)) => Ok((Training::Whole(r), c)),
        Err(IdentifyError::Data(e)) => Err(super::explain_data(e, a.robot, a.sidecar)),
        Err(e) => Err(format!(
            "choosing the low-pass cut-off (give one with --cutoff-hz): {e}"
        )),
    }
}

/// `--bounds`: a number ≥ 0, or `auto` (the 95 % confidence region).
fn parse_delta(s: &str, rank: usize, rows: usize) -> Result<f64, String> {
    let margin = momentlmi::identify::Margin::parse(s)
        .ok_or_else(|| format!("--bounds: '{s}' is neither a number ≥ 0 nor auto"))?;
    margin
        .delta(rank, rows)
        .map_err(|e| format!("--bounds auto: {e}"))
}

/// `--weight`: a number, or `auto` (None).
fn parse_weight(s: &str) -> Result<Option<f64>, String> {
    if s.trim() == "auto" {
        return Ok(None);
    }
    s.trim()
        .parse()
        .map(Some)
        .map_err(|_| format!("--weight: '{s}' is neither a number nor auto"))
}

/// An identification error, with the option it concerns and what to do.
fn explain(e: IdentifyError) -> String {
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

/// How a choice's cross-validation split the training data, in words.
fn folds_text(folds: momentlmi::identify::choose_weight::Folds, k: usize) -> String {
    match folds {
        momentlmi::identify::choose_weight::Folds::Segments => {
            format!(
                "{k} motions held out in turn: files or pieces between gaps, each with its repeats"
            )
        }
        momentlmi::identify::choose_weight::Folds::Time => {
            format!("{k} blocks in time held out in turn, the same block of every file")
        }
    }
}

/// The curve `--weight auto` chose from.
fn print_weight_choice(c: &momentlmi::identify::WeightChoice) {
    let folds = folds_text(c.folds, c.k);
    println!(
        "weight chosen by cross-validation ({folds}; the strongest prior within the noise of the lowest): mean held-out RMS per weight"
    );
    for (w, m) in c.weights.iter().zip(&c.mean_rms) {
        let mark = match (*w == c.chosen, *w == c.lowest) {
            (true, _) => "  ← chosen",
            (false, true) => "  (lowest)",
            _ => "",
        };
        println!("  {w:>7.0e}  {m:.4} N·m{mark}");
    }
    if !c.fold_notes.is_empty() {
        println!(
            "  ({} notes from the folds' fits, in the JSON's weight_choice.fold_notes; first: {})",
            c.fold_notes.len(),
            c.fold_notes[0]
        );
    }
}

fn print_friction_choice(c: &momentlmi::identify::friction_choice::FrictionChoice) {
    let folds = folds_text(c.folds, c.k);
    let weighed = c.weight_chosen();
    println!(
        "friction law{} chosen by cross-validation ({folds}; links and law refit by least squares{}): mean held-out RMS",
        if weighed { " and prior weight" } else { "" },
        if weighed {
            "; each law at its best weight"
        } else {
            ""
        },
    );
    // one row per law: the chosen entry in its law's row, else its best weight
    let same = |i: usize, j: usize| {
        c.laws[i].terms == c.laws[j].terms
            && c.laws[i].stribeck_velocity == c.laws[j].stribeck_velocity
    };
    let mut rows: Vec<usize> = vec![];
    for i in 0..c.laws.len() {
        match rows.iter_mut().find(|r| same(**r, i)) {
            Some(r) if *r == c.chosen => {}
            Some(r) if i == c.chosen || c.laws[i].mean_rms < c.laws[*r].mean_rms => *r = i,
            Some(_) => {}
            None => rows.push(i),
        }
    }
    rows.sort_by(|&a, &b| c.laws[a].mean_rms.total_cmp(&c.laws[b].mean_rms));
    let name = |l: &momentlmi::identify::friction_choice::LawScore| {
        let vs = l.stribeck_velocity.map(|v| format!(" (v_s {v})"));
        format!("{}{}", l.terms.join(", "), vs.unwrap_or_default())
    };
    let width = rows.iter().map(|&i| name(&c.laws[i]).chars().count()).max();
    for i in rows {
        let l = &c.laws[i];
        let w = if weighed {
            format!("  weight {:<8.2e}", l.weight)
        } else {
            String::new()
        };
        let mark = match (i == c.chosen, i == c.best) {
            (true, _) => "  ← chosen",
            (false, true) => "  (lowest)",
            _ => "",
        };
        println!(
            "  {:<width$}{w} {:.4} N·m{mark}",
            name(l),
            l.mean_rms,
            width = width.unwrap_or(0) + 1
        );
    }
    println!("  chosen: {}", c.rule);
}

/// A short human report.
pub fn print_report(r: &IdentifyResult) {
    println!(
        "{} — constraints: {}, {} prior with weight {:e}{}, {} training samples, rank {}/{}",
        r.robot,
        r.constraints.as_str(),
        r.regularizer.as_str(),
        r.weight,
        if r.prior_mass_weight > 0.0 {
            format!(" (masses {:e})", r.prior_mass_weight)
        } else {
            String::new()
        },
        r.training_samples,
        r.identifiability.rank,
        r.identifiability.columns
    );
    if let Some(c) = &r.model_selection {
        print_friction_choice(c);
    }
    if let Some(c) = &r.weight_choice {
        print_weight_choice(c);
    }
    println!(
        "{:<12} {:>9} {:>28} {:>34} {:>11} {:>11}",
        "body", "mass", "CoM [m]", "principal moments [kg·m²]", "consistent", "d(J‖Ĵ)"
    );
    for b in &r.bodies {
        let com = b.com.map_or_else(
            || format!("{:>28}", "- (no positive mass)"),
            |c| format!("({:>8.4}, {:>8.4}, {:>8.4})", c[0], c[1], c[2]),
        );
        let div = b
            .divergence_from_prior
            .map_or_else(|| "-".to_string(), |d| format!("{d:.3e}"));
        println!(
            "{:<12} {:>9.4} {com} ({:>10.3e}, {:>10.3e}, {:>10.3e}) {:>11} {div:>11}",
            b.name,
            b.mass,
            b.principal_moments[0],
            b.principal_moments[1],
            b.principal_moments[2],
            if b.consistent { "yes" } else { "NO" }
        );
    }
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let joints = r.joints.join(", ");
    println!("joints         {joints}");
    println!("viscous        {} N·m·s/rad", list(&r.friction.viscous));
    println!("Coulomb        {} N·m", list(&r.friction.coulomb));
    // the terms beyond the default, when identified (non-zero)
    for t in &FrictionTerm::ALL[2..] {
        let c = r.friction.coefficients(*t);
        if c.iter().any(|&c| c != 0.0) {
            let vs = (*t == FrictionTerm::Stribeck)
                .then(|| format!(" (v_s {} rad/s)", r.friction.stribeck_velocity()))
                .unwrap_or_default();
            println!("{:<15}{} {}{vs}", t.name(), list(c), t.unit());
        }
    }
    if let Some(s) = &r.joint_noise {
        println!("joint noise σ̂  {} N·m (weights ∝ 1/σ̂²)", list(s));
    }
    println!("training RMS   {} N·m", list(&r.training_rms));
    if let Some(v) = &r.validation_rms {
        println!(
            "validation RMS {} N·m ({} samples)",
            list(v),
            r.validation_samples
        );
    }
    println!(
        "status {}, {} iterations, constraints satisfied: {}",
        r.status, r.iterations, r.constraints_satisfied
    );
    print_base_parameters(&r.identifiability);
    if let Some(b) = &r.bounds {
        print_bounds(b);
    }
    print_timings(&r.timings);
}

/// One line of the stages' times (ms).
fn print_timings(t: &momentlmi::identify::Timings) {
    let ms = |s: f64| format!("{:.1}", 1e3 * s);
    let read = if t.streamed {
        format!("read {} (streamed, beside the reduction)", ms(t.read_s))
    } else {
        format!("read {}, filter {}", ms(t.read_s), ms(t.filter_s))
    };
    println!(
        "time [ms]      {read}, regressor + reduction {}, solve {}, check {}, validate {}, total {}",
        ms(t.reduce_s),
        ms(t.solve_s),
        ms(t.check_s),
        ms(t.validate_s),
        ms(t.total_s)
    );
}

/// The base parameters: value ± standard deviation, best determined first.
fn print_base_parameters(id: &momentlmi::identify::Identifiability) {
    println!(
        "base parameters ({} of {} columns; condition number {:.3e}; σ from the residual):",
        id.rank, id.columns, id.condition_number
    );
    for b in &id.base_parameters {
        let sd = b.std_dev.map_or_else(|| "-".into(), |s| format!("{s:.3e}"));
        // relative only where the value stands out of its σ
        let rel = (b.std_dev)
            .filter(|s| *s < b.value.abs())
            .map_or_else(String::new, |s| {
                format!(" ({:.1} %)", 100.0 * s / b.value.abs())
            });
        println!("  {:>12.5e} ± {sd}{rel:<10}  {}", b.value, b.combination);
    }
}

/// Whether a missing end is unbounded (else its solve failed: the note).
fn solved_end(p: &momentlmi::identify::ParamRange) -> bool {
    p.note.as_deref().is_none_or(|n| n.starts_with("unbounded"))
}

/// Each parameter's range over the models that fit almost as well.
fn print_bounds(b: &momentlmi::identify::ParameterBounds) {
    println!(
        "parameter ranges over the constrained models with residual ≤ (1 + {:.3e}) × {:.4e}:",
        b.delta, b.residual
    );
    println!(
        "  {:<24} {:>12} {:>12} {:>12} {:>12}  pinned by",
        "parameter", "estimate", "prior", "min", "max"
    );
    let v = |x: Option<f64>, none: &str| x.map_or_else(|| none.to_string(), |x| format!("{x:.5e}"));
    for p in &b.ranges {
        println!(
            "  {:<24} {:>12.5e} {:>12} {:>12} {:>12}  {}{}",
            p.name,
            p.estimate,
            v(p.prior, "-"),
            v(p.min, if solved_end(p) { "-∞" } else { "?" }),
            v(p.max, if solved_end(p) { "+∞" } else { "?" }),
            match p.pinned_by {
                momentlmi::identify::PinnedBy::Data => "data",
                momentlmi::identify::PinnedBy::Physics => "physics",
                momentlmi::identify::PinnedBy::Unknown => "unknown",
            },
            p.note
                .as_ref()
                .map_or_else(String::new, |n| format!(" ({n})"))
        );
    }
}
