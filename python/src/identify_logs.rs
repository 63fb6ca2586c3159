//! An identification of a floating-base robot from its logs, as
//! `momentlmi identify --json` reports it on the same files: each log a
//! file (CSV or `.npz`, read by the command line's reader) or named
//! columns (a DataFrame's, the CSV's names), the same set-up on the rows
//! fitted, the same report.

use crate::identify::with_friction;
use crate::robot::Robot;
use momentlmi::data::Dataset;
use momentlmi::data::floating_csv::floating_from_columns;
use momentlmi::dynamics::{ParamChoice, RobotDescription};
use momentlmi::identify::Rows;
use momentlmi::identify::floating_fit::fit_floating;
use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;

pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(identify_logs, m)?)?;
    Ok(())
}

/// One log: a file, or `(names, columns)` (1-D arrays of one length).
#[derive(FromPyObject)]
pub(crate) enum Log<'py> {
    Columns(Vec<String>, Vec<PyReadonlyArray1<'py, f64>>),
    File(PathBuf),
}

/// The memory allowed the files' numbers (the command line's default
/// `--max-memory-gib`).
const MAX_BYTES: u64 = 8 << 30;

/// The logs read, each named `what` (one) or `what[k]`; files as the
/// command line reads them (checked, laid end to end).
fn logs(robot: &RobotDescription, what: &str, given: &[Log]) -> PyResult<Vec<Dataset>> {
    let ff = &robot.model;
    let mut out = Vec::with_capacity(given.len());
    // (the files share the budget, as the command line's do)
    let budget = MAX_BYTES / given.len().max(1) as u64;
    for (k, log) in given.iter().enumerate() {
        let name = match given.len() {
            1 => what.to_string(),
            _ => format!("{what}[{k}]"),
        };
        let mut read = match log {
            Log::File(p) => (momentlmi::data::read_floating_logs(ff, &[p.as_path()], budget))
                .map_err(|e| PyValueError::new_err(format!("{name}: {e}")))?,
            Log::Columns(names, columns) => {
                let columns: Vec<&[f64]> = (columns.iter())
                    .map(|c| c.as_slice())
                    .collect::<Result<_, _>>()
                    .map_err(|e| PyValueError::new_err(format!("{name}: {e}")))?;
                (floating_from_columns(ff, names, &columns, &name))
                    .and_then(|d| momentlmi::data::usable_floating_log(ff, d, &name))
                    .map(|d| vec![d])
                    .map_err(|e| PyValueError::new_err(e.to_string()))?
            }
        };
        out.append(&mut read);
    }
    momentlmi::data::base::lay_end_to_end(&mut out);
    Ok(out)
}

/// The report (JSON) of a floating-base robot's identification on the
/// `data` logs, held out on `validate`'s, as `momentlmi identify
/// --floating-base --json` on the same files: `constraints` a level,
/// toward `prior` (cad, true or a parameter file) with `weight` (None:
/// 1e-6), `regularizer` (None: euclidean), `friction` the terms identified
/// (None: the robot's), `rows` base, joints or all (None: every row when
/// the logs have joint torques, else the base's). With the report, its
/// warnings (the kind, the words).
#[pyfunction]
#[pyo3(signature = (robot, data, validate, constraints, prior, weight, regularizer, friction, rows))]
#[allow(clippy::too_many_arguments)]
fn identify_logs(
    py: Python<'_>,
    robot: &Robot,
    data: Vec<Log>,
    validate: Vec<Log>,
    constraints: &str,
    prior: &str,
    weight: Option<f64>,
    regularizer: Option<&str>,
    friction: Option<&str>,
    rows: Option<&str>,
) -> PyResult<(String, Vec<crate::notes::Note>)> {
    let weight = weight.unwrap_or(1e-6);
    let setup = crate::setup::Setup::parse(constraints, regularizer, Some(weight))?;
    let desc = with_friction(robot, friction)?;
    if data.is_empty() {
        return Err(PyValueError::new_err("data: no logs"));
    }
    let (train, val) = (
        logs(&desc, "data", &data)?,
        logs(&desc, "validate", &validate)?,
    );
    let asked = rows.map(parse_rows).transpose()?;
    let (rows, _) =
        Rows::for_logs(asked, &train).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let choice: ParamChoice = prior.parse().unwrap_or(ParamChoice::Cad);
    let mut notes: Vec<crate::notes::Note> = vec![];
    if setup.level == momentlmi::identify::Level::Ellipsoid {
        let source = &desc.source;
        notes.extend(
            (desc.bounding_warnings().iter())
                .map(|w| ("bounding".into(), format!("{source}: {w}"))),
        );
    }
    let fit = py.detach(|| {
        let id = setup.identification(&desc, &choice, weight)?.rows(rows);
        fit_floating(&id, &desc.model, rows, &train, &val).map_err(|e| e.to_string())
    });
    let fit = fit.map_err(crate::errors::IdentifyError::new_err)?;
    notes.extend((fit.warnings.iter()).map(|w| ("inaccurate".into(), w.to_string())));
    let json = serde_json::to_string_pretty(&fit.to_json())
        .map_err(|e| crate::errors::IdentifyError::new_err(e.to_string()))?;
    Ok((json, notes))
}

/// `base`, `joints` or `all`.
fn parse_rows(r: &str) -> PyResult<Rows> {
    match r {
        "base" => Ok(Rows::Base),
        "joints" => Ok(Rows::Joints),
        "all" => Ok(Rows::All),
        _ => Err(PyValueError::new_err(format!(
            "rows: '{r}' is not one of base, joints, all"
        ))),
    }
}
