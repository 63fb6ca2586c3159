//! `momentlmi identify --robot MODEL --data FILE.csv --constraints LEVEL
//! [--prior cad|true|FILE] [--weight W] [--regularizer euclidean|entropic]
//! [--prior-mass-weight W] [--validate FILE.csv] [--json]`.

use momentlmi::dynamics::RobotDescription;
use momentlmi::dynamics::{FrictionTerm, ParamChoice};
use momentlmi::identify::{Identification, IdentifyError, IdentifyResult, Level, Regularizer};
use std::path::Path;

mod args;
mod held;
mod report;
mod training;

pub use args::IdentifyArgs;
use args::{explain, parse_delta, parse_level, streamed_default};
use held::Held;
use momentlmi::identify::planned;
pub use report::print_report;
use training::{Training, training};

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
    if !a.export.outputs().any() {
        return Ok(None);
    }
    let files: Vec<&Path> = (a.data.iter().chain(&a.validate).map(|p| p.as_path()))
        .chain(a.read.mapping.as_deref())
        .chain(a.with_effects.as_deref())
        .collect();
    let specs = [a.prior.as_deref().unwrap_or("")];
    let staged = momentlmi::data::Staged::protecting(a.robot.inputs_with(&files, &specs));
    a.export.outputs().claim(&staged)?;
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
        a.export.outputs(),
        &a.robot.package_path,
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

/// The identification with the robot's set-up and the flags' constraints,
/// at `weight` (the grid's first when it is chosen: the choice sets it);
/// a floating base's as well (its rows set by the caller).
pub(super) fn identification<'r>(
    a: &IdentifyArgs,
    robot: &'r RobotDescription,
    weight: f64,
) -> Result<Identification<'r>, String> {
    let level = parse_level(a.constraints.as_str(), "--constraints")?;
    let (prior, _) = super::parameters_without_effects_for(
        robot,
        "--prior",
        a.prior.as_deref(),
        ParamChoice::Cad,
        "a prior is the bodies' parameters",
    )?;
    warn_inconsistent_prior(&robot.model.body_names(), &prior.params());
    let regularizer = regularizer(a, &prior.params(), level)?;
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
    for l in &a.levels {
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
        if let Some(why) = momentlmi::dynamics::total_mass_refusal(m, &robot.model) {
            return Err(format!("--total-mass {why}"));
        }
        id = id.constrain(move |p, v| {
            p.add_eq(v.total_mass(), m)?;
            Ok(())
        });
    }
    for pair in &a.equal {
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
    parse_level(a.constraints.as_str(), "--constraints")?;
    if let Some(b) = a.bounds.as_deref() {
        // the form is checked before the fit (auto needs the fit's rank)
        parse_delta(b, 1, 2)?;
    }
    let robot = robot_with_terms(a)?;
    let held = (a.with_effects.as_deref())
        .map(|p| Held::read(&robot, p))
        .transpose()?;
    let mut opts = a.read.choice().options(&robot, true)?;
    let (mut train, cutoff) = read_training(a, &robot, &opts)?;
    // the validation files are prepared as the training ones were
    opts.cutoff_hz = cutoff.as_ref().map(|c| c.chosen_hz).or(opts.cutoff_hz);
    super::report_files("--data", train.files());
    if let (Some(h), Training::Whole(t)) = (&held, &mut train) {
        h.take_off(&mut t.data, "--data")?;
    }
    super::warn_cost(momentlmi::identify::cost(&robot.model, train.samples()).flops);
    // the held-out files are read while the SDP is solved (on the core the
    // solver leaves idle); a held-out file that cannot be read is the error
    // shown first (it is the one a user can fix without waiting for a fit)
    let read_val = || {
        let names = robot.model.joint_names();
        (!a.validate.is_empty())
            .then(|| a.robot.read(&a.validate, &names, &opts))
            .transpose()
    };
    let data = match &train {
        Training::Streamed(t) => planned::Training::Reduced(&t.reduced),
        Training::Whole(t) => planned::Training::Samples(&t.data),
    };
    let plan = plan(a, a.friction_auto() && matches!(train, Training::Whole(_)))?;
    let (fitted, val) = planned::identify_planned(&CliSetup(a), &robot, data, &plan, read_val);
    let mut val = val.transpose()?.flatten();
    if let (Some(c), Some(v)) = (&cutoff, &mut val) {
        let how = format!("the training logs' choice, {}", c.words());
        momentlmi::identify::cutoff::mark_chosen(&mut v.files, &how);
    }
    if let (Some(h), Some(v)) = (&held, &mut val) {
        h.take_off(&mut v.data, "--validate")?;
    }
    let planned::Planned {
        result: mut r,
        robot,
    } = fitted.map_err(|e| e.words(a))?;
    if let Some(v) = &val {
        super::report_reading("--validate", v);
        r.validate(&robot.model, &v.data).map_err(explain)?;
    }
    r.effects = held.map(|h| h.effects).unwrap_or_default();
    (r.timings.read_s, r.timings.filter_s, r.timings.streamed) = train.times();
    r.data_preparation = momentlmi::identify::DataPreparation {
        training: train.into_files(),
        validation: val.map(|v| v.files).unwrap_or_default(),
        cutoff_choice: cutoff,
    };
    Ok((r, robot))
}

/// The robot with `--friction`'s terms (a list; auto: the model's own
/// until the choice) and `--stribeck-velocity`.
fn robot_with_terms(a: &IdentifyArgs) -> Result<RobotDescription, String> {
    let mut robot = a.robot.load()?;
    let auto = a.friction_auto();
    if a.friction
        .as_deref()
        .is_some_and(|f| !auto && f.split(',').any(|t| t.trim() == "auto"))
    {
        return Err(
            "--friction: auto stands alone (the law chosen from the data), not in a list of terms"
                .into(),
        );
    }
    if let Some(list) = a.friction.as_deref().filter(|_| !auto) {
        let terms = FrictionTerm::parse_list(list).map_err(|e| format!("--friction: {e}"))?;
        robot.model = robot.model.with_friction_terms(&terms);
    }
    robot.model = (robot.model.clone())
        .with_stribeck_velocity(a.stribeck_velocity)
        .map_err(|e| format!("--stribeck-velocity: {e}"))?;
    Ok(robot)
}

/// `--data` read ([`training`]) while the bounding volumes are computed
/// (meshes read, ellipsoids fitted) when a level needs them, their
/// warnings printed.
fn read_training(
    a: &IdentifyArgs,
    robot: &RobotDescription,
    opts: &momentlmi::data::ReadOptions,
) -> Result<(Training, Option<momentlmi::identify::cutoff::CutoffCurve>), String> {
    let ellipsoid = a.constraints.as_str() == "ellipsoid"
        || a.levels.iter().any(|l| l.trim_end().ends_with("ellipsoid"));
    std::thread::scope(|s| {
        let bounds = ellipsoid.then(|| s.spawn(|| robot.bounding_warnings().len()));
        let train = training(a, robot, opts);
        if let Some(b) = bounds {
            b.join()
                .map_err(|_| "computing the bounding volumes failed")?;
            // the bounding volumes come from the geometry these warnings are about
            super::warn_robot(robot);
            for w in robot.bounding_warnings() {
                eprintln!("warning: {}: {w}", robot.source);
            }
        }
        train
    })
}

/// The command's options as the library's [`planned::Setup`].
struct CliSetup<'a>(&'a IdentifyArgs);

/// An error of the command (worded) or a failed step of the library's
/// sequence (worded by [`CliError::words`]).
enum CliError {
    Words(String),
    Failed(planned::Failed),
}

impl From<String> for CliError {
    fn from(e: String) -> Self {
        Self::Words(e)
    }
}

impl From<planned::Failed> for CliError {
    fn from(f: planned::Failed) -> Self {
        Self::Failed(f)
    }
}

impl CliError {
    /// The error with the option it concerns.
    fn words(self, a: &IdentifyArgs) -> String {
        use planned::Step;
        let f = match self {
            Self::Words(w) => return w,
            Self::Failed(f) => f,
        };
        match f.step {
            Step::Law => match a.friction {
                Some(_) => format!("--friction auto: {}", explain(f.source)),
                None => format!(
                    "choosing the friction law (the default; --friction LIST fits one): {}",
                    explain(f.source)
                ),
            },
            Step::Weight => match f.source {
                e @ IdentifyError::Fold { .. } => explain(e),
                e => format!("--weight auto: {}", explain(e)),
            },
            Step::Reduce | Step::Fit => explain(f.source),
            Step::Bounds => format!("--bounds: {}", explain(f.source)),
        }
    }
}

impl planned::Setup for CliSetup<'_> {
    type Error = CliError;

    fn identification<'r>(
        &self,
        robot: &'r RobotDescription,
        weight: f64,
    ) -> Result<Identification<'r>, CliError> {
        let id = identification(self.0, robot, weight)?;
        Ok(id.max_memory(super::gib(self.0.max_memory_gib)?))
    }
}

/// What the data choose (`choose`: the law, when it is auto and the data
/// are read whole), and the parameters' ranges.
fn plan(a: &IdentifyArgs, choose: bool) -> Result<planned::Plan, String> {
    let law = planned::LawPlan::for_options(choose, a.friction.is_some() || a.weight.is_some());
    let bounds = (a.bounds.as_deref())
        .map(|b| {
            momentlmi::identify::Margin::parse(b)
                .ok_or_else(|| format!("--bounds: '{b}' is neither a number ≥ 0 nor auto"))
        })
        .transpose()?;
    Ok(planned::Plan {
        law,
        weight: a.weight()?,
        bounds,
    })
}
