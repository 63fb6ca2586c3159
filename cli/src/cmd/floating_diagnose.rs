//! `diagnose --floating-base`: where a floating-base robot's nominal model
//! misses its logs, and which unmodelled effect explains it
//! (`momentlmi::diagnose::floating`).

use super::diagnose::DiagnoseArgs;
use super::floating::theta_of;
use super::floating::{Robot, read_logs, reading_options, refuse};
use momentlmi::data::Staged;
use momentlmi::diagnose::floating::{
    FloatingCandidate, FloatingDiagnosis, FloatingEffect, diagnose_floating,
};
use std::path::Path;

/// Diagnoses; exit 0 done, 2 bad input.
pub fn run(a: &DiagnoseArgs, robot: Robot) -> i32 {
    match diagnosis(a, robot) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

fn diagnosis(a: &DiagnoseArgs, robot: Robot) -> Result<(), String> {
    refuse(&[
        ("--repeats", !a.repeats.is_empty()),
        ("--nominal-data", !a.nominal_data.is_empty()),
    ])?;
    refuse(&reading_options(&a.read.choice()))?;
    let files: Vec<&Path> = a.data.iter().map(|p| p.as_path()).collect();
    let inputs = a
        .robot
        .inputs_with(&files, &[a.nominal.as_deref().unwrap_or("")]);
    if let Some(dir) = a.out.as_deref().filter(|d| d.exists() && !d.is_dir()) {
        return Err(format!(
            "--out {}: exists and is not a folder",
            dir.display()
        ));
    }
    let described = robot.describe(&a.robot.package_path)?;
    let (ff, friction) =
        super::floating::with_params(&described, a.nominal.as_deref(), "--nominal")?;
    let logs = read_logs(&ff, &a.data, ("--data", a.max_memory_gib))?;
    let d = diagnose_floating(&ff, &theta_of(&ff, &friction), &logs).map_err(|e| e.to_string())?;
    let json = serde_json::to_string_pretty(&d).map_err(|e| e.to_string())?;
    if let Some(dir) = a.out.as_deref() {
        let folder = super::OutDir::create(dir)?;
        let mut staged = Staged::protecting(inputs);
        let e = |e: momentlmi::data::DataError| e.to_string();
        staged
            .add_text(&dir.join("floating_diagnosis.json"), &json)
            .map_err(e)?;
        staged.commit().map_err(e)?;
        folder.keep();
    }
    if a.json {
        println!("{json}");
    } else {
        print!("{}", report_text(&d));
    }
    Ok(())
}

/// The text report: where, which, how far.
fn report_text(d: &FloatingDiagnosis) -> String {
    let mut out = format!(
        "floating base: {} samples fitted, {} held out (each log's first 70 % fitted)\nwhere (held-out RMS / noise floor; > 1.1 marked *):\n",
        d.samples[0], d.samples[1]
    );
    for ((row, r), f) in d.rows.iter().zip(&d.held_out).zip(&d.floor) {
        let ratio = r / f.max(1e-12);
        out += &format!(
            "  {row:<18} {r:>9.4} / {f:<9.4} {ratio:>6.2}{}\n",
            if ratio > 1.1 { " *" } else { "" }
        );
    }
    out += "which (forward selection; share of the held-out gap above the floor closed with the effects before):\n";
    for (k, r) in d.rounds.iter().enumerate() {
        for c in &r.candidates {
            let mark = if Some(c.effect) == r.accepted {
                "  accepted"
            } else {
                ""
            };
            let name = c.effect.name();
            out += &format!(
                "  round {}  {name:<16} {:>7.1} %{mark}\n",
                k + 1,
                100.0 * c.gap_closed
            );
        }
    }
    for c in d.accepted_fits() {
        out += &format!("accepted: {}: {}\n", c.effect.name(), values(c));
    }
    match d.final_fit() {
        Some(c) => {
            let left: Vec<&str> = (d.rows.iter().zip(&c.held_out).zip(&d.floor))
                .filter(|((_, r), f)| **r > 1.1 * **f)
                .map(|((n, _), _)| n.as_str())
                .collect();
            if !left.is_empty() {
                out += &format!(
                    "left: {} rows still above 1.1 × their floor ({}): a cause none of the candidates is\n",
                    left.len(),
                    left.join(", ")
                );
            }
        }
        None => {
            out += "accepted: none closes half the gap (the model explains the data, or the cause is none of these)\n"
        }
    }
    out
}

/// The accepted effect's fitted values, in the words of its kind.
fn values(c: &FloatingCandidate) -> String {
    let v = &c.values;
    match c.effect {
        FloatingEffect::Payload => {
            let m = v[0].1;
            format!(
                "{:+.4} kg on the base at [{:.4}, {:.4}, {:.4}] m (base frame)",
                m,
                v[1].1 / m,
                v[2].1 / m,
                v[3].1 / m
            )
        }
        FloatingEffect::BodyParameters => {
            format!("{} parameters (every body's; in --json)", v.len())
        }
        _ => (v.iter())
            .map(|(n, x)| format!("{n} {x:+.4}"))
            .collect::<Vec<_>>()
            .join(", "),
    }
}
