//! `momentlmi demo [--out DIR]`: the paper's experiment on a simulated
//! Cheetah 3 leg — simulate, identify at every constraint level, validate on
//! held-out data, write figures and tables — plus a check of the leg's
//! identified inertias and a diagnosis of a "real" leg.

use crate::experiment::{ExperimentConfig, ExperimentSummary, run_experiment};
use momentlmi::data::Staged;
use momentlmi::diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use momentlmi::dynamics::{RobotDescription, cheetah3};
use momentlmi::effects::simulate;
use momentlmi::identify::IdentifyResult;
use momentlmi::moments::{check_consistency, check_realizable};
use momentlmi::sim::{Effects, SimConfig};
use std::path::Path;

/// The effects the "real" leg has that the identified model lacks.
const WITHHELD: [&str; 2] = ["offset", "cogging"];

/// 1. The leg's identified inertias, checked.
fn check_leg(robot: &RobotDescription) {
    println!(
        "1. The leg's identified inertias, checked (J ≻ 0 and tr(JQ) ≥ 0 in each bounding ellipsoid):"
    );
    let params = robot.model.params();
    for (k, name) in robot.model.body_names().iter().enumerate() {
        let pi = momentlmi::moments::InertialParams(std::array::from_fn(|i| params[10 * k + i]));
        let Some(e) = robot.bounding()[k].first() else {
            continue;
        };
        let c = check_consistency(&pi, 1e-12);
        let r = check_realizable(&pi, e, 1e-12);
        println!(
            "   {name:<11} mass {:.3} kg  λmin(J) {:>9.2e}  tr(JQ) {:>7.3}  {}",
            pi.mass(),
            c.pseudo_inertia_min_eig,
            r.trace_jq,
            if r.realizable {
                "realizable"
            } else {
                "NOT realizable"
            }
        );
    }
}

/// 2. The experiment, with a progress bar.
fn experiment(
    out: (&Path, &mut Staged),
    cfg: &ExperimentConfig,
) -> Result<(ExperimentSummary, Vec<IdentifyResult>), String> {
    println!(
        "\n2. Simulating {} + {} samples at 1 kHz (shell excitation, rotors, Coulomb + viscous friction, σ = {} N·m), identifying with w = {:e} toward the CAD prior…",
        cfg.train, cfg.validate, cfg.noise, cfg.weight
    );
    let bar = indicatif::ProgressBar::new(1);
    if let Ok(style) = indicatif::ProgressStyle::with_template("   {bar:40} {pos}/{len} {msg}") {
        bar.set_style(style);
    }
    let res = run_experiment(out, cfg, |step, total, what| {
        bar.set_length(total as u64);
        bar.set_position(step as u64);
        bar.set_message(what.to_string());
    });
    bar.finish_and_clear();
    res
}

fn print_levels(summary: &ExperimentSummary, cfg: &ExperimentConfig) {
    println!(
        "\n   validation RMS on the next {} samples (N·m):",
        cfg.validate
    );
    println!(
        "   {:<11} {:>8} {:>8} {:>8} {:>8}   {:>10}  {:<22} {:>9}",
        "constraints",
        "ab/ad",
        "hip",
        "knee",
        "overall",
        "consistent",
        "Coulomb B_c (N·m)",
        "solve"
    );
    for l in &summary.levels {
        println!(
            "   {:<11} {:>8.3} {:>8.3} {:>8.3} {:>8.3}   {:>8}/6  ({:.2}, {:.2}, {:.2})     {:>6.1} ms",
            l.constraints.as_str(),
            l.validation_rms[0],
            l.validation_rms[1],
            l.validation_rms[2],
            l.overall_rms,
            l.consistent_bodies,
            l.coulomb[0],
            l.coulomb[1],
            l.coulomb[2],
            1e3 * l.solve_time_s
        );
    }
    println!(
        "   (true B_c = (3.12, 1.25, 0.95); the noise floor is σ = {} N·m)",
        cfg.noise
    );
}

fn print_study(summary: &ExperimentSummary, cfg: &ExperimentConfig, out: &Path) {
    println!("\n   validation RMS vs training samples (Fig. 6):");
    print!("   {:<11}", "samples");
    for n in &cfg.sizes {
        print!(" {n:>7}");
    }
    println!();
    for l in &summary.levels {
        print!("   {:<11}", l.constraints.as_str());
        for (_, _, r) in summary.sample_study.iter().filter(|s| s.0 == l.constraints) {
            print!(" {r:>7.3}");
        }
        println!();
    }
    print_regularizers(summary);
    println!("\n   files in {}:", out.display());
    for f in &summary.files {
        println!("     {f}");
    }
}

/// The Euclidean-against-entropic table (Fig. 7).
fn print_regularizers(summary: &ExperimentSummary) {
    println!(
        "\n   Euclidean vs entropic prior (ellipsoid level; weight chosen on held-out data, Fig. 7):"
    );
    println!(
        "   {:<10} {:>7} {:>9} {:>9} {:>14} {:>10}",
        "prior", "samples", "weight", "test RMS", "Σ d(J‖Jtrue)", "‖π−πtrue‖"
    );
    for r in &summary.regularizers {
        let div = r
            .divergence_from_truth
            .map_or_else(|| "singular".to_string(), |d| format!("{d:.3}"));
        let edge = if r.at_grid_edge { "*" } else { " " };
        println!(
            "   {:<10} {:>7} {:>8.0e}{edge} {:>9.4} {div:>14} {:>10.4}",
            r.regularizer.as_str(),
            r.samples,
            r.weight,
            r.test_rms,
            r.euclidean_error
        );
    }
    println!("   (* the best weight is at the edge of its grid)");
}

/// 3. A "real" leg with effects the model lacks, diagnosed against the
/// ellipsoid-level fit; stages `diagnosis.json` and the plots.
fn diagnose_real_leg(
    robot: &RobotDescription,
    best: &IdentifyResult,
    (out, staged): (&Path, &mut Staged),
) -> Result<Diagnosis, String> {
    let effects = Effects::new(
        ["rotor_inertia", "coulomb", "viscous"]
            .into_iter()
            .chain(WITHHELD),
    );
    let cfg = SimConfig::for_robot(robot, 15.0, effects, 2);
    let data = simulate(robot, &cfg, |_, _| {}).map_err(|e| e.to_string())?;
    let (nominal, friction) = best.applied_to(&robot.model).map_err(|e| e.to_string())?;
    let d = diagnose(&nominal, &friction, &data, &DiagnoseOptions::default())
        .map_err(|e| e.to_string())?;
    staged
        .add_text(
            &out.join("diagnosis.json"),
            &serde_json::to_string_pretty(&d).map_err(|e| e.to_string())?,
        )
        .map_err(|e| e.to_string())?;
    for (name, svg) in crate::plots::diagnosis::render_plots(&d)? {
        staged
            .add_text(&out.join(name), &svg)
            .map_err(|e| e.to_string())?;
    }
    Ok(d)
}

fn print_diagnosis(d: &Diagnosis, out: &Path) {
    for s in &d.summary {
        println!("   where: {s}");
    }
    for e in d.ranked_effects.iter().filter(|e| e.accepted) {
        let detail = if e.detail.is_empty() {
            String::new()
        } else {
            format!(" {}", e.detail)
        };
        println!(
            "   which: {}{detail}{} — held-out RMS {} → {} N·m",
            e.label(),
            e.ties(),
            super::per_joint(&e.heldout_rms_before, 2),
            super::per_joint(&e.heldout_rms_after, 2),
        );
    }
    println!(
        "   how far: gap above the noise floor closed {} %; {}",
        super::per_joint(
            &d.gap_closed.iter().map(|x| 100.0 * x).collect::<Vec<_>>(),
            0
        ),
        if d.unexplained {
            "a remainder is unexplained (see diagnosis.json)"
        } else {
            "nothing left above the noise floor"
        }
    );
    for w in &d.warnings {
        println!("   warning: {w}");
    }
    println!(
        "   (full report: {}; plots: residual_<joint>.svg, effects.svg)",
        out.join("diagnosis.json").display()
    );
}

/// Runs the demo; returns the exit code. Every file is written at the end,
/// together, or none is.
pub fn run(out: &Path) -> i32 {
    match run_inner(out) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

fn run_inner(out: &Path) -> Result<(), String> {
    println!(
        "momentlmi demo — physically consistent identification of a Cheetah 3 leg (Wensing, Kim & Slotine 2017)\n"
    );
    let robot = cheetah3::description();
    check_leg(&robot);
    let cfg = ExperimentConfig::default();
    let dir = super::OutDir::create(out)?;
    let mut staged = Staged::new();
    let (summary, results) = experiment((out, &mut staged), &cfg)?;
    print_levels(&summary, &cfg);
    print_study(&summary, &cfg, out);
    println!(
        "\n3. Diagnosing a \"real\" leg against the identified model (ellipsoid level); the diagnoser is not told that the data contain: {}",
        WITHHELD.join(", ")
    );
    let best = results.last().ok_or("no identification result")?;
    let d = diagnose_real_leg(&robot, best, (out, &mut staged))
        .map_err(|e| format!("diagnosis: {e}"))?;
    print_diagnosis(&d, out);
    let bar = indicatif::ProgressBar::new(16); // the arm's 5 stages, the real robot's 7, the floating base's 4
    if let Ok(style) = indicatif::ProgressStyle::with_template("   {bar:40} {pos}/{len} {msg}") {
        bar.set_style(style);
    }
    let mut tick = |what: &str| {
        bar.set_message(what.to_string());
        bar.inc(1);
    };
    let arm = super::demo_arm::run((out, &mut staged), &mut tick);
    let real = arm.map_err(|e| format!("the arm: {e}")).and_then(|()| {
        super::demo_real::run((out, &mut staged), &mut tick)
            .map_err(|e| format!("the real robot: {e}"))
            .map(|_| ())
    });
    let real = real.and_then(|()| {
        super::demo_floating::run((out, &mut staged), &mut tick)
            .map_err(|e| format!("the floating base: {e}"))
    });
    bar.finish_and_clear();
    real?;
    staged.commit().map_err(|e| e.to_string())?;
    dir.keep();
    println!(
        "
   every file is in {}",
        out.display()
    );
    Ok(())
}
