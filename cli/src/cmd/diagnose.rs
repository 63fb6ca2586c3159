//! `momentlmi diagnose --robot MODEL --data FILE.csv [--nominal cad|true|FILE] [--json] [--out DIR]`.

use momentlmi::data::write_whole;
use momentlmi::data::{Dataset, ReadOptions};
use momentlmi::diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use momentlmi::dynamics::ParamChoice;
use momentlmi::dynamics::robots::load_robot;
use std::path::Path;

fn diagnosis(
    robot: &str,
    sidecar: Option<&Path>,
    data: &Path,
    nominal: Option<&str>,
) -> Result<Diagnosis, String> {
    let robot = load_robot(robot, sidecar).map_err(|e| e.to_string())?;
    if nominal == Some("true") {
        super::warn_robot(&robot);
    }
    let choice = nominal.map_or(ParamChoice::Own, |p| p.parse().expect("infallible"));
    let (model, friction) = robot.parameters(&choice).map_err(|e| e.to_string())?;
    let d = Dataset::read_csv(data, &model.joint_names(), ReadOptions::default())
        .map_err(|e| e.to_string())?;
    diagnose(&model, &friction, &d, &DiagnoseOptions::default()).map_err(|e| e.to_string())
}

/// `diagnosis.json` and the plots into `dir`.
fn write_outputs(dg: &Diagnosis, text: &str, dir: &Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    write_whole(&dir.join("diagnosis.json"), text).map_err(|e| e.to_string())?;
    crate::plots::diagnosis::write_plots(dg, dir).map(|_| ())
}

/// Exit codes: 0 diagnosed, 2 bad input.
pub fn run(
    robot: &str,
    sidecar: Option<&Path>,
    data: &Path,
    nominal: Option<&str>,
    json: bool,
    out: Option<&Path>,
) -> i32 {
    let dg = match diagnosis(robot, sidecar, data, nominal) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    for w in &dg.warnings {
        eprintln!("warning: {w}");
    }
    let text = match serde_json::to_string_pretty(&dg) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: the report: {e}");
            return 2;
        }
    };
    if let Some(dir) = out
        && let Err(e) = write_outputs(&dg, &text, dir)
    {
        eprintln!("error: {}: {e}", dir.display());
        return 2;
    }
    if json {
        println!("{text}");
    } else {
        print_report(&dg);
    }
    0
}

/// The human report: where, which, how far.
fn print_report(dg: &Diagnosis) {
    println!("Where the gap lies (held-out part, nominal model):");
    for s in &dg.summary {
        println!("  {s}");
    }
    println!(
        "\nWhich effects explain it (forward selection, fitted on the first part, scored on the held-out part):"
    );
    println!(
        "  {:<20} {:<26} {:>6} {:>9} {:>7}  held-out RMS before → after",
        "effect", "detail", "params", "ΔBIC", "z"
    );
    let mut round = 0;
    for e in &dg.ranked_effects {
        if e.round != round {
            round = e.round;
            println!("  — round {round}");
        }
        if !e.accepted && e.z < 3.0 {
            continue;
        }
        println!(
            "  {:<20} {:<26} {:>6} {:>9.1} {:>7.1}  {:?} → {:?}{}{}",
            e.effect,
            e.detail,
            e.params,
            e.delta_bic,
            e.z,
            e.heldout_rms_before
                .iter()
                .map(|x| format!("{x:.3}"))
                .collect::<Vec<_>>(),
            e.heldout_rms_after
                .iter()
                .map(|x| format!("{x:.3}"))
                .collect::<Vec<_>>(),
            if e.accepted { "  ACCEPTED" } else { "" },
            if e.tied_with.is_empty() {
                String::new()
            } else {
                format!(" (tied with {})", e.tied_with.join(", "))
            }
        );
    }
    println!("\nHow far:");
    for (i, j) in dg.joints.iter().enumerate() {
        println!(
            "  {j:<10} held-out RMS {:.3} → {:.3} N·m, noise floor {:.3}, gap closed {:.0} %",
            dg.heldout_rms_nominal[i],
            dg.heldout_rms_final[i],
            dg.noise_floor[i],
            100.0 * dg.gap_closed[i]
        );
    }
    if dg.unexplained {
        println!("\nUnexplained remainder:");
        for s in &dg.unexplained_where {
            println!("  {s}");
        }
    } else {
        println!("\nNothing left above the noise floor.");
    }
}
