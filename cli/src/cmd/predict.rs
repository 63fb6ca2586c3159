//! `momentlmi predict --robot MODEL [--params true|cad|FILE] --data FILE.csv --out PRED.csv [--json]`.

use super::args::{FloatingArgs, ReadArgs, RobotArgs};
use momentlmi::data::Staged;
use momentlmi::dynamics::ParamChoice;
use momentlmi::effects::fitted::predict_with;
use serde_json::json;
use std::path::Path;
use std::path::PathBuf;

/// `momentlmi predict`'s options, declared once: clap parses them and the
/// command reads them (the robot's sidecar resolved first,
/// [`RobotArgs::resolve`]).
#[derive(clap::Args, Debug, Clone)]
pub struct PredictArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// `true` (own parameters + nominal friction), `cad` (the description's
    /// prior), or a parameter file (the JSON `identify --json` prints);
    /// default: the model's own, no friction.
    #[arg(long)]
    pub params: Option<String>,
    /// Data file (CSV: t, q_<joint>[, qd_<joint>][, qdd_<joint>]; extra columns are
    /// ignored; or NumPy .npz/.npy, or a ROS 2 .mcap bag, docs/inputs.md); repeatable:
    /// each file is a segment, predicted in order into one output.
    #[arg(long, required = true)]
    pub data: Vec<PathBuf>,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Output CSV: t, tau_<joint>…
    #[arg(long)]
    pub out: PathBuf,
    /// Print a JSON summary.
    #[arg(long)]
    pub json: bool,
    /// The torques of the model as its MuJoCo export holds it (`export --mjcf-out`): rotors
    /// as joint armature, no friction: what MuJoCo's inverse dynamics gives without
    /// passive and constraint forces.
    #[arg(long)]
    pub mujoco_view: bool,
    #[command(flatten)]
    pub floating: FloatingArgs,
}

/// Exit codes: 0 written, 2 bad input or failed write.
/// A fixed base's prediction ([`super::route::predict`] sends a floating
/// one to [`super::floating_predict`]).
pub fn run(a: &PredictArgs) -> i32 {
    match run_inner(a) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

/// The output, refused early if it is one of the inputs.
fn staged_output(a: &PredictArgs) -> Result<Staged, String> {
    let files: Vec<&Path> = (a.data.iter().map(|p| p.as_path()))
        .chain(a.read.mapping.as_deref())
        .collect();
    let staged = Staged::protecting(
        a.robot
            .inputs_with(&files, &[a.params.as_deref().unwrap_or("")]),
    );
    staged.claim(a.out.as_path()).map_err(|e| e.to_string())?;
    Ok(staged)
}

fn run_inner(a: &PredictArgs) -> Result<(), String> {
    let mut staged = staged_output(a)?;
    let robot = a.robot.load()?;
    if a.params.as_deref().is_some_and(|p| p == "true") {
        super::warn_robot(&robot);
    }
    let (model, friction, effects) = super::parameters_with_effects_for(
        &robot,
        "--params",
        a.params.as_deref(),
        ParamChoice::Own,
    )?;
    let names = model.joint_names();
    let mut opts = a.read.choice().options(&robot, false)?;
    super::cutoff_of_model(&mut opts, a.params.as_deref(), "--params");
    let paths: Vec<&Path> = a.data.iter().map(|p| p.as_path()).collect();
    let reading = a.robot.read(&a.data, &names, &opts)?;
    super::report_reading("--data", &reading);
    let d = reading.data;
    let tau = if a.mujoco_view {
        if !effects.is_empty() {
            return Err(format!(
                "--mujoco-view: the model's fitted effects ({}) have no place in MuJoCo's equations of motion",
                momentlmi::dynamics::params_file::FittedEffect::names(&effects)
            ));
        }
        view_torques(&model, &friction, &d)?
    } else {
        let lib = momentlmi::effects::Library::builtin();
        predict_with(&model, &friction, &effects, &d, &lib).map_err(|e| format!("--params: {e}"))?
    };
    staged
        .add_text(a.out.as_path(), &torques_csv(&d.t, &names, &tau))
        .map_err(|e| e.to_string())?;
    // with the predictions on standard output, the summary goes to standard error
    let to_stdout = staged.writes_stdout();
    staged.commit().map_err(|e| e.to_string())?;
    let summary = summary(a, &model.name, &names, &d, &paths, &tau);
    if to_stdout {
        eprint!("{summary}");
    } else {
        print!("{summary}");
    }
    Ok(())
}

/// The torques of the MuJoCo view of `model` (rigid bodies and armature).
fn view_torques(
    model: &momentlmi::dynamics::Model,
    friction: &momentlmi::dynamics::Friction,
    d: &momentlmi::data::Dataset,
) -> Result<momentlmi::dynamics::Samples, String> {
    let view = momentlmi::export::MujocoView::new(model, friction).map_err(|e| e.to_string())?;
    let mut data = momentlmi::dynamics::Data::new(&view.model);
    let rows: Vec<Vec<f64>> = (0..d.len())
        .map(|k| view.torques(&mut data, &d.q[k], &d.qd[k], &d.qdd[k]))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    Ok(momentlmi::dynamics::Samples::from_rows(&rows))
}

/// The predictions as CSV: `t,tau_<joint>,…`, a row per sample.
fn torques_csv(t: &[f64], names: &[&str], tau: &momentlmi::dynamics::Samples) -> String {
    let mut s = String::from("t");
    for j in names {
        s += &format!(",tau_{j}");
    }
    s.push('\n');
    for (k, row) in tau.iter().enumerate() {
        s += &t[k].to_string();
        for v in row {
            s += &format!(",{v:e}");
        }
        s.push('\n');
    }
    s
}

/// The summary: JSON, or a line and the RMS against the measured torques
/// per joint when the file has them.
fn summary(
    a: &PredictArgs,
    robot: &str,
    names: &[&str],
    d: &momentlmi::data::Dataset,
    paths: &[&Path],
    tau: &momentlmi::dynamics::Samples,
) -> String {
    use std::fmt::Write as _;
    let rms: Option<Vec<f64>> = (!d.tau.is_empty()).then(|| {
        (0..names.len())
            .map(|j| {
                let sq: f64 = (tau.iter().zip(&d.tau))
                    .map(|(p, m)| (p[j] - m[j]).powi(2))
                    .sum();
                (sq / tau.len() as f64).sqrt()
            })
            .collect()
    });
    let out = a.out.display().to_string();
    let mut summary = String::new();
    if a.json {
        let j = json!({ "robot": robot, "joints": names, "samples": d.len(), "out": out, "rms_vs_measured": rms });
        writeln!(summary, "{j}").expect("a String");
        return summary;
    }
    let files: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    let (n, files) = (d.len(), files.join(", "));
    writeln!(summary, "{robot}: {n} samples of {files} → {out}").expect("a String");
    for (j, v) in names.iter().zip(rms.into_iter().flatten()) {
        writeln!(summary, "  RMS(predicted − measured) {j:<12} {v:.4}").expect("a String");
    }
    summary
}
