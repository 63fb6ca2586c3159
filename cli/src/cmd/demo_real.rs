//! The demo's fifth part: a real robot, the KUKA LWR4+ of
//! `robots/kuka-lwr4` — its runs read as published, identified on runs 1–2
//! at three settings and at the options docs/real-robot.md recommends,
//! validated on run 3 beside the two published models (their inertias
//! held, friction refit on the same runs), a figure of measured against
//! predicted torque on run 3, and the diagnosis of run 3 against the best
//! model with runs 1–2's repeatability as the noise floor. Its files are
//! named `real_*`.

use crate::plots::figures::{Series, line_panels};
use momentlmi::data::{Dataset, ReadOptions, Reading, Staged, read_logs};
use momentlmi::diagnose::floor::repeat_floor;
use momentlmi::diagnose::{DiagnoseOptions, diagnose};
use momentlmi::dynamics::FrictionTerm;
use momentlmi::dynamics::RobotDescription;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::identify::{Identification, IdentifyError, IdentifyResult, Level, Regularizer};
use std::path::{Path, PathBuf};

/// Where the repository keeps the KUKA (its runs are 5.8 MB: not built in).
pub fn kuka_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4")
}

/// One model's held-out accuracy on run 3.
#[derive(Clone, Debug)]
pub struct Row {
    /// The model.
    pub name: String,
    /// RMS of the torque error on run 3 per joint (N·m).
    pub rms: Vec<f64>,
    /// How it was made (or what is degenerate in it).
    pub note: String,
}

/// Runs the part, staging its figure; returns the table printed, or `None`
/// when the repository's KUKA files are not on this machine (a binary run
/// elsewhere).
pub fn run(
    (out, staged): (&Path, &mut Staged),
    tick: &mut dyn FnMut(&str),
) -> Result<Option<Vec<Row>>, String> {
    let dir = kuka_dir();
    if !dir.join("data/measurements_3.npz").is_file() {
        println!(
            "\n5. A real robot: skipped — robots/kuka-lwr4 is not beside this binary's sources"
        );
        return Ok(None);
    }
    println!(
        "\n5. A real robot: the KUKA LWR4+ (robots/kuka-lwr4), three runs as FloBaRoID published them"
    );
    tick("real robot: reading its runs");
    let sidecar = dir.join("kuka_lwr4.toml");
    let robot = load_kuka(&dir.join("kuka_lwr4.urdf"), Some(&sidecar))?;
    let run = |k: usize| dir.join(format!("data/measurements_{k}.npz"));
    let opts = super::ReadChoice {
        mapping: None,
        cutoff_hz: None,
        velocity: momentlmi::data::Velocity::Differentiate,
    }
    .options(&robot, true)?;
    let train = read(&robot, &opts, &[&run(1), &run(2)])?;
    let val = read(&robot, &opts, &[&run(3)])?;
    print_reading(&train, &val);
    let mut recommended = robot.clone();
    recommended.model = (recommended.model.clone()).with_friction_terms(&RECOMMENDED_FRICTION);
    let (mut rows, best) = our_rows((&robot, &recommended), (&train, &val), tick)?;
    tick("real robot: the published models");
    rows.extend(published_rows(&dir, &train, &val)?);
    print_rows(&rows);
    let (label, best) = best.ok_or("no identification")?;
    let svg = validation_figure(&best, label, &val.data)?;
    staged
        .add_text(&out.join("real_validation.svg"), &svg)
        .map_err(|e| e.to_string())?;
    println!(
        "   (file: real_validation.svg — run 3, measured and predicted by the best of ours, {label})"
    );
    tick("real robot: diagnosing run 3");
    print_diagnosis(
        &best
            .applied_to(&recommended.model)
            .map_err(|e| e.to_string())?,
        &train,
        &val,
    )?;
    Ok(Some(rows))
}

/// The friction terms docs/real-robot.md recommends for an arm with joint
/// torque sensors and harmonic drives.
pub const RECOMMENDED_FRICTION: [FrictionTerm; 5] = [
    FrictionTerm::Viscous,
    FrictionTerm::Coulomb,
    FrictionTerm::Offset,
    FrictionTerm::Load,
    FrictionTerm::Stribeck,
];

/// `diagnose` on run 3 against `nominal`, the noise floor from runs 1 and 2
/// (the training data's two segments): per joint, the held-out RMS before
/// and after the accepted effects against the floor.
fn print_diagnosis(
    (model, friction): &(momentlmi::dynamics::Model, momentlmi::dynamics::Friction),
    train: &Reading,
    val: &Reading,
) -> Result<(), String> {
    let runs: Vec<Dataset> = (train.data.segment_ranges().into_iter())
        .map(|r| train.data.slice(r))
        .collect();
    let [one, two] = &runs[..] else {
        return Err(format!("runs 1–2 read as {} segments, not 2", runs.len()));
    };
    let floor = repeat_floor(one, two, ["run 1", "run 2"]).map_err(|e| e.to_string())?;
    let opts = DiagnoseOptions::default().with_noise_floor(floor);
    let dg = diagnose(model, friction, &val.data, &opts).map_err(|e| e.to_string())?;
    println!(
        "   diagnosis of run 3 against the best (accepted: {}); noise floor: runs 1–2's repeatability",
        if dg.accepted.is_empty() {
            "none".into()
        } else {
            dg.accepted.join(", ")
        }
    );
    for (i, j) in dg.joints.iter().enumerate() {
        println!(
            "   {j:<12} held-out RMS {:.3} → {:.3} N·m, floor {:.3}, gap closed {:>3.0} %",
            dg.heldout_rms_nominal[i],
            dg.heldout_rms_final[i],
            dg.noise_floor[i],
            100.0 * dg.gap_closed[i]
        );
    }
    Ok(())
}

fn load_kuka(urdf: &Path, sidecar: Option<&Path>) -> Result<RobotDescription, String> {
    let spec = urdf.to_str().ok_or("a non-UTF-8 path")?;
    load_robot(spec, sidecar).map_err(|e| e.to_string())
}

/// Runs read as the command line reads them with no option (the sidecar's
/// mapping as the default).
fn read(robot: &RobotDescription, opts: &ReadOptions, paths: &[&Path]) -> Result<Reading, String> {
    read_logs(paths, &robot.model.joint_names(), opts).map_err(|e| e.to_string())
}

fn print_reading(train: &Reading, val: &Reading) {
    let files = train.files.iter().chain(&val.files);
    let cut: Vec<String> = files.map(|f| format!("{:.1}", f.cutoff_hz)).collect();
    println!(
        "   read: Unix stamps 3–7 ms apart resampled at {:.0} Hz, q and τ low-passed alike at {} Hz (chosen from each run's spectrum), q̇ and q̈ differentiated",
        train.files[0].resampled_hz,
        cut.join(", ")
    );
    println!(
        "   trained on runs 1–2 ({} samples), validated on run 3 ({} samples); RMS of the torque error on run 3 (N·m):",
        train.data.len(),
        val.data.len()
    );
}

fn mean(r: &IdentifyResult) -> f64 {
    let v = r.validation_rms.as_deref().unwrap_or(&[]);
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

fn ours(label: &str, r: &IdentifyResult) -> Row {
    let degenerate = r.degenerate_bodies.len();
    Row {
        name: format!("momentlmi, {label}"),
        rms: r.validation_rms.clone().unwrap_or_default(),
        note: format!(
            "{} of {} bodies degenerate, solve {:.0} ms",
            degenerate,
            r.bodies.len(),
            1e3 * r.solve_time_s
        ),
    }
}

fn print_rows(rows: &[Row]) {
    for r in rows {
        let m = r.rms.iter().sum::<f64>() / r.rms.len().max(1) as f64;
        println!(
            "   {:<37} {}  mean {m:.3}  ({})",
            r.name,
            super::per_joint(&r.rms, 2),
            r.note
        );
    }
}

/// A published model's held-out accuracy with its own inertias: every
/// body's ten parameters held at the model's, friction fitted on `train`.
fn friction_refit(
    anchor: &RobotDescription,
    train: &Dataset,
    val: &Dataset,
) -> Result<IdentifyResult, IdentifyError> {
    let prior = anchor.prior_vector();
    let names = anchor.model.body_names();
    Identification::new(&anchor.model)
        .level_all(Level::None)
        .constrain(move |p, v| {
            for (b, name) in names.iter().enumerate() {
                for (i, x) in v.body(name)?.params().iter().enumerate() {
                    p.add_eq(x.clone(), prior[10 * b + i])?;
                }
            }
            Ok(())
        })
        .identify(train, Some(val))
}

/// Measured and predicted torques of every joint on run 3.
fn validation_figure(r: &IdentifyResult, label: &str, val: &Dataset) -> Result<String, String> {
    let t0 = val.t.first().copied().unwrap_or(0.0);
    let predicted = format!("predicted (momentlmi, {label})");
    let panels: Vec<Vec<Series>> = (0..val.joints.len())
        .map(|i| {
            let s = |label, v: &momentlmi::data::Samples, color| Series {
                label,
                points: val.t.iter().zip(v).map(|(t, x)| (t - t0, x[i])).collect(),
                color,
            };
            vec![
                s("measured (joint torque sensor)", &val.tau, 0),
                s(&predicted, &r.validation_prediction, 1),
            ]
        })
        .collect();
    line_panels(
        "KUKA LWR4+, run 3 (held out): joint torques measured and predicted",
        "t [s]",
        &val.joints,
        "τ [N·m]",
        &panels,
        false,
    )
}

/// Our identifications of runs 1–2 at each level (the last at the
/// recommended options, `recommended`'s law), held out on run 3; the rows
/// and the best of them.
fn our_rows(
    (robot, recommended): (&RobotDescription, &RobotDescription),
    (train, val): (&Reading, &Reading),
    tick: &mut dyn FnMut(&str),
) -> Result<(Vec<Row>, Option<(&'static str, IdentifyResult)>), String> {
    let mut rows = vec![];
    let mut best: Option<(&str, IdentifyResult)> = None;
    for (label, robot, level, reg, w) in [
        (
            "consistent",
            robot,
            Level::Consistent,
            Regularizer::Euclidean,
            1e-6,
        ),
        (
            "ellipsoid",
            robot,
            Level::Ellipsoid,
            Regularizer::Euclidean,
            1e-6,
        ),
        (
            "ellipsoid + entropic 1e-3",
            robot,
            Level::Ellipsoid,
            Regularizer::Entropic,
            1e-3,
        ),
        (
            "recommended: ellipsoid + entropic 1e-2, offset, load, Stribeck",
            recommended,
            Level::Ellipsoid,
            Regularizer::Entropic,
            1e-2,
        ),
    ] {
        tick(&format!("real robot: identifying ({label})"));
        let r = Identification::for_robot(robot, level, w)
            .map(|id| id.regularizer(reg))
            .and_then(|id| id.identify(&train.data, Some(&val.data)))
            .map_err(|e| format!("{label}: {e}"))?;
        rows.push(ours(label, &r));
        if best.as_ref().is_none_or(|(_, b)| mean(&r) < mean(b)) {
            best = Some((label, r));
        }
    }
    Ok((rows, best))
}

/// The published models' inertias, their viscous and Coulomb friction
/// refit on runs 1–2, held out on run 3.
fn published_rows(dir: &Path, train: &Reading, val: &Reading) -> Result<Vec<Row>, String> {
    let mut rows = vec![];
    for (file, who) in [
        ("kuka_lwr4_identified.urdf", "FloBaRoID's identified model"),
        ("kuka_lwr4_gaz.urdf", "Gaz, Flacco & De Luca 2014"),
    ] {
        let anchor = load_kuka(&dir.join("anchors").join(file), None)?;
        let r =
            friction_refit(&anchor, &train.data, &val.data).map_err(|e| format!("{file}: {e}"))?;
        rows.push(Row {
            name: who.into(),
            rms: r.validation_rms.clone().unwrap_or_default(),
            note: "its inertias; viscous + Coulomb refit on runs 1–2".into(),
        });
    }
    Ok(rows)
}
