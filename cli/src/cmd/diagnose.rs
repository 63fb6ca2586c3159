//! `momentlmi diagnose --robot MODEL --data FILE.csv [--nominal cad|true|FILE] [--json] [--out DIR]`.

use super::args::{FloatingArgs, ReadArgs, RobotArgs};
use momentlmi::data::Staged;
use momentlmi::diagnose::floor::repeat_floor;
use momentlmi::diagnose::{DiagnoseOptions, Diagnosis, FloorSource, diagnose_with};
use momentlmi::dynamics::ParamChoice;
use std::path::Path;
use std::path::PathBuf;

/// `momentlmi diagnose`'s options, declared once: clap parses them and the
/// command reads them (the robot's sidecar resolved first,
/// [`RobotArgs::resolve`]).
#[derive(clap::Args, Debug, Clone)]
pub struct DiagnoseArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Measured data (a CSV, NumPy .npz/.npy or ROS 2 .mcap log); repeatable: each
    /// file is a segment that no filter, difference or spectrum crosses.
    #[arg(long, required = true)]
    pub data: Vec<PathBuf>,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Nominal model: cad | true or a parameter file (e.g. from identify --json);
    /// default: the model's own parameters, no friction.
    #[arg(long)]
    pub nominal: Option<String>,
    /// The data the nominal model was identified on (read like --data; repeatable): its
    /// bodies are then refit with the friction law, on these data and the fitting part
    /// together, so that what these data could not determine is not named an effect
    /// (link_inertia and rotor_inertia are then not proposed) [default: the bodies are
    /// held as given].
    #[arg(long, value_name = "FILE")]
    pub nominal_data: Vec<PathBuf>,
    /// Two runs of one trajectory (read like --data) whose torque difference, once
    /// aligned by positions, is the noise floor: RMS(τ₁ − τ₂)/√2 per joint [default:
    /// the residual's first differences, a lower bound on low-pass filtered data].
    #[arg(long, num_args = 2, value_names = ["RUN1", "RUN2"])]
    pub repeats: Vec<PathBuf>,
    /// Print the JSON report.
    #[arg(long)]
    pub json: bool,
    /// Also write diagnosis.json into this folder (a floating base: floating_diagnosis.json).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the diagnosis' model — the nominal with its friction law refit and the
    /// accepted effects, fitted on the fitting part — as a parameter file that predict,
    /// identify --prior and export take (predict with it gives the held-out error reported).
    #[arg(long, value_name = "FILE")]
    pub model_out: Option<PathBuf>,
    /// Blocks of time the data are cut in for cross-validation when they are one or two
    /// files (3 to 10 files: one fold each).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(3..=50), allow_hyphen_values = true)]
    pub folds: u64,
    /// The memory the diagnosis may plan for (GiB): beyond it the compliance searches are skipped, or the diagnosis refused.
    #[arg(long, default_value_t = 8.0, allow_hyphen_values = true)]
    pub max_memory_gib: f64,
    #[command(flatten)]
    pub floating: FloatingArgs,
}

fn diagnosis(a: &DiagnoseArgs) -> Result<Diagnosis, String> {
    let mut opts = DiagnoseOptions::default()
        .with_max_memory(super::gib(a.max_memory_gib)?)
        .with_folds(a.folds as usize)
        .map_err(|e| e.to_string())?;
    let robot = a.robot.load()?;
    if a.nominal.as_deref() == Some("true") {
        super::warn_robot(&robot);
    }
    let (model, friction, effects) = super::parameters_with_effects_for(
        &robot,
        "--nominal",
        a.nominal.as_deref(),
        ParamChoice::Own,
    )?;
    let names = model.joint_names();
    let mut read = a.read.choice().options(&robot, true)?;
    super::cutoff_of_model(&mut read, a.nominal.as_deref(), "--nominal");
    let reading = a.robot.read(&a.data, &names, &read)?;
    super::report_reading("--data", &reading);
    let d = reading.data;
    if let [r1, r2] = a.repeats.as_slice() {
        let run = |p: &Path| {
            let r = a.robot.read(&[p.to_path_buf()], &names, &read)?;
            super::report_reading("--repeats", &r);
            Ok::<_, String>(r.data)
        };
        let (x, y) = (run(r1)?, run(r2)?);
        let shown = [r1, r2].map(|p| p.display().to_string());
        let floor =
            repeat_floor(&x, &y, [&shown[0], &shown[1]]).map_err(|e| format!("--repeats: {e}"))?;
        opts = opts.with_noise_floor(floor);
    }
    if !a.nominal_data.is_empty() {
        let r = a.robot.read(&a.nominal_data, &names, &read)?;
        super::report_reading("--nominal-data", &r);
        opts = opts.with_nominal_data(r.data);
    }
    diagnose_with((&model, &friction, &effects), &d, &opts).map_err(|e| match e {
        e @ momentlmi::diagnose::DiagnoseError::TooLarge { .. } => {
            format!("{e}\nhint: --max-memory-gib raises the limit")
        }
        e => e.to_string(),
    })
}

/// `diagnosis.json` and the plots into `dir` (when given) and the model
/// into `model_out` (when given), all or none; none may be an input of the
/// command.
fn write_outputs(
    dg: &Diagnosis,
    text: &str,
    (dir, model_out): (Option<&Path>, Option<&Path>),
    inputs: &[std::path::PathBuf],
) -> Result<(), String> {
    let folder = dir.map(super::OutDir::create).transpose()?;
    let mut staged = Staged::protecting(inputs);
    let e = |e: momentlmi::data::DataError| e.to_string();
    if let Some(path) = model_out {
        let model = serde_json::to_string_pretty(&dg.model).map_err(|e| e.to_string())?;
        staged
            .add_text(path, &(model + "\n"))
            .map_err(|e| format!("--model-out: {e}"))?;
    }
    if let Some(dir) = dir {
        staged
            .add_text(&dir.join("diagnosis.json"), text)
            .map_err(e)?;
        for (name, svg) in crate::plots::diagnosis::render_plots(dg)? {
            staged.add_text(&dir.join(name), &svg).map_err(e)?;
        }
    }
    staged.commit().map_err(e)?;
    folder.into_iter().for_each(|f| f.keep());
    Ok(())
}

/// Exit codes: 0 diagnosed, 2 bad input.
/// A fixed base's diagnosis ([`super::route::diagnose`] sends a floating
/// one to [`super::floating_diagnose`]).
pub fn run(a: &DiagnoseArgs) -> i32 {
    let (json, out) = (a.json, a.out.as_deref());
    if let Some(dir) = out
        && dir.exists()
        && !dir.is_dir()
    {
        eprintln!("error: --out {}: exists and is not a folder", dir.display());
        return 2;
    }
    if let Err(e) = check_outputs(a) {
        eprintln!("error: {e}");
        return 2;
    }
    let dg = match diagnosis(a) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    for w in &dg.warnings {
        eprintln!("warning: {w}");
    }
    let text = match serde_json::to_string_pretty(&dg) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: the report: {e}");
            return 2;
        }
    };
    if (out.is_some() || a.model_out.as_deref().is_some())
        && let Err(e) = write_outputs(&dg, &text, (out, a.model_out.as_deref()), &inputs(a))
    {
        match out {
            Some(dir) => eprintln!("error: {}: {e}", dir.display()),
            None => eprintln!("error: {e}"),
        }
        return 2;
    }
    if json {
        println!("{text}");
    } else {
        print_report(&dg);
    }
    0
}

/// The files the command reads, which no output may be.
fn inputs(a: &DiagnoseArgs) -> Vec<std::path::PathBuf> {
    let files: Vec<&Path> = (a.data.iter().chain(&a.repeats).chain(&a.nominal_data))
        .map(|p| p.as_path())
        .chain(a.read.mapping.as_deref())
        .collect();
    a.robot
        .inputs_with(&files, &[a.nominal.as_deref().unwrap_or("")])
}

/// `--model-out` is refused before the diagnosis runs when it is one of
/// the command's inputs (a data file's record beside it included), a
/// folder, in a folder that does not exist, or inside `--out`.
fn check_outputs(a: &DiagnoseArgs) -> Result<(), String> {
    let Some(path) = a.model_out.as_deref() else {
        return Ok(());
    };
    let bad = |why: &str| Err(format!("--model-out {}: {why}", path.display()));
    if path.is_dir() {
        return bad("is a folder (a file name is needed)");
    }
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
    if a.out
        .as_deref()
        .is_some_and(|o| parent == Some(o) || path == o)
    {
        return bad("is inside --out's folder, which the diagnosis writes whole");
    }
    if parent.is_some_and(|p| !p.is_dir()) {
        return bad("its folder does not exist");
    }
    let records: Vec<std::path::PathBuf> = (a.data.iter().chain(&a.repeats).chain(&a.nominal_data))
        .map(|p| momentlmi::data::record_path(p))
        .filter(|r| r.is_file())
        .collect();
    let mut protected = inputs(a);
    protected.extend(records);
    Staged::protecting(protected)
        .claim(path)
        .map_err(|e| format!("--model-out: {e}"))?;
    Ok(())
}

/// Where the noise floor came from, in words.
fn floor_source(s: &FloorSource) -> String {
    match s {
        FloorSource::Repeats {
            runs,
            lag,
            position_rms,
            samples,
        } => format!(
            "the repeated runs {}, aligned at a lag of {lag} samples, positions within {position_rms:.1e} RMS, {samples} samples",
            runs.join(" and ")
        ),
        FloorSource::FirstDifferences { low_passed } if low_passed.is_empty() => {
            "the residual's first differences".into()
        }
        FloorSource::FirstDifferences { low_passed } => format!(
            "the residual's first differences, a lower bound on {}, whose residual is low-pass filtered (--repeats gives one that holds)",
            low_passed.join(", ")
        ),
    }
}

/// The human report: where, which, how far.
fn print_report(dg: &Diagnosis) {
    println!("Where the gap lies (held-out part, nominal model):");
    for s in &dg.summary {
        println!("  {s}");
    }
    println!(
        "\nWhich effects explain it (cross-validated over {}: each candidate refit with the nominal friction law and the effects accepted before it):",
        dg.folds
    );
    println!(
        "  {:<20} {:>6} {:>5}  held-out RMS (N·m): as given → refit without → with",
        "effect", "params", "z"
    );
    print_ranked(dg);
    if !dg.reestimated.is_empty() {
        println!(
            "\nThe nominal friction law's coefficients these data move (refit on the fitting part):"
        );
        for r in &dg.reestimated {
            println!("  {} (nominal {:.4})", r.refit.words(), r.nominal);
        }
    }
    println!(
        "\nHow far (held-out part; noise floor: {}):",
        floor_source(&dg.noise_floor_source)
    );
    for (i, j) in dg.joints.iter().enumerate() {
        println!(
            "  {j:<10} held-out RMS {:.3} as given, {:.3} with the friction law refit, {:.3} with the accepted effects; noise floor {:.3}, gap closed {:.0} %",
            dg.heldout_rms_nominal[i],
            dg.heldout_rms_refit[i],
            dg.heldout_rms_final[i],
            dg.noise_floor[i],
            100.0 * dg.gap_closed[i]
        );
    }
    if dg.unexplained {
        println!("\nUnexplained remainder:");
        for s in &dg.unexplained_where {
            println!("  {s}");
        }
    } else {
        println!("\nNothing left above the noise floor.");
    }
}

/// The candidates of every round (those not refused outright), each with
/// its held-out errors and, when accepted, its joints, rule, sizes and ties.
fn print_ranked(dg: &Diagnosis) {
    let mut round = 0;
    for e in dg
        .ranked_effects
        .iter()
        .filter(|e| e.accepted || !e.rule.starts_with("not"))
    {
        if e.round != round {
            round = e.round;
            println!("  — round {round}");
        }
        print_effect(e);
    }
}

/// One ranked candidate's lines.
fn print_effect(e: &momentlmi::diagnose::EffectReport) {
    println!(
        "  {:<20} {:>6} {:>5.1}  {} → {} → {}{}{}",
        e.label(),
        e.params,
        e.z,
        super::per_joint(&e.heldout_rms_nominal, 3),
        super::per_joint(&e.heldout_rms_before, 3),
        super::per_joint(&e.heldout_rms_after, 3),
        if e.accepted { "  ACCEPTED" } else { "" },
        e.ties()
    );
    if e.accepted {
        println!("  {:<20} on {}: {}", "", e.joints.join(", "), e.rule);
        for size in &e.sizes {
            println!("  {:<20} {}", "", size.words());
        }
        for t in &e.ties {
            println!(
                "  {:<20} {} (`excite --separate {},{}` designs one that does)",
                "",
                t.words(&e.effect),
                e.effect,
                t.effect
            );
        }
    }
    if let Some(why) = &e.removed {
        println!("  {:<20} accepted, then {why}", "");
    }
    if !e.detail.is_empty() {
        println!("  {:<20} {}", "", e.detail);
    }
}
