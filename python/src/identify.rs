//! An identification from arrays, as `momentlmi identify --json` reports
//! it: each segment's samples prepared as a log file would be (taken as
//! they are with q̈; filtered and differentiated without), the same
//! identification set-up, the same report.

use crate::arrays::{samples, times};
use crate::errors::{IdentifyError, OrPy};
use crate::robot::Robot;
use momentlmi::data::{RawLog, ReadOptions, Reading, Samples, Velocity, prepare_logs};
use momentlmi::dynamics::{FrictionTerm, ParamChoice, RobotDescription};
use momentlmi::identify::{DataPreparation, WEIGHT_GRID};
use numpy::PyReadonlyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(identify, m)?)?;
    Ok(())
}

/// One segment's arrays: t (N,), q, and q̇, q̈, τ when given, (N, n).
pub(crate) type Segment<'py> = (
    PyReadonlyArrayDyn<'py, f64>,
    PyReadonlyArrayDyn<'py, f64>,
    Option<PyReadonlyArrayDyn<'py, f64>>,
    Option<PyReadonlyArrayDyn<'py, f64>>,
    Option<PyReadonlyArrayDyn<'py, f64>>,
);

/// A segment's arrays checked into a raw log named `name`.
fn raw_log(name: &str, (t, q, qd, qdd, tau): &Segment, n: usize) -> PyResult<RawLog> {
    let tv = times(&format!("{name}: t"), t)?;
    let rows = tv.len();
    let series = |what: &str, a: &PyReadonlyArrayDyn<f64>| -> PyResult<Samples> {
        let (r, v) = samples(&format!("{name}: {what}"), a, n)?;
        if r != rows {
            return Err(PyValueError::new_err(format!(
                "{name}: {what} has {r} samples, t has {rows}"
            )));
        }
        Ok(Samples::from_flat(n, v).unwrap_or_else(|| Samples::new(n)))
    };
    let opt = |what: &str, a: &Option<PyReadonlyArrayDyn<f64>>| {
        a.as_ref().map(|a| series(what, a)).transpose()
    };
    Ok(RawLog {
        path: name.into(),
        t: tv,
        q: series("q", q)?,
        qd: opt("qd", qd)?,
        qdd: opt("qdd", qdd)?,
        tau: opt("tau", tau)?,
        warnings: vec![],
    })
}

/// The robot with the friction terms `list` names (`viscous,coulomb,…`;
/// `None`: its own), as `--friction` makes it.
fn with_friction(robot: &Robot, list: Option<&str>) -> PyResult<std::sync::Arc<RobotDescription>> {
    let Some(list) = list else {
        return Ok(robot.robot.clone());
    };
    let terms = FrictionTerm::parse_list(list)
        .map_err(|e| PyValueError::new_err(format!("friction: {e}")))?;
    let mut d = (*robot.robot).clone();
    d.model = d.model.with_friction_terms(&terms);
    Ok(std::sync::Arc::new(d))
}

/// Segments prepared and joined, as files are.
pub(crate) fn prepared(
    robot: &RobotDescription,
    what: &str,
    segs: &[Segment],
    opts: &ReadOptions,
) -> PyResult<Reading> {
    let raws = raw_logs(what, segs, robot.model.dof())?;
    prepare_logs(raws, &robot.model.joint_names(), opts).or_py()
}

/// The segments as raw logs, each named `what` (one) or `what[k]`.
fn raw_logs(what: &str, segs: &[Segment], n: usize) -> PyResult<Vec<RawLog>> {
    (segs.iter().enumerate())
        .map(|(k, s)| match segs.len() {
            1 => raw_log(what, s, n),
            _ => raw_log(&format!("{what}[{k}]"), s, n),
        })
        .collect()
}

/// The report (JSON) of the identification on the `data` segments, held
/// out on `validate`'s: `constraints` a level, toward `prior` (cad, true or
/// a parameter file) with `weight` (a number, or auto: chosen by
/// cross-validation; None: auto when the friction law is chosen, else
/// 1e-6 — `--weight`), `regularizer` euclidean, entropic or pullback (None:
/// `--regularizer`'s default); `cutoff_hz` and
/// `velocity` (differentiate, file) prepare raw segments; `friction` the
/// friction terms identified, or auto (None: auto, the model's own law
/// kept when the data are too short to choose — `--friction`); `bounds` each
/// parameter's range with that residual margin δ (`auto`: the 95 %
/// confidence region; None: none).
#[pyfunction]
#[pyo3(signature = (robot, data, validate, constraints, prior, weight, regularizer, cutoff_hz, velocity, friction, bounds))]
#[allow(clippy::too_many_arguments)]
fn identify(
    py: Python<'_>,
    robot: &Robot,
    data: Vec<Segment>,
    validate: Vec<Segment>,
    constraints: &str,
    prior: &str,
    weight: Option<&str>,
    regularizer: Option<&str>,
    cutoff_hz: Option<f64>,
    velocity: &str,
    friction: Option<&str>,
    bounds: Option<&str>,
) -> PyResult<String> {
    // as the command line reads --friction and --weight
    let auto = friction.is_none_or(|f| f.trim() == "auto");
    let by_default = friction.is_none() && weight.is_none();
    let weight = match weight.map(str::trim) {
        Some("auto") => None,
        Some(w) => Some(w.parse::<f64>().map_err(|_| {
            PyValueError::new_err(format!("weight: '{w}' is not a number or 'auto'"))
        })?),
        None if auto => None,
        None => Some(WEIGHT_GRID[0]),
    };
    let setup = crate::setup::Setup::parse(constraints, regularizer, weight)?;
    let velocity = match velocity {
        "differentiate" => Velocity::Differentiate,
        "file" => Velocity::File,
        v => {
            return Err(PyValueError::new_err(format!(
                "velocity: '{v}' is not one of differentiate, file"
            )));
        }
    };
    if data.is_empty() {
        return Err(PyValueError::new_err("data: no segments"));
    }
    let desc = &*with_friction(robot, friction.filter(|_| !auto))?;
    let mut opts = ReadOptions {
        cutoff_hz,
        velocity,
        ..ReadOptions::default()
    };
    // no cut-off given: chosen on the training segments by held-out torque
    // error when one is raw (as the command line does)
    let cutoff_choice = match cutoff_hz {
        Some(_) => None,
        None => {
            let raws = raw_logs("data", &data, desc.model.dof())?;
            momentlmi::identify::cutoff::choose_cutoff(&raws, &desc.model, velocity).map_err(
                |e| {
                    PyValueError::new_err(format!(
                        "choosing the low-pass cut-off (give cutoff_hz): {e}"
                    ))
                },
            )?
        }
    };
    opts.cutoff_hz = cutoff_choice.as_ref().map(|c| c.chosen_hz).or(cutoff_hz);
    let mut train = prepared(desc, "data", &data, &opts)?;
    let mut val = (!validate.is_empty())
        .then(|| prepared(desc, "validate", &validate, &opts))
        .transpose()?;
    if let Some(c) = &cutoff_choice {
        use momentlmi::identify::cutoff::mark_chosen;
        mark_chosen(&mut train.files, &c.words());
        if let Some(v) = &mut val {
            mark_chosen(
                &mut v.files,
                &format!("the training data's choice, {}", c.words()),
            );
        }
    }
    let choice: ParamChoice = prior.parse().unwrap_or(ParamChoice::Cad);
    let result = py.detach(|| {
        // friction "auto": the law (and a Euclidean prior's weight, when it
        // is auto) chosen on the training data, as --friction auto does
        let (mut selection, kept) = match auto {
            false => (None, None),
            true => {
                use momentlmi::identify::friction_choice::LawChoice::{Chosen, Kept};
                let id = setup.identification(desc, &choice, weight.unwrap_or(WEIGHT_GRID[0]))?;
                let weights = id.model_weights(weight.is_none());
                let what = match friction.is_none() {
                    true => "choosing the friction law (the default; friction=LIST fits one)",
                    false => "friction auto",
                };
                let failed = |e| format!("{what}: {e}");
                match by_default {
                    false => (
                        Some(id.choose_model(&train.data, weights).map_err(failed)?),
                        None,
                    ),
                    true => match id
                        .choose_model_or_keep(&train.data, weights)
                        .map_err(failed)?
                    {
                        Chosen(c) => (Some(c), None),
                        Kept(w) => (None, Some(w)),
                    },
                }
            }
        };
        let chosen_desc;
        let desc = match &selection {
            Some(c) => {
                let mut d = desc.clone();
                d.model = c
                    .apply(d.model)
                    .map_err(|e| format!("friction auto: {e}"))?;
                chosen_desc = d;
                &chosen_desc
            }
            None => desc,
        };
        let mut id = setup.identification(desc, &choice, weight.unwrap_or(WEIGHT_GRID[0]))?;
        if let Some(c) = selection.as_ref().filter(|c| c.weight_chosen()) {
            id = id.with_weight(c.weight()).map_err(|e| e.to_string())?;
        }
        let choice = match weight {
            Some(_) => None,
            None if selection.as_ref().is_some_and(|c| c.weight_chosen()) => None,
            None if kept.is_some() => None,
            None => Some(
                id.choose_weight(&train.data, &WEIGHT_GRID)
                    .map_err(|e| e.to_string())?,
            ),
        };
        let red = (id.reduce_chosen(&train.data, selection.as_mut())).map_err(|e| e.to_string())?;
        let mut r = id
            .fit_reduced(&train.data, &red)
            .map_err(|e| e.to_string())?;
        if let Some(v) = &val {
            r.validate(&desc.model, &v.data)
                .map_err(|e| e.to_string())?;
        }
        if let Some(b) = bounds {
            let rows = red.samples * desc.model.dof();
            let delta = momentlmi::identify::Margin::parse(b)
                .ok_or_else(|| format!("bounds: '{b}' is not a number ≥ 0 or auto"))?
                .delta(r.identifiability.rank, rows)
                .map_err(|e| e.to_string())?;
            let pb = id.parameter_bounds(&red, &r.theta, &r.identifiability, delta);
            r.bounds = Some(pb.map_err(|e| e.to_string())?);
        }
        r.weight_choice = choice;
        r.model_selection = selection;
        r.warnings.extend(kept);
        r.data_preparation = DataPreparation {
            training: train.files.clone(),
            validation: val.as_ref().map(|v| v.files.clone()).unwrap_or_default(),
            cutoff_choice: cutoff_choice.clone(),
        };
        Ok::<_, String>(r)
    });
    let r = result.map_err(IdentifyError::new_err)?;
    serde_json::to_string_pretty(&r).map_err(|e| IdentifyError::new_err(e.to_string()))
}
