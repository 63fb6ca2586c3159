//! `momentlmi simulate --robot MODEL --seconds S --effects a,b --out FILE.csv
//! [--seed N] [--noise SIGMA] [--effect-param NAME=VALUE …]`.

use momentlmi::data::write_with_record;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::sim::{Effects, SimConfig, simulate};
use std::path::Path;

/// Arguments of `simulate`.
pub struct SimulateArgs<'a> {
    /// Robot.
    pub robot: &'a str,
    /// Sidecar for a URDF.
    pub sidecar: Option<&'a Path>,
    /// Duration (s).
    pub seconds: f64,
    /// Comma-separated effects.
    pub effects: &'a str,
    /// NAME=VALUE overrides.
    pub effect_params: &'a [String],
    /// Output CSV (a JSON record is written beside it).
    pub out: &'a Path,
    /// Seed.
    pub seed: u64,
    /// Torque noise σ (N·m).
    pub noise: Option<f64>,
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

fn run_inner(a: &SimulateArgs) -> Result<(), String> {
    let model = load_robot(a.robot, a.sidecar).map_err(|e| e.to_string())?;
    let effects = Effects::parse(a.effects, a.effect_params)?;
    if !(a.seconds > 0.0 && a.seconds.is_finite()) {
        return Err(format!("--seconds must be positive, got {}", a.seconds));
    }
    let mut cfg = SimConfig::for_model(a.robot, &model, a.seconds, effects, a.seed);
    if let Some(s) = a.noise {
        if !(s >= 0.0 && s.is_finite()) {
            return Err(format!("--noise must be ≥ 0, got {s}"));
        }
        cfg.noise_sigma = s;
        if s == 0.0 {
            cfg.encoder_counts = 0.0;
            cfg.processed = false;
        }
    }
    let bar = indicatif::ProgressBar::new((cfg.seconds * cfg.rate_hz) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("simulating {bar:40} {pos}/{len} samples")
            .map_err(|e| e.to_string())?,
    );
    let d = simulate(&model, &cfg, |done, _| bar.set_position(done as u64))?;
    bar.finish_and_clear();
    let record = serde_json::json!({
        "generator": format!("momentlmi {}", env!("CARGO_PKG_VERSION")),
        "samples": d.len(),
        "joints": d.joints,
        "config": cfg,
    });
    let rec = write_with_record(&d, a.out, &record).map_err(|e| e.to_string())?;
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
