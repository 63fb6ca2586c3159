//! `momentlmi simulate --robot MODEL --seconds S --effects a,b --out FILE.csv
//! [--trajectory FILE.csv] [--seed N] [--noise SIGMA] [--effect-param NAME=VALUE …]`.

use momentlmi::data::{Staged, record_path, stage_with_record};
use momentlmi::effects::Library;
use momentlmi::sim::trajectory::Trajectory;
use momentlmi::sim::{Effects, SampledTrajectory, SimConfig, SimError, simulate_with};
use std::path::Path;

/// Arguments of `simulate`.
pub struct SimulateArgs<'a> {
    /// Robot.
    pub robot: &'a str,
    /// Sidecar for a URDF.
    pub sidecar: Option<&'a Path>,
    /// Folders of `package://` meshes.
    pub package_paths: &'a [std::path::PathBuf],
    /// Duration (s).
    pub seconds: f64,
    /// A trajectory file to drive the robot along (default: its excitation).
    pub trajectory: Option<&'a Path>,
    /// Effects, by name.
    pub effects: &'a [String],
    /// NAME=VALUE overrides.
    pub effect_params: &'a [String],
    /// Output CSV (a JSON record is written beside it).
    pub out: &'a Path,
    /// Seed.
    pub seed: u64,
    /// Torque noise σ (N·m).
    pub noise: Option<f64>,
    /// Filter cut-off (Hz).
    pub cutoff: Option<f64>,
    /// Link-side encoder bits.
    pub link_encoder_bits: Option<f64>,
    /// `--floating-base` given.
    pub floating_base: bool,
    /// A floating base's contacts.
    pub contacts: Option<super::floating::Contacts>,
    /// A floating base's true robot's effects.
    pub floating_effects: &'a [super::floating::SimEffect],
}

/// Exit codes: 0 written, 2 bad input or failure (nothing written).
/// A fixed base's simulation ([`super::route::simulate`] sends a floating
/// one to [`super::floating_simulate`]).
pub fn run(a: &SimulateArgs) -> i32 {
    match fixed(a) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

/// The fixed-base simulation, the floating-base options refused.
fn fixed(a: &SimulateArgs) -> Result<(), String> {
    if a.contacts.is_some() || !a.floating_effects.is_empty() {
        return Err(
            "--contacts and --floating-effects are for a floating base (--floating-base)".into(),
        );
    }
    run_inner(a)
}

/// The outputs (the CSV and its record), refused early if either is an input.
fn staged_outputs(a: &SimulateArgs) -> Result<Staged, String> {
    let files: Vec<&Path> = a.sidecar.into_iter().chain(a.trajectory).collect();
    let staged = Staged::protecting(super::input_files(&files, &[a.robot]));
    for p in [a.out, &record_path(a.out)] {
        staged.claim(p).map_err(|e| e.to_string())?;
    }
    Ok(staged)
}

/// A simulation's error; one of the trajectory file's says it is that file.
fn sim_error(e: SimError) -> String {
    match e {
        SimError::TrajectoryFile { .. } | SimError::Data(_) => format!("--trajectory: {e}"),
        e => e.to_string(),
    }
}

/// The configuration the arguments ask for, checked (with its number of
/// samples).
fn sim_config(
    a: &SimulateArgs,
    robot: &momentlmi::dynamics::RobotDescription,
    effects: Effects,
) -> Result<(SimConfig, usize), String> {
    let mut cfg = SimConfig::for_robot(robot, a.seconds, effects, a.seed);
    if let Some(path) = a.trajectory {
        let sampled =
            SampledTrajectory::read(path, &robot.model.joint_names()).map_err(sim_error)?;
        cfg = cfg.with_trajectory(Trajectory::Sampled(sampled));
    }
    cfg.sidecar = a.sidecar.map(|p| p.display().to_string());
    if let Some(s) = a.noise {
        cfg.noise_sigma = s;
        if s == 0.0 {
            cfg.encoder_counts = 0.0;
            cfg.processed = false;
        }
    }
    if let Some(c) = a.cutoff {
        cfg.cutoff_hz = c;
    }
    if let Some(b) = a.link_encoder_bits {
        cfg.link_encoder_bits = Some(b);
    }
    let samples = cfg.validate(&robot.model).map_err(sim_error)?;
    if let Trajectory::Sampled(s) = &cfg.trajectory {
        eprintln!(
            "note: --trajectory {}: {} samples at {} Hz, {}",
            s.source,
            s.samples,
            (s.rate_hz * 1e6).round() / 1e6,
            if s.wraps {
                "periodic (repeats)".to_string()
            } else {
                format!(
                    "not periodic: the data start {} s after its first sample (more with a delay or compliance)",
                    if cfg.processed { cfg.edge_seconds } else { 0.0 }
                )
            }
        );
    }
    Ok((cfg, samples))
}

fn run_inner(a: &SimulateArgs) -> Result<(), String> {
    let mut staged = staged_outputs(a)?;
    let robot = super::load_robot(a.robot, a.sidecar, a.package_paths)?;
    let library = Library::builtin();
    let effects =
        Effects::parse(&a.effects.join(","), a.effect_params).map_err(|e| e.to_string())?;
    library.check(&effects).map_err(|e| e.to_string())?;
    let (cfg, samples) = sim_config(a, &robot, effects)?;
    super::warn_robot(&robot);
    let truth = library
        .true_robot(&robot, &cfg.effects)
        .map_err(|e| e.to_string())?;
    for w in truth.warnings() {
        eprintln!("warning: {w}");
    }
    let bar = indicatif::ProgressBar::new(samples as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("simulating {bar:40} {pos}/{len} samples")
            .map_err(|e| e.to_string())?,
    );
    let d = simulate_with(&robot, &truth, &cfg, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64)
    })
    .map_err(sim_error)?;
    bar.finish_and_clear();
    // the record states what the robot description filled in
    let magnitudes = library
        .magnitudes(&robot, &cfg.effects)
        .map_err(|e| e.to_string())?;
    let record = serde_json::json!({
        "generator": format!("momentlmi {}", env!("CARGO_PKG_VERSION")),
        "samples": d.len(),
        "joints": d.joints,
        "config": cfg,
        "encoders": (0..robot.model.dof()).map(|j| {
            let (resolution, side) = cfg.encoder(&robot.model, j);
            serde_json::json!({"joint": robot.model.joints[j].name, "resolution": resolution, "where": side})
        }).collect::<Vec<_>>(),
        "effect_magnitudes": magnitudes,
        "nominal_friction": robot.friction,
        "tool": robot.model.tool.map(|t| serde_json::json!({
            "body": robot.model.joints[t.body].body,
            "point": [t.point.x, t.point.y, t.point.z],
        })),
        "warnings": super::warnings_json(&robot.warnings),
    });
    let rec = stage_with_record(&mut staged, &d, a.out, &record).map_err(|e| e.to_string())?;
    staged.commit().map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} samples, effects: {}) and {}",
        a.out.display(),
        d.len(),
        if cfg.effects.on.is_empty() {
            "none".to_string()
        } else {
            cfg.effects.on.join(", ")
        },
        rec.display()
    );
    Ok(())
}
