//! Designed against default excitation: for the leg and the Panda arm, the
//! same identification (consistent level, the robot's prior with weight
//! 1e-6) on T = 2, 5, 10, 20 s of each motion (σ = 0.3 N·m, seed 1; the
//! leg with rotors, Coulomb and viscous friction, the arm with friction),
//! and
//! - the **model error**: RMS over 2,000 random states (positions within
//!   the limits, velocities and accelerations ±2) of the torque difference
//!   between the identified and the true robot, noise-free (N·m);
//! - the **held-out RMS** on 20 s of the default excitation with another
//!   seed (N·m; its floor is the noise, 0.3).
//!
//! ```sh
//! cargo run --release --example excite_study [-- OUT.json]
//! ```
//! prints a Markdown table and writes the numbers as JSON and an SVG
//! figure beside (`OUT.json`, `OUT.svg`; default `excite_study.*`).

use momentlmi::dynamics::robots::load_robot;
use momentlmi::dynamics::{RobotDescription, Samples, regressor_batch};
use momentlmi::effects::{Library, simulate};
use momentlmi::excite::{ExciteOptions, design};
use momentlmi::identify::{Identification, Level};
use momentlmi::sim::{Effects, SimConfig, TrueRobot};
use std::error::Error;

const SECONDS: [f64; 4] = [2.0, 5.0, 10.0, 20.0];

#[derive(serde::Serialize)]
struct Row {
    robot: String,
    motion: &'static str,
    seconds: f64,
    model_error: f64,
    held_out: f64,
}

/// RMS over random states of the identified model's torque (`Y θ̂`) minus
/// the true robot's, noise-free.
fn model_error(
    robot: &RobotDescription,
    truth: &TrueRobot,
    est: &[f64],
) -> Result<f64, Box<dyn Error>> {
    let n = robot.model.dof();
    let s = momentlmi::dynamics::random_states(&robot.model, 2000, 5);
    let y = regressor_batch(&robot.model, &s[0], &s[1], &s[2])?;
    let flat = |v: &[f64]| Samples::from_flat(n, v.to_vec()).ok_or("ragged states");
    let tau = truth.torques(&flat(&s[0])?, &flat(&s[1])?, &flat(&s[2])?)?;
    let p = est.len();
    let rows = y.len() / p;
    let tau = tau.as_flat();
    let sq: f64 = (0..rows)
        .map(|i| ((0..p).map(|j| y[i * p + j] * est[j]).sum::<f64>() - tau[i]).powi(2))
        .sum();
    Ok((sq / rows as f64).sqrt())
}

fn study(
    robot: &RobotDescription,
    effects: &str,
    rows: &mut Vec<Row>,
) -> Result<(), Box<dyn Error>> {
    let none = Effects::parse(effects, &[])?;
    let truth = Library::builtin().true_robot(robot, &none)?;
    let held = simulate(
        robot,
        &SimConfig::for_robot(robot, 20.0, none.clone(), 99),
        |_, _| {},
    )?;
    for &t in &SECONDS {
        let default = SimConfig::for_robot(robot, t, none.clone(), 1);
        let designed = design(
            robot,
            &ExciteOptions {
                seconds: t,
                ..ExciteOptions::default()
            },
        )?;
        let mut with_design = default.clone();
        with_design.trajectory = designed.trajectory.clone();
        if let Some(f) = with_design.trajectory.top_hz() {
            with_design.cutoff_hz = (10.0 * f).clamp(5.0, 30.0);
        }
        for (motion, cfg) in [("default", default), ("designed", with_design)] {
            let data = simulate(robot, &cfg, |_, _| {})?;
            let mut r = Identification::for_robot(robot, Level::Consistent, 1e-6)?.fit(&data)?;
            r.validate(&robot.model, &held)?;
            let v = r.validation_rms.clone().unwrap_or_default();
            let held_out = (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
            let row = Row {
                robot: robot.model.name.clone(),
                motion,
                seconds: t,
                model_error: model_error(robot, &truth, &r.theta)?,
                held_out,
            };
            println!(
                "| {} | {} | {} | {:.4} | {:.4} |",
                row.robot, row.motion, row.seconds, row.model_error, row.held_out
            );
            rows.push(row);
        }
    }
    Ok(())
}

/// A log-scale line figure of the model error against T.
fn svg(rows: &[Row]) -> String {
    let (w, h, m) = (640.0, 400.0, 60.0);
    let err: Vec<f64> = rows.iter().map(|r| r.model_error.max(1e-6)).collect();
    let (lo, hi) = err
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    let (lo, hi) = (
        lo.log10().floor(),
        hi.log10().ceil().max(lo.log10().floor() + 1.0),
    );
    let x =
        |t: f64| m + (t.log10() - 2f64.log10()) / (20f64.log10() - 2f64.log10()) * (w - 2.0 * m);
    let y = |v: f64| h - m - (v.max(1e-6).log10() - lo) / (hi - lo) * (h - 2.0 * m);
    let mut s = format!(
        "<svg xmlns='http://www.w3.org/2000/svg' width='{w}' height='{h}' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n<text x='{m}' y='24'>model error on random states (N·m, log) against the motion's length T (s)</text>\n"
    );
    for t in SECONDS {
        s += &format!(
            "<text x='{}' y='{}' text-anchor='middle'>{t}</text>\n",
            x(t),
            h - m + 18.0
        );
    }
    for e in lo as i32..=hi as i32 {
        s += &format!(
            "<text x='{}' y='{}' text-anchor='end'>1e{e}</text>\n",
            m - 6.0,
            y(10f64.powi(e)) + 4.0
        );
    }
    let series: [(&str, &str, &str); 4] = [
        ("cheetah3-leg", "default", "#999999"),
        ("cheetah3-leg", "designed", "#000000"),
        ("panda", "default", "#9999ff"),
        ("panda", "designed", "#0000cc"),
    ];
    for (k, (robot, motion, colour)) in series.iter().enumerate() {
        let pts: Vec<String> = (rows.iter())
            .filter(|r| r.robot.contains(robot) && r.motion == *motion)
            .map(|r| format!("{:.1},{:.1}", x(r.seconds), y(r.model_error)))
            .collect();
        s += &format!(
            "<polyline fill='none' stroke='{colour}' stroke-width='2' points='{}'/>\n",
            pts.join(" ")
        );
        s += &format!(
            "<text x='{}' y='{}' fill='{colour}'>{robot} {motion}</text>\n",
            w - m - 150.0,
            m + 16.0 * k as f64
        );
    }
    s + "</svg>\n"
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "excite_study.json".into());
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let arm = load_robot(
        dir.join("panda.urdf").to_str().unwrap_or_default(),
        Some(&dir.join("panda.toml")),
    )?;
    let leg = load_robot("cheetah3-leg", None)?;
    println!(
        "| robot | motion | T (s) | model error (N·m) | held-out RMS (N·m) |\n|---|---|---|---|---|"
    );
    let mut rows = vec![];
    study(&leg, "rotor_inertia,coulomb,viscous", &mut rows)?;
    study(&arm, "coulomb,viscous", &mut rows)?;
    std::fs::write(&out, serde_json::to_string_pretty(&rows)?)?;
    std::fs::write(std::path::Path::new(&out).with_extension("svg"), svg(&rows))?;
    Ok(())
}
