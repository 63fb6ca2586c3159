//! The demo's sixth part: a floating base. Solo12 (robots/solo12, built
//! into the binary) hung from a harness is identified from its load cell
//! alone (the base rows: no joint torque), then from its joint rows, then
//! stands on four force plates; held-out errors against the noise floor and
//! the whole robot's mass, CoM and centroidal inertia against the truth,
//! and a figure of the held-out base wrench and joint torque errors. Its
//! files are named `floating_*`.

use crate::plots::figures::{Series, line_panels};
use momentlmi::data::Dataset;
use momentlmi::data::Staged;
use momentlmi::dynamics::sidecar::Sidecar;
use momentlmi::dynamics::urdf::free_flyer_from_robot;
use momentlmi::dynamics::{Data, Model};
use momentlmi::identify::floating_fit::{
    FloatingFit, fit_floating, floating_rms, residual, whole_body,
};
use momentlmi::identify::{Identification, Rows};
use momentlmi::sim::floating::{SuspendedConfig, simulate_suspended};
use momentlmi::sim::standing::{StandingConfig, simulate_standing};
use std::path::Path;

const URDF: &str = include_str!("../../../robots/solo12/solo12.urdf");
const SIDECAR: &str = include_str!("../../../robots/solo12/solo12.toml");

/// Solo12 and its sidecar, from the embedded files.
fn solo() -> Result<(Model, Sidecar), String> {
    let path = "robots/solo12/solo12.urdf";
    let robot = momentlmi::urdf::read_str(URDF, path).map_err(|e| e.to_string())?;
    let sidecar =
        Sidecar::parse(SIDECAR, "robots/solo12/solo12.toml").map_err(|e| e.to_string())?;
    let ff = free_flyer_from_robot(&robot, path, Some(&sidecar)).map_err(|e| e.to_string())?;
    Ok((ff, sidecar))
}

/// The true model's θ (its bodies; no friction acts in the simulation).
fn truth(ff: &Model) -> Vec<f64> {
    let mut t = ff.params();
    t.resize(ff.regressor_columns(), 0.0);
    t
}

/// Runs the part (`tick(what)` per stage), staging its figure.
pub fn run((out, staged): (&Path, &mut Staged), tick: &mut dyn FnMut(&str)) -> Result<(), String> {
    let (ff, sidecar) = solo()?;
    println!(
        "\n6. A floating base: Solo12 (robots/solo12, 2.5 kg, 12 joints), its root free (docs/floating-base.md)"
    );
    tick("floating base: simulating Solo12 on a harness");
    let cfg = |seconds, seed| SuspendedConfig {
        seconds,
        seed,
        ..SuspendedConfig::default()
    };
    let e = |e: momentlmi::sim::SimError| e.to_string();
    let train = simulate_suspended(&ff, &cfg(120.0, 1)).map_err(e)?;
    let test = simulate_suspended(&ff, &cfg(20.0, 2)).map_err(e)?;
    println!(
        "   hung from a harness, a six-axis load cell at the base: 120 s to fit, 20 s held out (200 Hz)"
    );
    tick("floating base: identifying from the load cell alone");
    let base = fit(&ff, Rows::Base, &train, &test)?;
    let joints = fit(&ff, Rows::Joints, &train, &test)?;
    let all = fit(&ff, Rows::All, &train, &test)?;
    print_fits(&ff, (&test, &train.state(0).0), [&base, &joints, &all])?;
    tick("floating base: standing on force plates");
    standing(&ff, &sidecar)?;
    tick("floating base: diagnosing a payload the URDF lacks");
    diagnose_payload(&ff)?;
    let svg = figure(&ff, &base, &test)?;
    (staged.add_text(&out.join("floating_errors.svg"), &svg)).map_err(|e| e.to_string())?;
    println!("   figure: floating_errors.svg (held-out base wrench and joint torque errors)");
    Ok(())
}

fn fit(ff: &Model, rows: Rows, train: &Dataset, test: &Dataset) -> Result<FloatingFit, String> {
    let id = Identification::for_free_flyer(ff, rows);
    fit_floating(
        &id,
        ff,
        rows,
        std::slice::from_ref(train),
        std::slice::from_ref(test),
    )
    .map_err(|e| e.to_string())
}

/// The fits' held-out RMS against the floor, and the whole robot against
/// the truth.
/// `q0`: the first training sample's configuration, where the fits' whole
/// robot is.
fn print_fits(
    ff: &Model,
    (test, q0): (&Dataset, &[f64]),
    fits: [&FloatingFit; 3],
) -> Result<(), String> {
    let floor = floating_rms(ff, &truth(ff), test).map_err(|e| e.to_string())?;
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    println!(
        "   held-out RMS            base force  base moment  joint torque (mean)   whole robot vs truth"
    );
    println!(
        "   floor (true model)      {:>7.4} N  {:>7.4} N·m  {:>7.4} N·m",
        floor.base_force,
        floor.base_moment,
        mean(&floor.joints)
    );
    for fit in fits {
        let v = fit.validation.as_ref().ok_or("no held-out residual")?;
        if fit.rows == Rows::Joints {
            println!(
                "   joint torques (joints)        —            —     {:>7.4} N·m     — (the base's parameters enter no joint row)",
                mean(&v.joints)
            );
            continue;
        }
        let w = &fit.whole_body;
        let t = whole_body(ff, q0).map_err(|e| e.to_string())?;
        let com = (0..3)
            .map(|i| (w.com[i] - t.com[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        let inertia = relative(&w.centroidal_inertia, &t.centroidal_inertia);
        println!(
            "   {:<22}  {:>7.4} N  {:>7.4} N·m  {:>7.4} N·m     mass {:+.2} %, CoM {:.1} mm, centroidal inertia {:.1} %",
            match fit.rows {
                Rows::Base => "load cell alone (base)",
                Rows::Joints => "joint torques (joints)",
                Rows::All => "every row (all)",
            },
            v.base_force,
            v.base_moment,
            mean(&v.joints),
            100.0 * (w.mass - t.mass) / t.mass,
            1e3 * com,
            100.0 * inertia
        );
    }
    let base = fits[0].validation.as_ref().ok_or("no held-out residual")?;
    if fits[0].rows == Rows::Base && mean(&base.joints) <= 1.1 * mean(&floor.joints) {
        println!(
            "   the base rows alone predict the joint torques within 10 % of their floor: they determine every identifiable parameter (Ayusawa et al. 2014)"
        );
    }
    Ok(())
}

/// `‖a − b‖ / ‖b‖` (Frobenius).
fn relative(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> f64 {
    let (mut d, mut n) = (0.0, 0.0);
    for i in 0..3 {
        for j in 0..3 {
            d += (a[i][j] - b[i][j]).powi(2);
            n += b[i][j].powi(2);
        }
    }
    (d / n).sqrt()
}

/// Standing on force plates: the base rows weigh the robot and place its
/// CoM over the feet.
fn standing(ff: &Model, sidecar: &Sidecar) -> Result<(), String> {
    let facts = sidecar.floating_base.clone().unwrap_or_default();
    let stance = super::floating::stance(ff, &facts)?;
    let cfg = |seconds, seed| StandingConfig {
        seconds,
        seed,
        ..StandingConfig::new(facts.feet.clone(), stance.clone())
    };
    let e = |e: momentlmi::sim::SimError| e.to_string();
    let (train, test) = (
        simulate_standing(ff, &cfg(60.0, 1)).map_err(e)?,
        simulate_standing(ff, &cfg(20.0, 2)).map_err(e)?,
    );
    let fit = fit(ff, Rows::Base, &train, &test)?;
    let floor = floating_rms(ff, &truth(ff), &test).map_err(|e| e.to_string())?;
    let v = fit.validation.as_ref().ok_or("no held-out residual")?;
    let (w, t) = (
        &fit.whole_body,
        whole_body(ff, &train.state(0).0).map_err(|e| e.to_string())?,
    );
    println!(
        "   standing on four force plates, the base swaying (60 s to fit, 20 s held out), base rows: held-out {:.4} N / {:.4} N·m (floor {:.4} / {:.4});",
        v.base_force, v.base_moment, floor.base_force, floor.base_moment
    );
    println!(
        "   mass {:+.2} %, CoM {:.1} mm off horizontally, {:.1} mm vertically (a sway barely shows the CoM's height or the inertia)",
        100.0 * (w.mass - t.mass) / t.mass,
        1e3 * (w.com[0] - t.com[0]).hypot(w.com[1] - t.com[1]),
        1e3 * (w.com[2] - t.com[2]).abs()
    );
    Ok(())
}

/// The held-out residual (measured − predicted) over 5 s: the base force
/// and moment's vertical rows and one knee's torque, of the model
/// identified from the load cell alone and of the true one.
fn figure(ff: &Model, fit: &FloatingFit, test: &Dataset) -> Result<String, String> {
    let knee = ff
        .joint_names()
        .iter()
        .position(|j| *j == "FL_KFE")
        .unwrap_or(0);
    let rows = [2, 5, 6 + knee];
    let titles = [
        "base force z [N]".to_string(),
        "base moment z [N·m]".into(),
        format!("{} torque [N·m]", ff.joint_names()[knee]),
    ];
    let mut data = Data::new(ff);
    let mut series = |theta: &[f64]| -> Result<Vec<Vec<(f64, f64)>>, String> {
        let mut pts = vec![vec![]; rows.len()];
        for k in 0..test.len().min(1000) {
            let r = residual(ff, &mut data, theta, test, k).map_err(|e| e.to_string())?;
            for (p, &row) in pts.iter_mut().zip(&rows) {
                p.push((test.t[k], r[row]));
            }
        }
        Ok(pts)
    };
    let (fitted, true_model) = (series(&fit.solved.theta)?, series(&truth(ff))?);
    let panels: Vec<Vec<Series>> = (fitted.into_iter().zip(true_model))
        .map(|(f, t)| {
            vec![
                Series {
                    label: "true model (the noise floor)",
                    points: t,
                    color: 0,
                },
                Series {
                    label: "identified from the load cell alone",
                    points: f,
                    color: 1,
                },
            ]
        })
        .collect();
    line_panels(
        "Solo12 on a harness: held-out errors (measured − predicted)",
        "t [s]",
        &titles,
        "error",
        &panels,
        false,
    )
}

/// A Solo12 carrying 0.3 kg the URDF lacks, diagnosed against the URDF.
fn diagnose_payload(ff: &Model) -> Result<(), String> {
    use momentlmi::diagnose::floating::diagnose_floating;
    use momentlmi::sim::floating::FloatingEffects;
    let effects = FloatingEffects {
        payload: Some((0.3, [0.05, 0.0, 0.03])),
        ..Default::default()
    };
    let cfg = SuspendedConfig {
        seconds: 60.0,
        seed: 3,
        effects,
        ..SuspendedConfig::default()
    };
    let log = simulate_suspended(ff, &cfg).map_err(|e| e.to_string())?;
    let d = diagnose_floating(ff, &truth(ff), &[log]).map_err(|e| e.to_string())?;
    let best = d.final_fit();
    match best {
        Some(c) if c.values.len() >= 4 => {
            let m = c.values[0].1;
            println!(
                "   a 0.3 kg payload at [0.05, 0, 0.03] m the URDF lacks (the diagnoser is not told): accepted {} ({:.0} % of the gap), {m:.3} kg at [{:.3}, {:.3}, {:.3}] m",
                c.effect.name(),
                100.0 * c.gap_closed,
                c.values[1].1 / m,
                c.values[2].1 / m,
                c.values[3].1 / m
            );
        }
        _ => println!("   a 0.3 kg payload the URDF lacks: no effect accepted"),
    }
    Ok(())
}
