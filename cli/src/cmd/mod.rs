//! One module per command; each `run` returns the process exit code (0
//! success, 1 a negative finding or an unsolved problem, 2 bad input).

pub mod check;
pub mod demo;
pub mod demo_arm;
pub mod diagnose;
pub mod identify;
pub mod predict;
pub mod sdpa;
pub mod simulate;

use std::path::Path;

/// Numbers for a text report, `a/b/c` (one per joint), `digits` decimals.
pub(crate) fn per_joint(v: &[f64], digits: usize) -> String {
    v.iter()
        .map(|x| format!("{x:.digits$}"))
        .collect::<Vec<_>>()
        .join("/")
}

/// The robot (a built-in name, or a URDF with its sidecar and mesh
/// folders), with its sidecar's `[effects]` names checked against the
/// built-in effects: a typo is an error here, whatever the command.
pub(crate) fn load_robot(
    spec: &str,
    sidecar: Option<&Path>,
    package_paths: &[std::path::PathBuf],
) -> Result<momentlmi::dynamics::RobotDescription, String> {
    let robot = momentlmi::dynamics::robots::load_robot_with(spec, sidecar, package_paths)
        .map_err(|e| e.to_string())?;
    momentlmi::effects::Library::builtin()
        .check_defaults(&robot)
        .map_err(|e| e.to_string())?;
    Ok(robot)
}

/// Warnings as JSON: each its `kind` and values, and its sentence as
/// `message` (the form the library's reports use).
pub(crate) fn warnings_json<W: serde::Serialize + std::fmt::Display>(
    warnings: &[W],
) -> Vec<serde_json::Value> {
    warnings
        .iter()
        .map(|w| {
            let mut v = serde_json::to_value(w).unwrap_or_default();
            if let Some(m) = v.as_object_mut() {
                m.insert("message".into(), w.to_string().into());
            }
            v
        })
        .collect()
}

/// Prints what the robot description filled in (placeholder friction, …).
pub(crate) fn warn_robot(robot: &momentlmi::dynamics::RobotDescription) {
    for w in &robot.warnings {
        eprintln!("warning: {}: {w}", robot.source);
    }
}

/// Reads a data file for the joints `names` of the robot `spec`; a missing
/// joint (its `q_` column) of a URDF robot given without `--sidecar` says
/// that a sidecar may be what locks the joint the data lack.
pub(crate) fn read_data(
    path: &Path,
    names: &[&str],
    opts: momentlmi::data::ReadOptions,
    spec: &str,
    sidecar: Option<&Path>,
) -> Result<momentlmi::data::Dataset, String> {
    use momentlmi::data::{DataError, Dataset};
    Dataset::read_csv(path, names, opts).map_err(|e| match e {
        DataError::MissingColumn { ref column, .. }
            if column.starts_with("q_") && sidecar.is_none() && Path::new(spec).is_file() =>
        {
            match simulated_with_sidecar(path) {
                Some(sc) => format!(
                    "{e}\nhint: the data were simulated with --sidecar {sc}; pass it here too"
                ),
                None => format!(
                    "{e}\nhint: {spec} has joints the data do not; if the data were made with a \
                     sidecar that locks them (a gripper's fingers, say), pass it with --sidecar FILE"
                ),
            }
        }
        e => e.to_string(),
    })
}

/// The sidecar a data file was simulated with, from the JSON `simulate`
/// writes beside it (`config.sidecar`), if that file is there, small and says so.
fn simulated_with_sidecar(data: &Path) -> Option<String> {
    let json = data.with_extension("json");
    if std::fs::metadata(&json).ok()?.len() > 64 << 20 {
        return None;
    }
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(json).ok()?).ok()?;
    v["config"]["sidecar"].as_str().map(str::to_string)
}

/// The model and friction of a parameter choice given with `flag`; an error
/// names the flag and, unless it is a file (whose errors name it), the
/// value typed.
pub(crate) fn parameters_for(
    robot: &momentlmi::dynamics::RobotDescription,
    flag: &str,
    value: Option<&str>,
    default: momentlmi::dynamics::ParamChoice,
) -> Result<(momentlmi::dynamics::Model, momentlmi::dynamics::Friction), String> {
    use momentlmi::dynamics::ParamChoice;
    let choice = value.map_or(default, |p| p.parse().expect("infallible"));
    robot
        .parameters(&choice)
        .map_err(|e| match (&choice, value) {
            (ParamChoice::File(_), _) | (_, None) => format!("{flag}: {e}"),
            (_, Some(v)) => format!("{flag} {v}: {e}"),
        })
}

/// The files a command reads, to protect from its outputs: `files`, and
/// each of `specs` (a robot or parameter choice: a built-in name, `cad`,
/// `true` or a path) that names an existing file.
pub(crate) fn input_files<'a>(files: &[&'a Path], specs: &[&'a str]) -> Vec<&'a Path> {
    let named = specs.iter().map(|s| Path::new(*s)).filter(|p| p.is_file());
    files.iter().copied().chain(named).collect()
}

/// An output folder: created if missing, and removed again (when still
/// empty) unless the command [`OutDir::keep`]s it, so a failed command
/// leaves no empty folder behind.
pub(crate) struct OutDir {
    path: std::path::PathBuf,
    created: bool,
}

impl OutDir {
    /// Creates `path` (and its parents) if it does not exist.
    pub(crate) fn create(path: &std::path::Path) -> Result<Self, String> {
        if path.exists() && !path.is_dir() {
            return Err(format!("{}: exists and is not a folder", path.display()));
        }
        let created = !path.exists();
        std::fs::create_dir_all(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(Self {
            path: path.to_path_buf(),
            created,
        })
    }

    /// The folder stays (its files were committed).
    pub(crate) fn keep(mut self) {
        self.created = false;
    }
}

impl Drop for OutDir {
    fn drop(&mut self) {
        if self.created {
            // only an empty folder goes: remove_dir refuses any other
            let _ = std::fs::remove_dir(&self.path);
        }
    }
}

/// `--max-memory-gib` in bytes (positive and finite).
pub(crate) fn gib(g: f64) -> Result<u64, String> {
    if g > 0.0 && g.is_finite() && g < 1e9 {
        Ok((g * (1u64 << 30) as f64) as u64)
    } else {
        Err(format!(
            "--max-memory-gib {g}: must be a positive number of GiB"
        ))
    }
}

/// Says up front when the reduction's arithmetic alone is large (≥ 10¹²
/// operations: minutes on a laptop core).
pub(crate) fn warn_cost(flops: f64) {
    if flops >= 1e12 {
        eprintln!(
            "warning: reducing these data takes about {flops:.1e} floating-point operations (minutes or more); fewer samples or locked joints take less"
        );
    }
}
