//! The fleet path: samples reduced into sums of a fixed size (the Gram
//! matrix of the regressor and torques), sums of parts added, stored as
//! bytes and loaded again, one SDP solved on them.

use crate::arrays::samples;
use crate::errors::{IdentifyError, OrPy};
use crate::robot::Robot;
use momentlmi::dynamics::{ParamChoice, RobotDescription};
use momentlmi::identify::fleet::signature;
use momentlmi::identify::{Reduced, StreamReducer};
use numpy::PyReadonlyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::sync::Arc;

/// Samples multiplied out a chunk at a time.
const CHUNK: usize = 256;

/// A robot's data reduced: `update` with samples, `merge` another
/// reducer's sums, `to_bytes` / `from_bytes` to move them between
/// processes or machines, `solve` the identification on them.
#[pyclass(module = "momentlmi")]
pub struct Reducer {
    robot: Arc<RobotDescription>,
    reduced: Option<Reduced>,
}

#[pymethods]
impl Reducer {
    #[new]
    fn new(robot: &Robot) -> PyResult<Self> {
        Ok(Self {
            robot: robot.fixed("Reducer")?.clone(),
            reduced: None,
        })
    }

    /// The samples reduced so far.
    #[getter]
    fn samples(&self) -> usize {
        self.reduced.as_ref().map_or(0, |r| r.samples)
    }

    /// Adds samples: q (rad), v (rad/s), a (rad/s²) and measured τ (N·m),
    /// each (N, n) in the robot's joint order.
    fn update(
        &mut self,
        py: Python<'_>,
        q: PyReadonlyArrayDyn<f64>,
        v: PyReadonlyArrayDyn<f64>,
        a: PyReadonlyArrayDyn<f64>,
        tau: PyReadonlyArrayDyn<f64>,
    ) -> PyResult<()> {
        let n = self.robot.model.dof();
        let (rows, q) = samples("q", &q, n)?;
        let mut rest = vec![];
        for (what, x) in [("v", &v), ("a", &a), ("tau", &tau)] {
            let (r, x) = samples(what, x, n)?;
            if r != rows {
                let m = format!("{what}: {r} samples, q has {rows}");
                return Err(PyValueError::new_err(m));
            }
            rest.push(x);
        }
        if rows == 0 {
            return Ok(()); // nothing to add (no sums of zero samples are kept)
        }
        let (model, first) = (&self.robot.model, self.samples());
        let part = py.detach(|| {
            let mut r = StreamReducer::starting_at(model, CHUNK, first);
            for s in 0..rows {
                let at = s * n..(s + 1) * n;
                let x = |k: usize| &rest[k][at.clone()];
                r.push(&q[at.clone()], x(0), x(1), x(2))?;
            }
            r.finish()
        });
        let part = part.or_py()?;
        self.add(part)
    }

    /// The Gram matrix `[Y τ]ᵀ[Y τ]` of the samples so far, (p + 1) × (p + 1).
    fn gram<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArrayDyn<f64>>> {
        let Some(r) = &self.reduced else {
            return Err(IdentifyError::new_err("reduced data: no samples yet"));
        };
        let k = r.gram.nrows();
        let values = (0..k * k).map(|ij| r.gram[(ij / k, ij % k)]).collect();
        crate::arrays::array(py, values, &[k, k])
    }

    /// Adds the sums of `other` (the same robot's).
    fn merge(&mut self, other: &Reducer) -> PyResult<()> {
        let (mine, theirs) = (signature(&self.robot.model), signature(&other.robot.model));
        if mine != theirs {
            let m = format!("reduced data: of another robot ({theirs}; this one: {mine})");
            return Err(IdentifyError::new_err(m));
        }
        match &other.reduced {
            Some(r) => self.add(r.clone()),
            None => Ok(()),
        }
    }

    /// The sums as bytes (versioned; `from_bytes` checks them).
    fn to_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let Some(r) = &self.reduced else {
            return Err(IdentifyError::new_err("reduced data: no samples yet"));
        };
        Ok(PyBytes::new(py, &r.to_bytes(&self.robot.model)))
    }

    /// A reducer with the sums `data` holds, for `robot`.
    #[staticmethod]
    fn from_bytes(robot: &Robot, data: &[u8]) -> PyResult<Self> {
        let reduced = Reduced::from_bytes(&robot.fixed("Reducer")?.model, data).or_py()?;
        Ok(Self {
            robot: robot.robot.clone(),
            reduced: Some(reduced),
        })
    }

    /// The identification on the sums, as `momentlmi identify --json`
    /// reports it (JSON), and its warnings: `constraints` a level (none, semi, consistent,
    /// ellipsoid), toward the robot's prior with `weight` and `regularizer`
    /// (euclidean, entropic or pullback).
    #[pyo3(signature = (constraints="ellipsoid", weight=1e-6, regularizer="euclidean"))]
    fn solve(
        &self,
        py: Python<'_>,
        constraints: &str,
        weight: f64,
        regularizer: &str,
    ) -> PyResult<(String, Vec<crate::notes::Note>)> {
        let Some(red) = &self.reduced else {
            return Err(IdentifyError::new_err("reduced data: no samples yet"));
        };
        let setup = crate::setup::Setup::parse(constraints, Some(regularizer), Some(weight))?;
        let robot = &*self.robot;
        let result = py.detach(|| {
            let id = setup.identification(robot, &ParamChoice::Cad, weight)?;
            id.fit_streamed(red).map_err(|e| e.to_string())
        });
        let result = result.map_err(IdentifyError::new_err)?;
        let json = serde_json::to_string_pretty(&result)
            .map_err(|e| IdentifyError::new_err(e.to_string()))?;
        Ok((json, crate::notes::of_identification(&result)))
    }
}

impl Reducer {
    fn add(&mut self, part: Reduced) -> PyResult<()> {
        self.reduced = Some(match self.reduced.take() {
            None => part,
            Some(r) => r.merge(&part).or_py()?,
        });
        Ok(())
    }
}
