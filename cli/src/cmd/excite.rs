//! `momentlmi excite --robot R [--seconds T] [--criterion d|e|cond]
//! [--pool N] [--out traj.csv] [--json]`: a designed excitation.

use momentlmi::data::{Staged, record_path, stage_with_record};
use momentlmi::excite::{Criterion, Designed, ExciteOptions, design, samples};
use std::path::{Path, PathBuf};

/// Arguments of `excite`.
pub struct ExciteArgs<'a> {
    /// Robot.
    pub robot: &'a str,
    /// Sidecar for a URDF.
    pub sidecar: Option<&'a Path>,
    /// Folders of `package://` meshes.
    pub package_paths: &'a [PathBuf],
    /// The settings.
    pub options: ExciteOptions,
    /// The criterion's name.
    pub criterion: &'a str,
    /// Output CSV (t, q, q̇, q̈ per joint) and its JSON report beside it.
    pub out: Option<&'a Path>,
    /// Its sample rate (Hz).
    pub rate_hz: f64,
    /// JSON to standard output.
    pub json: bool,
}

/// Exit codes: 0 designed (and written), 2 bad input or failure.
pub fn run(a: &ExciteArgs) -> i32 {
    match run_inner(a) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

fn run_inner(a: &ExciteArgs) -> Result<(), String> {
    let criterion = Criterion::parse(a.criterion)
        .ok_or_else(|| format!("--criterion: '{}' is not one of d, e, cond", a.criterion))?;
    let mut staged = Staged::protecting(super::input_files(
        &a.sidecar.into_iter().collect::<Vec<_>>(),
        &[a.robot],
    ));
    if let Some(out) = a.out {
        for p in [out, &record_path(out)] {
            staged.claim(p).map_err(|e| e.to_string())?;
        }
    }
    let robot = super::load_robot(a.robot, a.sidecar, a.package_paths)?;
    super::warn_robot(&robot);
    let opts = ExciteOptions {
        criterion,
        ..a.options.clone()
    };
    let d = design(&robot, &opts).map_err(|e| e.to_string())?;
    if let Some(out) = a.out {
        let data = samples(&d, a.rate_hz).map_err(|e| e.to_string())?;
        stage_with_record(&mut staged, &data, out, &d).map_err(|e| e.to_string())?;
        staged.commit().map_err(|e| e.to_string())?;
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&d).map_err(|e| e.to_string())?
        );
    } else {
        print_report(&d, a.out);
    }
    warn_torques(&d);
    Ok(())
}

/// A warning per joint whose effort limit the motion passes.
fn warn_torques(d: &Designed) {
    for (l, m) in d.limits.iter().zip(&d.torque_margins) {
        if let Some(m) = m.filter(|m| *m < 0.0) {
            eprintln!(
                "warning: joint '{}' needs {:.0} % more torque than its effort limit {} along the motion (the description's model; checked, not enforced)",
                l.joint,
                -100.0 * m,
                l.effort.unwrap_or(f64::NAN)
            );
        }
    }
}

fn print_report(d: &Designed, out: Option<&Path>) {
    let hz = match &d.trajectory {
        momentlmi::sim::trajectory::Trajectory::Fourier { omega, .. } => {
            omega / (2.0 * std::f64::consts::PI)
        }
        _ => f64::NAN,
    };
    println!(
        "{}: {} s ({} periods of {:.4} Hz, {} harmonics), {:?}-optimal on {} base parameters: value {:.4} (best random start {:.4}), log det {:.4}, condition number {:.3e}",
        d.robot,
        d.options.seconds,
        (d.options.seconds * hz).round(),
        hz,
        d.options.harmonics,
        d.options.criterion,
        d.base_parameters,
        d.value,
        d.best_seed_value,
        d.log_det,
        d.condition_number
    );
    println!("method: {}", d.method);
    println!(
        "{:<20} {:>22} {:>10} {:>10} {:>10}   margins: position, velocity, acceleration, torque",
        "joint", "position [lo, hi]", "|q̇| max", "|q̈| max", "|τ| max"
    );
    for ((l, m), t) in d.limits.iter().zip(&d.margins).zip(&d.torque_margins) {
        let effort = l
            .effort
            .map_or_else(|| "-".to_string(), |e| format!("{e:.1}"));
        let torque = t.map_or_else(|| "-".to_string(), |t| format!("{:.1} %", 100.0 * t));
        println!(
            "{:<20} [{:>9.4}, {:>9.4}] {:>10.4} {:>10.4} {:>10}   {:.1} %, {:.1} %, {:.1} %, {torque}",
            l.joint,
            l.position.0,
            l.position.1,
            l.velocity,
            l.acceleration,
            effort,
            100.0 * m[0],
            100.0 * m[1],
            100.0 * m[2]
        );
    }
    let from: Vec<String> = (d.limits.iter())
        .map(|l| {
            format!(
                "{}: velocity from the {}, acceleration from the {}",
                l.joint, l.velocity_from, l.acceleration_from
            )
        })
        .collect();
    println!("limits: {}", from.join("; "));
    if let Some(p) = &d.pool {
        println!(
            "convex pool design over {} candidates (the design among them): bound {:.4}, design {:.4}, efficiency {:.1} %",
            p.candidates,
            p.bound,
            p.designed,
            100.0 * p.efficiency
        );
    }
    if let Some(out) = out {
        println!("wrote {} and {}", out.display(), record_path(out).display());
    }
}
