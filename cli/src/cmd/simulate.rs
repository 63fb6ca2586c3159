//! `momentlmi simulate --robot MODEL --seconds S --effects a,b --out FILE.csv
//! [--trajectory FILE.csv] [--seed N] [--noise SIGMA] [--effect-param NAME=VALUE …]`.

use super::args::{FloatingArgs, RobotArgs, effect_names, effect_param_help};
use momentlmi::data::{Staged, record_path, stage_with_record};
use momentlmi::effects::Library;
use momentlmi::sim::trajectory::Trajectory;
use momentlmi::sim::{Effects, SampledTrajectory, SimConfig, SimError, simulate_with};
use std::path::Path;
use std::path::PathBuf;

/// `momentlmi simulate`'s options, declared once: clap parses them and the
/// command reads them (the robot's sidecar resolved first,
/// [`RobotArgs::resolve`]).
#[derive(clap::Args, Debug, Clone)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Duration in seconds (1 kHz sampling; 200 Hz for a floating base).
    #[arg(long, default_value_t = 20.0, allow_hyphen_values = true)]
    pub seconds: f64,
    /// Drive the robot along the trajectory in FILE instead of its default excitation:
    /// a CSV with columns t, q_<joint>…, qd_<joint>…, qdd_<joint>… for every joint of the
    /// robot (s, rad, rad/s, rad/s²; m for prismatic joints), uniformly sampled,
    /// interpolated by quintic Hermite polynomials. If its last sample continues into its
    /// first one step later it is periodic and repeats (write one period, t = 0 … T − dt);
    /// otherwise it must span --seconds plus the 0.5 s edges simulated before and after
    /// the data (none with --noise 0), and the data start that far after its first sample
    /// (a delay or compliance effect needs a little more). The cut-off default becomes
    /// 30 Hz. Columns, units and tolerances: docs/inputs.md, "Trajectory files".
    #[arg(long, value_name = "FILE")]
    pub trajectory: Option<PathBuf>,
    /// Comma-separated effects the true robot has (`momentlmi::effects`).
    #[arg(long, value_parser = effect_names(), value_delimiter = ',')]
    pub effects: Vec<String>,
    /// Output CSV (a JSON record of how it was made is written beside it).
    #[arg(long)]
    pub out: PathBuf,
    /// Random seed.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub seed: u64,
    /// Torque noise σ in N·m (default 0.3; a floating base's joint torques 0.02); 0 writes
    /// exact, unprocessed states (a floating base: every sensor exact).
    #[arg(long, allow_hyphen_values = true)]
    pub noise: Option<f64>,
    /// Cut-off (Hz) of the offline filter of q, q̇, q̈ (default: 30 Hz, or 10× the top
    /// frequency of a multi-sine excitation when lower, at least 5 Hz; 30 Hz with
    /// --trajectory).
    #[arg(long, value_name = "HZ", allow_hyphen_values = true)]
    pub cutoff: Option<f64>,
    /// Bits per turn of the link-side encoders of revolute joints without a rotor
    /// (default 19; joints with a rotor have 2^14 counts per motor turn).
    #[arg(long, value_name = "BITS", allow_hyphen_values = true)]
    pub link_encoder_bits: Option<f64>,
    /// Effect parameter override NAME=VALUE (repeatable), e.g. `stiffness=300`;
    /// the defaults come from the robot's description.
    #[arg(long = "effect-param", value_name = "NAME=VALUE", long_help = effect_param_help())]
    pub effect_param: Vec<String>,
    #[command(flatten)]
    pub floating: FloatingArgs,
    /// A floating base's contacts: suspended (a load cell at the base, the default) or
    /// standing (the sidecar's [floating_base] feet on force plates, in its stance).
    #[arg(long, value_enum)]
    pub contacts: Option<crate::cmd::floating::Contacts>,
    /// Effects a floating base's true robot has (comma-separated): joint_friction (0.01
    /// N·m·s/rad viscous, 0.05 N·m Coulomb per joint), wrench_offset (every contact's
    /// sensor off by [1, −0.5, 2] N, [0.05, 0.02, −0.03] N·m), payload (0.3 kg on the base
    /// at [0.05, 0, 0.03] m).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub floating_effects: Vec<crate::cmd::floating::SimEffect>,
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
    let files: Vec<&Path> = a.trajectory.as_deref().into_iter().collect();
    let staged = Staged::protecting(a.robot.inputs_with(&files, &[]));
    for p in [a.out.as_path(), &record_path(a.out.as_path())] {
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
    if let Some(path) = a.trajectory.as_deref() {
        let sampled =
            SampledTrajectory::read(path, &robot.model.joint_names()).map_err(sim_error)?;
        cfg = cfg.with_trajectory(Trajectory::Sampled(sampled));
    }
    cfg.sidecar = a.robot.sidecar.as_deref().map(|p| p.display().to_string());
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
    let robot = a.robot.load()?;
    let library = Library::builtin();
    let effects =
        Effects::parse(&a.effects.join(","), &a.effect_param).map_err(|e| e.to_string())?;
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
    let rec =
        stage_with_record(&mut staged, &d, a.out.as_path(), &record).map_err(|e| e.to_string())?;
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
