//! The demo's fourth part: "your own URDF", the Panda arm of `robots/panda`
//! through the same code path as the leg — its CAD inertias checked against
//! its meshes, simulated data, identification at two levels, a figure and a
//! diagnosis of an arm with an encoder zero offset. Its files are named
//! `arm_*`.

use crate::plots::figures::{Series, line_panels};
use momentlmi::data::{Dataset, Staged};
use momentlmi::diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use momentlmi::dynamics::RobotDescription;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::effects::simulate;
use momentlmi::identify::{Identification, IdentifyResult, Level};
use momentlmi::moments::urdf_check::check_urdf_file;
use momentlmi::sim::{Effects, SimConfig};
use std::path::{Path, PathBuf};

/// Where the repository keeps the arm.
fn arm_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/panda")
}

/// The arm's files, built into the binary (188 KiB): the URDF, its sidecar,
/// the collision meshes and their licence, at their paths below `robots/panda`.
macro_rules! embedded {
    ($($path:literal),* $(,)?) => {
        [$(($path, include_bytes!(concat!("../../../robots/panda/", $path)) as &[u8])),*]
    };
}
const ARM_FILES: [(&str, &[u8]); 13] = embedded![
    "panda.urdf",
    "panda.toml",
    "example-robot-data/robots/panda_description/LICENSE",
    "example-robot-data/robots/panda_description/meshes/collision/link0.stl",
    "example-robot-data/robots/panda_description/meshes/collision/link1.stl",
    "example-robot-data/robots/panda_description/meshes/collision/link2.stl",
    "example-robot-data/robots/panda_description/meshes/collision/link3.stl",
    "example-robot-data/robots/panda_description/meshes/collision/link4.stl",
    "example-robot-data/robots/panda_description/meshes/collision/link5.stl",
    "example-robot-data/robots/panda_description/meshes/collision/link6.stl",
    "example-robot-data/robots/panda_description/meshes/collision/link7.stl",
    "example-robot-data/robots/panda_description/meshes/collision/hand.stl",
    "example-robot-data/robots/panda_description/meshes/collision/finger.stl",
];

/// The folder holding `panda.urdf` and `panda.toml`: the repository's when it
/// is on this machine, else the embedded copy written to a temporary folder
/// (kept alive by the returned guard).
fn arm_files() -> Result<(PathBuf, Option<tempfile::TempDir>), String> {
    let dir = arm_dir();
    if dir.join("panda.urdf").is_file() {
        return Ok((dir, None));
    }
    let tmp = tempfile::tempdir().map_err(|e| format!("a temporary folder for the arm: {e}"))?;
    write_embedded_arm(tmp.path())?;
    Ok((tmp.path().to_path_buf(), Some(tmp)))
}

/// Writes the arm's embedded files below `dir` (`dir/panda.urdf`, …).
pub fn write_embedded_arm(dir: &Path) -> Result<(), String> {
    for (path, bytes) in ARM_FILES {
        let p = dir.join(path);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
        }
        std::fs::write(&p, bytes).map_err(|e| format!("{}: {e}", p.display()))?;
    }
    Ok(())
}

/// Runs the arm's part (`tick(what)` per stage), staging its files.
pub fn run((out, staged): (&Path, &mut Staged), tick: &mut dyn FnMut(&str)) -> Result<(), String> {
    let (dir, _guard) = arm_files()?;
    let (urdf, sidecar) = (dir.join("panda.urdf"), dir.join("panda.toml"));
    println!(
        "\n4. Your own URDF: the Panda arm (robots/panda), the same commands and code path as the leg"
    );
    tick("arm: checking its inertias against its meshes");
    let (_, report) = check_urdf_file(&urdf, &[]).map_err(|e| e.to_string())?;
    let not: Vec<&str> = report
        .links
        .iter()
        .filter(|l| l.realizable_in_geometry == Some(false))
        .map(|l| l.name.as_str())
        .collect();
    println!(
        "   check: {} links with inertials, all consistent: {}; not density realizable in their collision meshes: {}",
        report.links.len(),
        report.consistent,
        if not.is_empty() {
            "none".into()
        } else {
            not.join(", ")
        }
    );
    let robot = load_robot(urdf.to_str().ok_or("a non-UTF-8 path")?, Some(&sidecar))
        .map_err(|e| e.to_string())?;
    tick("arm: simulating");
    let sim = |effects: &str, seed| -> Result<Dataset, String> {
        let fx = Effects::parse(effects, &[]).map_err(|e| e.to_string())?;
        let cfg = SimConfig::for_robot(&robot, 15.0, fx, seed);
        simulate(&robot, &cfg, |_, _| {}).map_err(|e| e.to_string())
    };
    let (train, val) = (sim("coulomb,viscous", 1)?, sim("coulomb,viscous", 2)?);
    let mut fits = vec![];
    println!("   validation RMS on 15 s of other data (N·m; σ = 0.3), 15 s of training data:");
    for level in [Level::Consistent, Level::Ellipsoid] {
        tick(&format!("arm: identifying ({})", level.as_str()));
        let r = Identification::for_robot(&robot, level, 1e-6)
            .and_then(|id| id.identify(&train, Some(&val)))
            .map_err(|e| e.to_string())?;
        print_level(&r);
        fits.push(r);
    }
    // the model a user would keep: the lower mean validation RMS
    let mean_rms = |r: &IdentifyResult| {
        let v = r.validation_rms.as_deref().unwrap_or(&[]);
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let best = fits
        .into_iter()
        .min_by(|a, b| mean_rms(a).total_cmp(&mean_rms(b)))
        .ok_or("no identification")?;
    staged
        .add_text(
            &out.join("arm_validation.svg"),
            &validation_figure(&best, &val)?,
        )
        .map_err(|e| e.to_string())?;
    tick("arm: diagnosing");
    let d = diagnose_arm(&robot, &best, &sim("coulomb,viscous,joint_offset", 7)?)?;
    stage_diagnosis(&d, (out, staged))?;
    print_diagnosis(&d, best.constraints.as_str());
    Ok(())
}

fn print_level(r: &IdentifyResult) {
    let rms = r.validation_rms.as_deref().unwrap_or(&[]);
    println!(
        "   {:<11} {}   consistent {}/{}, solve {:.1} ms",
        r.constraints.as_str(),
        rms.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(" "),
        r.bodies.iter().filter(|b| b.consistent).count(),
        r.bodies.len(),
        1e3 * r.solve_time_s
    );
}

/// Measured and predicted held-out torques of every joint, the first 5 s.
fn validation_figure(r: &IdentifyResult, val: &Dataset) -> Result<String, String> {
    let k = val.len().min(5000);
    let t = &val.t[..k];
    let predicted = format!("predicted ({} level)", r.constraints.as_str());
    let panels: Vec<Vec<Series>> = (0..val.joints.len())
        .map(|i| {
            let s = |label, v: &momentlmi::data::Samples, color| Series {
                label,
                points: t.iter().zip(v).map(|(t, x)| (*t, x[i])).collect(),
                color,
            };
            vec![
                s("measured", &val.tau, 0),
                s(&predicted, &r.validation_prediction, 1),
            ]
        })
        .collect();
    line_panels(
        "Panda: held-out torques, measured and predicted",
        "t [s]",
        &val.joints,
        "τ [N·m]",
        &panels,
        false,
    )
}

fn diagnose_arm(
    robot: &RobotDescription,
    best: &IdentifyResult,
    data: &Dataset,
) -> Result<Diagnosis, String> {
    let (nominal, friction) = best.applied_to(&robot.model).map_err(|e| e.to_string())?;
    diagnose(&nominal, &friction, data, &DiagnoseOptions::default()).map_err(|e| e.to_string())
}

fn stage_diagnosis(d: &Diagnosis, (out, staged): (&Path, &mut Staged)) -> Result<(), String> {
    let e = |e: momentlmi::data::DataError| e.to_string();
    let json = serde_json::to_string_pretty(d).map_err(|e| e.to_string())?;
    staged
        .add_text(&out.join("arm_diagnosis.json"), &json)
        .map_err(e)?;
    for (name, svg) in crate::plots::diagnosis::render_plots(d)? {
        staged
            .add_text(&out.join(format!("arm_{name}")), &svg)
            .map_err(e)?;
    }
    Ok(())
}

fn print_diagnosis(d: &Diagnosis, level: &str) {
    println!(
        "   diagnosis of an arm whose encoders are 0.05 rad off zero (the diagnoser is not told),"
    );
    println!("   against the {level} model (the lower validation RMS above):");
    for e in d.ranked_effects.iter().filter(|e| e.accepted) {
        let tied = e.ties();
        let detail = if e.detail.is_empty() {
            String::new()
        } else {
            format!(", {}", e.detail)
        };
        println!(
            "   which: {}{detail}{tied} — held-out RMS {} → {} N·m",
            e.label(),
            super::per_joint(&e.heldout_rms_before, 2),
            super::per_joint(&e.heldout_rms_after, 2)
        );
    }
    println!(
        "   {}",
        if d.unexplained {
            "a remainder is unexplained (see arm_diagnosis.json)"
        } else {
            "nothing left above the noise floor"
        }
    );
    println!(
        "   (files: arm_validation.svg, arm_diagnosis.json, arm_residual_<joint>.svg, arm_effects.svg)"
    );
}
