//! `predict --floating-base`: the generalized force a floating-base model
//! predicts for every sample of its logs (the contact wrenches' resultant
//! on the base, then the joint torques), and its residual RMS by row group
//! against what the logs measured.

use super::floating::{Robot, read_logs, reading_options, refuse, theta_of};
use super::predict::PredictArgs;
use momentlmi::data::Dataset;
use momentlmi::data::Staged;
use momentlmi::dynamics::{Data, Model};
use momentlmi::identify::floating_fit::floating_rms_of;
use std::path::Path;

/// The memory `predict` may use for the logs (GiB).
const DEFAULT_MAX_MEMORY_GIB: f64 = 8.0;

/// Predicts and writes `--out` whole (or nothing).
pub fn run(a: &PredictArgs, robot: Robot) -> Result<(), String> {
    refuse(&[("--mujoco-view", a.mujoco_view)])?;
    refuse(&reading_options(&a.read.choice()))?;
    let files: Vec<&Path> = a.data.iter().map(|p| p.as_path()).collect();
    let inputs = a
        .robot
        .inputs_with(&files, &[a.params.as_deref().unwrap_or("")]);
    let mut staged = Staged::protecting(inputs);
    staged.claim(a.out.as_path()).map_err(|e| e.to_string())?;
    let described = robot.describe(&a.robot.package_path)?;
    let (ff, friction) = super::floating::with_params(&described, a.params.as_deref(), "--params")?;
    let theta = theta_of(&ff, &friction);
    let logs = read_logs(&ff, &a.data, ("--data", DEFAULT_MAX_MEMORY_GIB))?;
    let mut text = header(&ff);
    for log in &logs {
        text += &rows(&ff, &theta, log)?;
    }
    let rms = floating_rms_of(&ff, &theta, &logs).map_err(|e| e.to_string())?;
    staged
        .add(a.out.as_path(), text.as_bytes())
        .map_err(|e| e.to_string())?;
    staged.commit().map_err(|e| e.to_string())?;
    let summary = serde_json::json!({
        "out": a.out.display().to_string(),
        "floating_base": true,
        "samples": rms.samples,
        "rms": rms,
    });
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?
        );
    } else {
        println!(
            "wrote {} ({} samples); residual RMS: base force {:.4} N, base moment {:.4} N·m{}",
            a.out.display(),
            rms.samples,
            rms.base_force,
            rms.base_moment,
            if rms.joints.is_empty() {
                String::new()
            } else {
                format!(", joints {} N·m", super::per_joint(&rms.joints, 4))
            }
        );
    }
    Ok(())
}

/// `t, base_force_x…z, base_moment_x…z, tau_<joint>…`.
fn header(ff: &Model) -> String {
    let mut h = vec!["t".to_string()];
    for kind in ["force", "moment"] {
        h.extend(["x", "y", "z"].map(|a| format!("base_{kind}_{a}")));
    }
    h.extend(ff.joint_names().iter().map(|j| format!("tau_{j}")));
    h.join(",") + "\n"
}

/// The predicted `Y θ` of every sample, one CSV row each.
fn rows(ff: &Model, theta: &[f64], log: &Dataset) -> Result<String, String> {
    let mut data = Data::new(ff);
    let th = nalgebra::DVector::from_column_slice(theta);
    let mut out = String::new();
    for k in 0..log.len() {
        if !log.tau.is_empty() {
            data.load.copy_from_slice(&log.tau[k]);
        }
        let (q, v, acc) = log.state(k);
        let y = momentlmi::dynamics::regressor(ff, &mut data, &q, &v, &acc)
            .map_err(|e| format!("sample {k}: {e}"))?;
        let g = y * &th;
        let cells: Vec<String> = std::iter::once(log.t[k])
            .chain(g.iter().copied())
            .map(|x| format!("{x:e}"))
            .collect();
        out += &cells.join(",");
        out.push('\n');
    }
    Ok(out)
}
