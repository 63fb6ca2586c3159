//! A robot simulated with unmodelled effects, as `momentlmi simulate` does
//! (the same configuration for the same seed: the same samples).

use crate::arrays::array;
use crate::errors::{DataError, MomentlmiError};
use crate::robot::Robot;
use momentlmi::effects::Library;
use momentlmi::sim::{Effects, SimConfig, simulate_with};
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;

pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    Ok(())
}

/// `seconds` of the robot's excitation with `effects` (names, with
/// `NAME=VALUE` overrides in `params`), torque noise `noise` (N·m; the
/// robot's default when `None`; 0: exact, unprocessed): a dict of arrays
/// `t` (N,), `q`, `qd`, `qdd`, `tau` (N, n) and `joints`.
#[pyfunction]
#[pyo3(signature = (robot, seconds, effects=vec![], params=vec![], seed=1, noise=None))]
fn simulate<'py>(
    py: Python<'py>,
    robot: &Robot,
    seconds: f64,
    effects: Vec<String>,
    params: Vec<String>,
    seed: u64,
    noise: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let err = |e: String| MomentlmiError::new_err(e);
    let library = Library::builtin();
    let effects = Effects::parse(&effects.join(","), &params).map_err(|e| err(e.to_string()))?;
    library.check(&effects).map_err(|e| err(e.to_string()))?;
    let desc = &**robot.fixed("simulate")?;
    let mut cfg = SimConfig::for_robot(desc, seconds, effects, seed);
    if let Some(s) = noise {
        cfg.noise_sigma = s;
        if s == 0.0 {
            (cfg.encoder_counts, cfg.processed) = (0.0, false);
        }
    }
    cfg.validate(&desc.model)
        .map_err(|e| DataError::new_err(e.to_string()))?;
    let d = py.detach(|| {
        let truth = library
            .true_robot(desc, &cfg.effects)
            .map_err(|e| e.to_string())?;
        simulate_with(desc, &truth, &cfg, |_, _| {}).map_err(|e| e.to_string())
    });
    let d = d.map_err(err)?;
    let (k, n) = (d.len(), desc.model.dof());
    let out = PyDict::new(py);
    out.set_item("t", array(py, d.t.clone(), &[k])?)?;
    for (name, s) in [("q", &d.q), ("qd", &d.qd), ("qdd", &d.qdd), ("tau", &d.tau)] {
        let a: Bound<'py, PyArrayDyn<f64>> = array(py, s.as_flat().to_vec(), &[k, n])?;
        out.set_item(name, a)?;
    }
    out.set_item("joints", d.joints.clone())?;
    Ok(out)
}
