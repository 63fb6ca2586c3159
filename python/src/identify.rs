//! An identification from arrays, as `momentlmi identify --json` reports
//! it: each segment's samples prepared as a log file would be (taken as
//! they are with q̈; filtered and differentiated without), the same
//! identification set-up, the same report.

use crate::arrays::{samples, times};
use crate::errors::{IdentifyError, OrPy};
use crate::robot::Robot;
use momentlmi::data::{RawLog, ReadOptions, Reading, Samples, Velocity, prepare_logs};
use momentlmi::dynamics::{FrictionTerm, ParamChoice, RobotDescription};
use momentlmi::identify::cutoff::{CutoffCurve, choose_cutoff, mark_chosen};
use momentlmi::identify::planned::{
    Failed, LawPlan, Plan, Planned, Setup, Step, Training, identify_planned,
};
use momentlmi::identify::{DataPreparation, Identification, Margin, WEIGHT_GRID};
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
pub(crate) fn with_friction(
    robot: &Robot,
    list: Option<&str>,
) -> PyResult<std::sync::Arc<RobotDescription>> {
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
/// confidence region; None: none). With the report, its warnings
/// ([`crate::notes`]).
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
) -> PyResult<(String, Vec<crate::notes::Note>)> {
    let plan = plan(friction, weight, bounds)?;
    if let Some(c) = cutoff_hz.filter(|c| !(c.is_finite() && *c > 0.0)) {
        let m = format!("cutoff_hz: {c} is not a frequency > 0 (Hz)");
        return Err(PyValueError::new_err(m));
    }
    let setup = crate::setup::Setup::parse(constraints, regularizer, plan.weight)?;
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
    let auto = plan.law != LawPlan::Own;
    let desc = &*with_friction(robot, friction.filter(|_| !auto))?;
    let (train, val, cutoff_choice) = prepared_both(desc, (&data, &validate), cutoff_hz, velocity)?;
    let choice: ParamChoice = prior.parse().unwrap_or(ParamChoice::Cad);
    let setup = PySetup {
        setup: &setup,
        prior: &choice,
    };
    let result = py.detach(|| {
        let (fitted, _) =
            identify_planned(&setup, desc, Training::Samples(&train.data), &plan, || ());
        let Planned {
            result: mut r,
            robot,
        } = fitted.map_err(|e| e.words(friction))?;
        if let Some(v) = &val {
            r.validate(&robot.model, &v.data)
                .map_err(|e| e.to_string())?;
        }
        r.data_preparation = DataPreparation {
            training: train.files.clone(),
            validation: val.as_ref().map(|v| v.files.clone()).unwrap_or_default(),
            cutoff_choice: cutoff_choice.clone(),
        };
        Ok::<_, String>(r)
    });
    let r = result.map_err(IdentifyError::new_err)?;
    let json =
        serde_json::to_string_pretty(&r).map_err(|e| IdentifyError::new_err(e.to_string()))?;
    Ok((json, crate::notes::of_identification(&r)))
}

/// What the data choose, as the command line reads `--friction`,
/// `--weight` and `--bounds`: the law when `friction` is auto or not given
/// (kept for want of data only when neither it nor `weight` is given), the
/// weight when it is `auto` or not given with the law chosen.
fn plan(friction: Option<&str>, weight: Option<&str>, bounds: Option<&str>) -> PyResult<Plan> {
    let auto = friction.is_none_or(|f| f.trim() == "auto");
    let law = LawPlan::for_options(auto, friction.is_some() || weight.is_some());
    let weight = match weight.map(str::trim) {
        Some("auto") => None,
        Some(w) => Some(w.parse::<f64>().map_err(|_| {
            PyValueError::new_err(format!("weight: '{w}' is not a number or 'auto'"))
        })?),
        None if auto => None,
        None => Some(WEIGHT_GRID[0]),
    };
    let bounds = (bounds.map(|b| {
        Margin::parse(b).ok_or_else(|| {
            PyValueError::new_err(format!("bounds: '{b}' is not a number ≥ 0 or auto"))
        })
    }))
    .transpose()?;
    Ok(Plan {
        law,
        weight,
        bounds,
    })
}

/// The training and validation segments prepared as files are, with the
/// cut-off given, or (none given) chosen on the training segments by
/// held-out torque error when one is raw, as the command line does.
fn prepared_both(
    desc: &RobotDescription,
    (data, validate): (&[Segment], &[Segment]),
    cutoff_hz: Option<f64>,
    velocity: Velocity,
) -> PyResult<(Reading, Option<Reading>, Option<CutoffCurve>)> {
    let cutoff_choice = match cutoff_hz {
        Some(_) => None,
        None => {
            let raws = raw_logs("data", data, desc.model.dof())?;
            choose_cutoff(&raws, &desc.model, velocity).map_err(|e| {
                PyValueError::new_err(format!(
                    "choosing the low-pass cut-off (give cutoff_hz): {e}"
                ))
            })?
        }
    };
    let opts = ReadOptions {
        cutoff_hz: cutoff_choice.as_ref().map(|c| c.chosen_hz).or(cutoff_hz),
        velocity,
        ..ReadOptions::default()
    };
    let mut train = prepared(desc, "data", data, &opts)?;
    let mut val = (!validate.is_empty())
        .then(|| prepared(desc, "validate", validate, &opts))
        .transpose()?;
    if let Some(c) = &cutoff_choice {
        mark_chosen(&mut train.files, &c.words());
        if let Some(v) = &mut val {
            let how = format!("the training data's choice, {}", c.words());
            mark_chosen(&mut v.files, &how);
        }
    }
    Ok((train, val, cutoff_choice))
}

/// The binding's set-up as the library's [`Setup`].
struct PySetup<'a> {
    setup: &'a crate::setup::Setup,
    prior: &'a ParamChoice,
}

/// An error of the binding (worded) or a failed step of the library's
/// sequence (worded by [`PyFailure::words`]).
enum PyFailure {
    Words(String),
    Failed(Failed),
}

impl From<String> for PyFailure {
    fn from(e: String) -> Self {
        Self::Words(e)
    }
}

impl From<Failed> for PyFailure {
    fn from(f: Failed) -> Self {
        Self::Failed(f)
    }
}

impl PyFailure {
    /// The error with the argument it concerns (`friction` as given).
    fn words(self, friction: Option<&str>) -> String {
        let f = match self {
            Self::Words(w) => return w,
            Self::Failed(f) => f,
        };
        match (f.step, friction) {
            (Step::Law, None) => format!(
                "choosing the friction law (the default; friction=LIST fits one): {}",
                f.source
            ),
            (Step::Law, Some(_)) => format!("friction auto: {}", f.source),
            (Step::Bounds, _) => format!("bounds: {}", f.source),
            _ => f.source.to_string(),
        }
    }
}

impl Setup for PySetup<'_> {
    type Error = PyFailure;

    fn identification<'r>(
        &self,
        robot: &'r RobotDescription,
        weight: f64,
    ) -> Result<Identification<'r>, PyFailure> {
        Ok(self.setup.identification(robot, self.prior, weight)?)
    }
}
