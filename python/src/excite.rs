//! A designed excitation, as `momentlmi excite --json` reports it, with
//! its samples.

use crate::arrays::array;
use crate::errors::IdentifyError;
use crate::robot::Robot;
use momentlmi::excite::{Criterion, ExciteOptions, design, samples};
use numpy::PyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(excite, m)?)?;
    Ok(())
}

type Arrays<'py> = (
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
);

/// The report (JSON) of the design and its samples at `rate_hz`: t (N,),
/// q, q̇, q̈ (N, n).
#[pyfunction]
#[pyo3(signature = (robot, seconds, criterion, harmonics, base_hz, seeds, seed, pool, rate_hz))]
#[allow(clippy::too_many_arguments)]
fn excite<'py>(
    py: Python<'py>,
    robot: &Robot,
    seconds: f64,
    criterion: &str,
    harmonics: usize,
    base_hz: f64,
    seeds: usize,
    seed: u64,
    pool: usize,
    rate_hz: f64,
) -> PyResult<(String, Arrays<'py>)> {
    let criterion = Criterion::parse(criterion).ok_or_else(|| {
        PyValueError::new_err(format!("criterion: '{criterion}' is not one of d, e, cond"))
    })?;
    let opts = ExciteOptions {
        seconds,
        criterion,
        harmonics,
        base_hz,
        seeds,
        seed,
        pool,
        ..ExciteOptions::default()
    };
    let desc = robot.fixed("excite")?.clone();
    let (d, data) = py
        .detach(|| {
            let d = design(&desc, &opts)?;
            let data = samples(&d, rate_hz)?;
            Ok::<_, momentlmi::excite::ExciteError>((d, data))
        })
        .map_err(|e| IdentifyError::new_err(e.to_string()))?;
    let json = serde_json::to_string(&d).map_err(|e| IdentifyError::new_err(e.to_string()))?;
    let (rows, n) = (data.len(), desc.model.dof());
    let flat = |s: &momentlmi::dynamics::Samples| s.as_flat().to_vec();
    Ok((
        json,
        (
            array(py, data.t.clone(), &[rows])?,
            array(py, flat(&data.q), &[rows, n])?,
            array(py, flat(&data.qd), &[rows, n])?,
            array(py, flat(&data.qdd), &[rows, n])?,
        ),
    ))
}
