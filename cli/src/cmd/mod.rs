//! One module per command; each `run` returns the process exit code (0
//! success, 1 a negative finding or an unsolved problem, 2 bad input).

pub mod args;
pub mod check;
pub mod demo;
pub mod demo_arm;
pub mod demo_floating;
pub mod demo_real;
pub mod diagnose;
pub mod excite;
pub mod export;
pub mod floating;
pub mod floating_diagnose;
pub mod floating_identify;
pub mod floating_predict;
pub mod floating_simulate;
pub mod identify;
pub mod predict;
pub mod route;
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
/// built-in effects: a typo is an error here, whatever the command; its
/// URDF's root link a free-flying base when `free_flyer`
/// ([`momentlmi::dynamics::robots::load_free_flyer`]).
pub(crate) fn load_robot_rooted(
    spec: &str,
    sidecar: Option<&Path>,
    package_paths: &[std::path::PathBuf],
    free_flyer: bool,
) -> Result<momentlmi::dynamics::RobotDescription, String> {
    use momentlmi::dynamics::robots::{load_free_flyer, load_robot_with};
    let load = if free_flyer {
        load_free_flyer
    } else {
        load_robot_with
    };
    let mut robot = load(spec, sidecar, package_paths).map_err(|e| e.to_string())?;
    if let Some(cache) = solve_cache() {
        robot = robot.with_bounding_cache(cache);
    }
    momentlmi::effects::Library::builtin()
        .check_defaults(&robot)
        .map_err(|e| e.to_string())?;
    Ok(robot)
}

/// Where solved bounding ellipsoids are kept between runs
/// ([`SolveCache::from_env`](momentlmi::moments::cache::SolveCache::from_env)).
pub(crate) fn solve_cache() -> Option<momentlmi::moments::cache::SolveCache> {
    momentlmi::moments::cache::SolveCache::from_env()
}

/// A URDF's own sidecar: `NAME.toml` beside `NAME.urdf`, if there is one.
pub(crate) fn sidecar_beside(spec: &str) -> Option<std::path::PathBuf> {
    let p = Path::new(spec);
    let is_urdf = p
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("urdf"));
    let toml = p.with_extension("toml");
    (is_urdf && p.is_file() && toml.is_file()).then_some(toml)
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

/// How the user asked for logs to be read (`--mapping`, `--cutoff-hz`,
/// `--velocity`).
#[derive(Clone, Copy, Debug)]
pub struct ReadChoice<'a> {
    /// `--mapping`.
    pub mapping: Option<&'a Path>,
    /// `--cutoff-hz`.
    pub cutoff_hz: Option<f64>,
    /// `--velocity`.
    pub velocity: momentlmi::data::Velocity,
}

impl ReadChoice<'_> {
    /// The library's options: the mapping given, else the robot's default
    /// (its sidecar's `[data] mapping`).
    pub(crate) fn options(
        &self,
        robot: &momentlmi::dynamics::RobotDescription,
        require_tau: bool,
    ) -> Result<momentlmi::data::ReadOptions, String> {
        let path = self
            .mapping
            .map(Path::to_path_buf)
            .or_else(|| robot.data_mapping.clone());
        let mapping = path
            .map(|p| momentlmi::data::Mapping::read(&p))
            .transpose()
            .map_err(|e| {
                let from = if self.mapping.is_some() {
                    "--mapping"
                } else {
                    "the sidecar's [data] mapping"
                };
                format!("{from}: {e}")
            })?;
        let opts = momentlmi::data::ReadOptions {
            cutoff_hz: self.cutoff_hz,
            velocity: self.velocity,
            require_tau,
            mapping,
            mapping_is_default: self.mapping.is_none(),
        };
        opts.check().map_err(|e| format!("--cutoff-hz: {e}"))?;
        Ok(opts)
    }
}

/// Without `--cutoff-hz`, the raw-log cut-off an identification chose on
/// its training logs, when `params` is its JSON report
/// (`data_preparation.cutoff_choice.chosen_hz`): a model is used on data
/// prepared as the data it was fitted on. `opts` takes it, with a note.
pub(crate) fn cutoff_of_model(
    opts: &mut momentlmi::data::ReadOptions,
    params: Option<&str>,
    flag: &str,
) {
    let Some(path) = params.filter(|_| opts.cutoff_hz.is_none()) else {
        return;
    };
    let chosen = std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|j| j["data_preparation"]["cutoff_choice"]["chosen_hz"].as_f64())
        .filter(|c| c.is_finite() && *c > 0.0);
    if let Some(c) = chosen {
        eprintln!(
            "note: raw logs low-passed at {c:.3} Hz, the cut-off {flag} {path} was identified with (--cutoff-hz sets another)"
        );
        opts.cutoff_hz = Some(c);
    }
}

/// Reads log files (each a segment) for the joints `names` of the robot
/// `spec`; a missing joint (its `q_` column) of a URDF robot given without
/// `--sidecar` says that a sidecar may be what locks the joint the data lack.
pub(crate) fn read_data(
    paths: &[&Path],
    names: &[&str],
    opts: &momentlmi::data::ReadOptions,
    spec: &str,
    sidecar: Option<&Path>,
) -> Result<momentlmi::data::Reading, String> {
    momentlmi::data::read_logs(paths, names, opts).map_err(|e| explain_data(e, spec, sidecar))
}

/// A data error, with a hint when a missing joint column may be one a
/// sidecar locks (see [`read_data`]).
pub(crate) fn explain_data(
    e: momentlmi::data::DataError,
    spec: &str,
    sidecar: Option<&Path>,
) -> String {
    use momentlmi::data::DataError;
    match e {
        DataError::MissingColumn {
            ref column,
            ref path,
            ..
        } if column.starts_with("q_") && sidecar.is_none() && Path::new(spec).is_file() => {
            match simulated_with_sidecar(Path::new(path)) {
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
    }
}

/// Prints what reading did to each raw log (files taken as prepared say
/// nothing).
pub(crate) fn report_reading(what: &str, r: &momentlmi::data::Reading) {
    report_files(what, &r.files)
}

/// [`report_reading`] of the files' reports.
pub(crate) fn report_files(what: &str, files: &[momentlmi::data::FileReport]) {
    for f in files {
        for w in &f.warnings {
            eprintln!("warning: {what} {}: {w}", f.path);
        }
    }
    for f in files.iter().filter(|f| !f.taken_as_prepared) {
        eprintln!(
            "note: {what} {}: {} rows, {} repeated dropped, steps {:.2}–{:.2} ms (median {:.2}), {} gap(s), {} segment(s), resampled at {:.1} Hz, low-pass {:.2} Hz ({}), q̇ {}, {} samples trimmed per segment end, {} samples",
            f.path,
            f.rows,
            f.repeated_rows_dropped,
            1e3 * f.steps_s[1],
            1e3 * f.steps_s[2],
            1e3 * f.steps_s[0],
            f.gaps_s.len(),
            f.segments,
            f.resampled_hz,
            f.cutoff_hz,
            f.cutoff_from,
            match f.velocity {
                momentlmi::data::Velocity::Differentiate => "differentiated from the filtered q",
                momentlmi::data::Velocity::File => "the file's, filtered",
            },
            f.trimmed_per_end,
            f.samples
        );
        if f.short_segment_samples_dropped > 0 {
            eprintln!(
                "warning: {what} {}: {} samples in segments shorter than {} dropped",
                f.path,
                f.short_segment_samples_dropped,
                momentlmi::data::prepare::MIN_SEGMENT
            );
        }
    }
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

/// A model, its friction and its fitted effects (a diagnosis' model file;
/// none for other choices), of a parameter choice given with `flag`.
pub(crate) type WithEffects = (
    momentlmi::dynamics::Model,
    momentlmi::dynamics::Friction,
    Vec<momentlmi::dynamics::params_file::FittedEffect>,
);

/// The model, friction and fitted effects of a parameter choice given with
/// `flag`; an error names the flag and, unless it is a file (whose errors
/// name it), the value typed.
pub(crate) fn parameters_with_effects_for(
    robot: &momentlmi::dynamics::RobotDescription,
    flag: &str,
    value: Option<&str>,
    default: momentlmi::dynamics::ParamChoice,
) -> Result<WithEffects, String> {
    use momentlmi::dynamics::ParamChoice;
    let choice = value.map_or(default, |p| p.parse().expect("infallible"));
    robot
        .parameters_with_effects(&choice)
        .map_err(|e| match (&choice, value) {
            (ParamChoice::File(_), _) | (_, None) => format!("{flag}: {e}"),
            (_, Some(v)) => format!("{flag} {v}: {e}"),
        })
}

/// [`parameters_with_effects_for`] for a use that takes a model file's bodies and
/// friction law but not its fitted effects (a diagnosis' model as
/// `identify --prior` or for `export`): a warning names the effects left
/// out and `why`.
pub(crate) fn parameters_without_effects_for(
    robot: &momentlmi::dynamics::RobotDescription,
    flag: &str,
    value: Option<&str>,
    default: momentlmi::dynamics::ParamChoice,
    why: &str,
) -> Result<(momentlmi::dynamics::Model, momentlmi::dynamics::Friction), String> {
    let (model, friction, effects) = parameters_with_effects_for(robot, flag, value, default)?;
    if !effects.is_empty() {
        eprintln!(
            "warning: {flag} {}: its fitted effects ({}) are left out: {why}; its bodies (any payload merged into them) and friction law are used",
            value.unwrap_or(""),
            momentlmi::dynamics::params_file::FittedEffect::names(&effects)
        );
    }
    Ok((model, friction))
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

/// The largest `--max-memory-gib` (an exbibyte: far beyond any machine,
/// and its bytes still fit a u64).
const MAX_GIB: f64 = 1e9;

/// `--max-memory-gib` in bytes (positive, at most [`MAX_GIB`]).
pub(crate) fn gib(g: f64) -> Result<u64, String> {
    if g > 0.0 && g <= MAX_GIB {
        Ok((g * (1u64 << 30) as f64) as u64)
    } else {
        Err(format!(
            "--max-memory-gib {}: must be a positive number of GiB, at most {}",
            momentlmi::numfmt::short(g),
            momentlmi::numfmt::short(MAX_GIB)
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
