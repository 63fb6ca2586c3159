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

/// The most a floating-base log's numbers may take in memory (bytes): the
/// log and its columns are held at once.
const MAX_FLOATING_BYTES: f64 = 4.0 * (1u64 << 30) as f64;

/// A floating base hung from a harness (the load cell at the base), as
/// `momentlmi simulate` makes it for the same seed: a dict of the log's
/// columns (1-D arrays named as the CSV's: `t`, `base_x` …, `q_<joint>` …,
/// `force_<link>_x` …), which `identify` takes as a log.
fn floating<'py>(
    py: Python<'py>,
    robot: &Robot,
    seconds: f64,
    (effects, seed, noise): (&[String], u64, Option<f64>),
) -> PyResult<Bound<'py, PyDict>> {
    use momentlmi::sim::floating::{FloatingEffects, FloatingNoise, SuspendedConfig};
    let value = |e: String| pyo3::exceptions::PyValueError::new_err(e);
    let ff = &robot.robot.model;
    let effects = FloatingEffects::named(effects).map_err(|e| value(format!("effects: {e}")))?;
    let noise = match noise {
        None => FloatingNoise::default(),
        Some(s) if s == 0.0 => FloatingNoise::none(),
        Some(s) if s.is_finite() && s > 0.0 => FloatingNoise {
            torque: s,
            ..FloatingNoise::default()
        },
        Some(s) => return Err(value(format!("noise: {s} (a finite σ ≥ 0, N·m)"))),
    };
    let cfg = SuspendedConfig {
        seconds,
        seed,
        noise,
        effects,
        ..SuspendedConfig::default()
    };
    let columns = (1 + ff.nq() + 2 * ff.nv() + ff.dof() + 6) as f64;
    if !(seconds * cfg.rate * columns * 16.0 <= MAX_FLOATING_BYTES) {
        return Err(value(format!(
            "seconds: {seconds} s at {} Hz would need more than 4 GiB",
            cfg.rate
        )));
    }
    let log = py.detach(|| momentlmi::sim::floating::simulate_suspended(ff, &cfg));
    let log = log.map_err(|e| DataError::new_err(e.to_string()))?;
    log.check(ff)
        .map_err(|e| DataError::new_err(e.to_string()))?;
    let header = log.csv_header();
    let mut cols = vec![Vec::with_capacity(log.len()); header.len()];
    for k in 0..log.len() {
        cols.iter_mut()
            .zip(log.csv_row(k))
            .for_each(|(c, x)| c.push(x));
    }
    let out = PyDict::new(py);
    for (name, c) in header.into_iter().zip(cols) {
        let n = c.len();
        let a: Bound<'py, PyArrayDyn<f64>> = array(py, c, &[n])?;
        out.set_item(name, a)?;
    }
    Ok(out)
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
    if robot.robot.model.is_floating() {
        if !params.is_empty() {
            let m = "params: a floating base's effects have fixed sizes (no NAME=VALUE)";
            return Err(pyo3::exceptions::PyValueError::new_err(m));
        }
        return floating(py, robot, seconds, (&effects, seed, noise));
    }
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
