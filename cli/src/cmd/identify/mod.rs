//! `momentlmi identify --robot MODEL --data FILE.csv --constraints LEVEL
//! [--prior cad|true|FILE] [--weight W] [--regularizer euclidean|entropic]
//! [--prior-mass-weight W] [--validate FILE.csv] [--json]`.

use momentlmi::dynamics::RobotDescription;
use momentlmi::dynamics::{FrictionTerm, ParamChoice};
use momentlmi::identify::{
    Identification, IdentifyResult, IdentifyWarning, Level, Regularizer, WEIGHT_GRID,
};
use std::path::Path;

mod args;
mod held;
mod report;
mod training;

pub use args::IdentifyArgs;
use args::{explain, parse_delta, parse_level, streamed_default};
use held::Held;
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
        .chain(a.robot.sidecar.as_deref())
        .collect();
    let specs = [a.robot.robot.as_str(), a.prior.as_deref().unwrap_or("")];
    let staged = momentlmi::data::Staged::protecting(super::input_files(&files, &specs));
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

/// The identification with the robot's set-up and the flags' constraints.
fn identification<'r>(
    a: &'r IdentifyArgs,
    robot: &'r RobotDescription,
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
        if !(m > 0.0 && m.is_finite()) {
            return Err(format!("--total-mass must be positive and finite, got {m}"));
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
    let mut robot = super::load_robot(
        a.robot.robot.as_str(),
        a.robot.sidecar.as_deref(),
        &a.robot.package_path,
    )?;
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
    let held = a
        .with_effects
        .as_deref()
        .map(|p| Held::read(&robot, p))
        .transpose()?;
    let ellipsoid = a.constraints.as_str() == "ellipsoid"
        || a.levels.iter().any(|l| l.trim_end().ends_with("ellipsoid"));
    let names = robot.model.joint_names();
    let mut opts = a.read.choice().options(&robot, true)?;
    let read_with = |paths: &[std::path::PathBuf], o: &momentlmi::data::ReadOptions| {
        let p: Vec<&Path> = paths.iter().map(|p| p.as_path()).collect();
        super::read_data(
            &p,
            &names,
            o,
            a.robot.robot.as_str(),
            a.robot.sidecar.as_deref(),
        )
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
                .then(|| read_with(&a.validate, opts))
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
        if let Some(delta) = a.bounds.as_deref() {
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
    let what = match a.friction.as_deref() {
        Some(_) => "--friction auto",
        None => "choosing the friction law (the default; --friction LIST fits one)",
    };
    let failed = |e| format!("{what}: {}", explain(e));
    if a.friction.as_deref().is_some() || a.weight.as_deref().is_some() {
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
