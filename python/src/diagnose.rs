//! The sim-to-real gap diagnosis of arrays, as `momentlmi diagnose --json`
//! reports it.

use crate::errors::MomentlmiError;
use crate::identify::{Segment, prepared};
use crate::robot::Robot;
use momentlmi::data::ReadOptions;
use momentlmi::diagnose::floor::repeat_floor;
use momentlmi::diagnose::{DiagnoseOptions, diagnose};
use momentlmi::dynamics::ParamChoice;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(diagnosis, m)?)?;
    Ok(())
}

/// The report (JSON) of where the `data` segments depart from the
/// `nominal` model (None: the robot's own parameters; cad, true or a
/// parameter file), which unmodelled effects explain it and how far; the
/// noise floor from two `repeats` of one trajectory when given; the data
/// the nominal was identified on (`nominal_data`) when given, its bodies
/// refit with the law (`--nominal-data`).
#[pyfunction]
#[pyo3(signature = (robot, data, nominal, repeats, nominal_data))]
fn diagnosis(
    py: Python<'_>,
    robot: &Robot,
    data: Vec<Segment>,
    nominal: Option<&str>,
    repeats: Vec<Segment>,
    nominal_data: Vec<Segment>,
) -> PyResult<String> {
    if data.is_empty() {
        return Err(PyValueError::new_err("data: no segments"));
    }
    if !(repeats.is_empty() || repeats.len() == 2) {
        let m = format!(
            "repeats: {} segments, two runs of one trajectory expected",
            repeats.len()
        );
        return Err(PyValueError::new_err(m));
    }
    let desc = &**robot.fixed("diagnose")?;
    let opts = ReadOptions::default();
    let d = prepared(desc, "data", &data, &opts)?.data;
    let runs = (repeats.iter().enumerate())
        .map(|(k, r)| {
            prepared(
                desc,
                &format!("repeats[{k}]"),
                std::slice::from_ref(r),
                &opts,
            )
            .map(|r| r.data)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let choice = nominal.map_or(ParamChoice::Own, |s| s.parse().unwrap_or(ParamChoice::Own));
    let err = |e: String| MomentlmiError::new_err(e);
    let (model, friction) = desc
        .parameters(&choice)
        .map_err(|e| err(format!("nominal: {e}")))?;
    let mut dopts = DiagnoseOptions::default();
    if let [x, y] = &runs[..] {
        let floor = repeat_floor(x, y, ["repeats[0]", "repeats[1]"])
            .map_err(|e| err(format!("repeats: {e}")))?;
        dopts = dopts.with_noise_floor(floor);
    }
    if !nominal_data.is_empty() {
        let own = prepared(desc, "nominal_data", &nominal_data, &opts)?.data;
        dopts = dopts.with_nominal_data(own);
    }
    let dg = py
        .detach(|| diagnose(&model, &friction, &d, &dopts))
        .map_err(|e| err(e.to_string()))?;
    serde_json::to_string(&dg).map_err(|e| err(e.to_string()))
}
