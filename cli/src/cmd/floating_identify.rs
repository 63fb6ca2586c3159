//! `identify --floating-base [--rows base|joints|all]`: a floating-base
//! robot identified from its logs (docs/floating-base.md): the report, or
//! with `--json` a parameter file (`predict --params` reads it) with the fit.

use super::floating::{Robot, read_logs, refuse};
use super::identify::IdentifyArgs;
use momentlmi::dynamics::FrictionTerm;
use momentlmi::identify::floating_fit::{FloatingFit, FloatingRms, fit_floating};
use momentlmi::identify::{CHECK_TOL, JointWeighting, Regularizer, Rows};

/// Identifies; exit 0 every body consistent and at its constraint level,
/// 1 not, 2 bad input.
pub fn run(a: &IdentifyArgs, robot: Robot) -> i32 {
    match fit(a, robot) {
        Ok(fit) => {
            for w in &fit.warnings {
                eprintln!("warning: {w}");
            }
            let out = if a.json {
                serde_json::to_string_pretty(&fit.to_json()).map_err(|e| e.to_string())
            } else {
                Ok(report(&fit, a.verbose))
            };
            match out {
                Ok(text) => println!("{text}"),
                Err(e) => {
                    eprintln!("error: {e}");
                    return 2;
                }
            }
            let worst = fit
                .min_eigenvalues
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            if worst >= -CHECK_TOL && fit.constraints_satisfied {
                0
            } else {
                1
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

fn refused(a: &IdentifyArgs) -> Result<(), String> {
    refuse(&super::floating::reading_options(&a.read.choice()))?;
    refuse(&[
        ("--bounds", a.bounds.as_deref().is_some()),
        ("--with-effects", a.with_effects.is_some()),
        (
            "--joint-weighting noise",
            a.joint_weighting != JointWeighting::Equal,
        ),
        ("--urdf-out/--mjcf-out", a.export.outputs().any()),
        (
            "--weight auto",
            a.weight.as_deref().is_some_and(|w| w.trim() == "auto"),
        ),
        (
            "--friction auto",
            a.friction.as_deref().is_some_and(|f| f.trim() == "auto"),
        ),
        (
            "--stribeck-velocity",
            a.stribeck_velocity != momentlmi::dynamics::DEFAULT_STRIBECK_VELOCITY,
        ),
    ])
}

/// Reads the logs, sets the problem up as the flags say (the fixed base's
/// set-up, [`super::identify::identification`], on the rows fitted) and
/// solves it.
fn fit(a: &IdentifyArgs, robot: Robot) -> Result<FloatingFit, String> {
    refused(a)?;
    let mut described = robot.describe(&a.robot.package_path)?;
    if let Some(list) = a.friction.as_deref() {
        let terms = FrictionTerm::parse_list(list).map_err(|e| format!("--friction: {e}"))?;
        described.model = described.model.clone().with_friction_terms(&terms);
    }
    let ff = &described.model;
    let budget = a.max_memory_gib;
    let train = read_logs(ff, &a.data, ("--data", budget))?;
    let validate = read_logs(ff, &a.validate, ("--validate", budget))?;
    let rows = rows(a.rows, &train)?;
    let given = a.weight.as_deref().unwrap_or("1e-6");
    let weight: f64 = (given.trim().parse().ok())
        .filter(|w: &f64| w.is_finite() && *w >= 0.0)
        .ok_or_else(|| format!("--weight: '{given}' is not a number ≥ 0"))?;
    let regularizer = a.regularizer.unwrap_or(Regularizer::Euclidean);
    if regularizer != Regularizer::Euclidean && weight <= 0.0 {
        return Err(format!(
            "--regularizer {} needs --weight > 0 (typically 1e-3 to 1e-1), got {weight}",
            regularizer.as_str()
        ));
    }
    let ellipsoid = a.constraints.as_str() == "ellipsoid"
        || a.levels.iter().any(|l| l.trim_end().ends_with("ellipsoid"));
    if ellipsoid {
        // the bounding volumes come from the geometry these warnings are about
        for w in described.bounding_warnings() {
            eprintln!("warning: {}: {w}", described.source);
        }
    }
    let id = super::identify::identification(a, &described, weight)?
        .regularizer(regularizer)
        .rows(rows);
    fit_floating(&id, ff, rows, &train, &validate).map_err(|e| e.to_string())
}

/// The rows asked, else every row when each log has joint torques, else
/// the base rows (said on stderr).
fn rows(asked: Option<Rows>, train: &[momentlmi::data::Dataset]) -> Result<Rows, String> {
    let (rows, said) = Rows::for_logs(asked, train).map_err(|e| format!("--{e}"))?;
    if let Some(said) = said {
        eprintln!("note: fitting {said}; --rows base|joints|all to choose");
    }
    Ok(rows)
}

/// `a/b/c` RMS by row group.
fn rms_line(r: &FloatingRms) -> String {
    let joints = if r.joints.is_empty() {
        "no joint torques".to_string()
    } else {
        format!("joints {} N·m", super::per_joint(&r.joints, 4))
    };
    format!(
        "base force {:.4} N, base moment {:.4} N·m, {joints} ({} samples)",
        r.base_force, r.base_moment, r.samples
    )
}

/// The text report.
fn report(fit: &FloatingFit, verbose: bool) -> String {
    let s = &fit.solved;
    let w = &fit.whole_body;
    let mut out = format!(
        "floating base: {} rows fitted, solver {:?} in {} iterations ({:.2} s)\n",
        fit.rows.as_str(),
        s.status,
        s.iterations,
        s.solve_time_s
    );
    out += &format!("training RMS:  {}\n", rms_line(&fit.train));
    if let Some(v) = &fit.validation {
        out += &format!("held-out RMS:  {}\n", rms_line(v));
    }
    out += &format!(
        "whole robot (first training sample, base axes): mass {:.4} kg, CoM [{:.4}, {:.4}, {:.4}] m, centroidal inertia diag [{:.5}, {:.5}, {:.5}] kg·m²\n",
        w.mass,
        w.com[0],
        w.com[1],
        w.com[2],
        w.centroidal_inertia[0][0],
        w.centroidal_inertia[1][1],
        w.centroidal_inertia[2][2]
    );
    out += "body                mass (kg)   CoM (m)                      principal moments (kg·m²)        consistent  min eig J\n";
    for (b, body) in fit.bodies.iter().enumerate() {
        let c = body.com.unwrap_or([f64::NAN; 3]);
        let pm = body.principal_moments;
        out += &format!(
            "{:<18} {:>10.4}   [{:>7.4}, {:>7.4}, {:>7.4}]   [{:>8.2e}, {:>8.2e}, {:>8.2e}]   {:<10}  {:>10.2e}\n",
            body.name,
            body.mass,
            c[0],
            c[1],
            c[2],
            pm[0],
            pm[1],
            pm[2],
            if body.consistent { "yes" } else { "NO" },
            fit.min_eigenvalues[b]
        );
    }
    let alone = fit.determined_alone();
    let most = if verbose { alone.len() } else { 6 };
    let shown: Vec<&str> = alone.iter().take(most).map(String::as_str).collect();
    out += &format!(
        "identifiability: {}\ndetermined on their own by these rows: {} parameters{}",
        s.identifiability.summary(),
        alone.len(),
        if alone.len() > shown.len() {
            format!(" ({}, … all with --verbose)", shown.join(", "))
        } else if alone.is_empty() {
            " (only combinations: the base parameters in --json)".into()
        } else {
            format!(" ({})", shown.join(", "))
        }
    );
    out
}
