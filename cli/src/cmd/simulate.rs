//! `momentlmi simulate --robot MODEL --seconds S --effects a,b --out FILE.csv
//! [--seed N] [--noise SIGMA] [--effect-param NAME=VALUE …]`.

use momentlmi::data::{Staged, record_path, stage_with_record};
use momentlmi::effects::Library;
use momentlmi::sim::{Effects, SimConfig, simulate_with};
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
}

/// Exit codes: 0 written, 2 bad input or failure (nothing written).
pub fn run(a: &SimulateArgs) -> i32 {
    match run_inner(a) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

/// The outputs (the CSV and its record), refused early if either is an input.
fn staged_outputs(a: &SimulateArgs) -> Result<Staged, String> {
    let files: Vec<&Path> = a.sidecar.into_iter().collect();
    let staged = Staged::protecting(super::input_files(&files, &[a.robot]));
    for p in [a.out, &record_path(a.out)] {
        staged.claim(p).map_err(|e| e.to_string())?;
    }
    Ok(staged)
}

fn run_inner(a: &SimulateArgs) -> Result<(), String> {
    let mut staged = staged_outputs(a)?;
    let robot = super::load_robot(a.robot, a.sidecar, a.package_paths)?;
    let library = Library::builtin();
    let effects =
        Effects::parse(&a.effects.join(","), a.effect_params).map_err(|e| e.to_string())?;
    library.check(&effects).map_err(|e| e.to_string())?;
    let mut cfg = SimConfig::for_robot(&robot, a.seconds, effects, a.seed);
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
    let samples = cfg.validate(&robot.model).map_err(|e| e.to_string())?;
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
    .map_err(|e| e.to_string())?;
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
