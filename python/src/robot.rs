//! A robot (built-in, or a URDF with its sidecar) and its dynamics over
//! many samples at once: arrays of shape (N, n), the robot's joint order.

use crate::arrays::{array, samples};
use crate::errors::{MomentlmiError, OrPy};
use momentlmi::dynamics::{Data, RobotDescription, regressor_batch, rnea};
use numpy::{PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// A robot: its model (links, rotors, friction terms), prior, bounding
/// volumes and the names of its joints and bodies.
#[pyclass(frozen, module = "momentlmi")]
pub struct Robot {
    pub(crate) robot: Arc<RobotDescription>,
    /// What it was loaded from (a built-in's name or a URDF's path, the
    /// sidecar, the package paths): loaded again when it is unpickled.
    load: (String, Option<PathBuf>, Vec<PathBuf>),
    /// `floating_base` was asked (the sidecar's `[floating_base]` table
    /// asks it too).
    floating_asked: bool,
}

impl Robot {
    /// (as the command line loads it: the bounding-volume cache, the
    /// sidecar's effect names checked)
    pub(crate) fn load(
        spec: &str,
        sidecar: Option<PathBuf>,
        package_paths: Vec<PathBuf>,
        floating_asked: bool,
    ) -> PyResult<Self> {
        use momentlmi::dynamics::robots::{load_free_flyer, load_robot_with};
        let floating = floating_asked || sidecar_floats(sidecar.as_deref())?;
        let load = if floating {
            load_free_flyer
        } else {
            load_robot_with
        };
        let mut robot = load(spec, sidecar.as_deref(), &package_paths).or_py()?;
        let from = (spec.to_string(), sidecar, package_paths);
        if let Some(cache) = momentlmi::moments::cache::SolveCache::from_env() {
            robot = robot.with_bounding_cache(cache);
        }
        let effects = momentlmi::effects::Library::builtin();
        effects
            .check_defaults(&robot)
            .map_err(|e| MomentlmiError::new_err(e.to_string()))?;
        Ok(Self {
            robot: Arc::new(robot),
            load: from,
            floating_asked,
        })
    }

    /// The robot's description, unless its root is free: `what` (a
    /// function of the binding) takes a fixed base only, for now.
    pub(crate) fn fixed(&self, what: &str) -> PyResult<&Arc<RobotDescription>> {
        if self.robot.model.is_floating() {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{what}: '{}' has a floating base, and this is for a fixed-base robot for now (a floating base's logs go to identify; docs/floating-base.md)",
                self.robot.model.name
            )));
        }
        Ok(&self.robot)
    }

    /// `q, v, a` checked (each (N, n) or (n,), the same N) and read.
    fn states(
        &self,
        q: &PyReadonlyArrayDyn<f64>,
        v: &PyReadonlyArrayDyn<f64>,
        a: &PyReadonlyArrayDyn<f64>,
    ) -> PyResult<(usize, [Vec<f64>; 3])> {
        let n = self.fixed("rnea, regressor and predict")?.model.dof();
        let (rows, q) = samples("q", q, n)?;
        let mut out = [q, vec![], vec![]];
        for (k, (what, x)) in [("v", v), ("a", a)].into_iter().enumerate() {
            let (r, x) = samples(what, x, n)?;
            if r != rows {
                let m = format!("{what}: {r} samples, q has {rows}");
                return Err(pyo3::exceptions::PyValueError::new_err(m));
            }
            out[k + 1] = x;
        }
        Ok((rows, out))
    }
}

/// Whether the sidecar has a `[floating_base]` table (the robot's root is
/// free, as the command line reads it).
fn sidecar_floats(sidecar: Option<&std::path::Path>) -> PyResult<bool> {
    match sidecar {
        None => Ok(false),
        Some(p) => {
            let s = momentlmi::dynamics::sidecar::Sidecar::read(p)
                .map_err(|e| MomentlmiError::new_err(e.to_string()))?;
            Ok(s.floating_base.is_some())
        }
    }
}

/// The largest regressor returned at once (bytes): more is refused, not
/// an allocation that could abort the interpreter.
const MAX_REGRESSOR_BYTES: usize = 4_000_000_000;

/// `values` (rows of `k`), unless one is not finite (states too large for
/// the model): an error naming the sample, never an inf or NaN returned.
fn finite_out(what: &str, values: Vec<f64>, k: usize) -> PyResult<Vec<f64>> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(values),
        Some(i) => Err(MomentlmiError::new_err(format!(
            "sample {}: a {what} is not finite ({}): the states are too large for the model",
            i / k.max(1),
            values[i]
        ))),
    }
}

#[pymethods]
impl Robot {
    /// A built-in robot by name (`cheetah3-leg`); another name is a
    /// `ValueError` naming it and the built-in ones.
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<Self> {
        if momentlmi::dynamics::robots::built_in(name).is_none() {
            let known = momentlmi::dynamics::robots::built_in_names().join(", ");
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "name: no built-in robot '{name}' (built in: {known})"
            )));
        }
        Self::load(name, None, vec![], false)
    }

    /// What it was loaded from: the built-in's name or the URDF's path,
    /// the sidecar's path, the package paths (to load it again).
    #[getter]
    fn load_args(&self) -> (String, Option<PathBuf>, Vec<PathBuf>) {
        self.load.clone()
    }

    /// What a reduction's sums and a parameter vector depend on, by name
    /// (joints, bodies, friction terms), as `Reducer.to_bytes` records it.
    #[getter]
    fn signature(&self) -> String {
        momentlmi::identify::fleet::signature(&self.robot.model)
    }

    /// A URDF robot: `sidecar` the TOML of its rotors, friction, bounding
    /// volumes and data mapping; `package_paths` the folders where its
    /// `package://` meshes are found; `floating_base` its root link free
    /// (a free-flying base; the sidecar's `[floating_base]` table says so
    /// too).
    #[staticmethod]
    #[pyo3(signature = (path, sidecar=None, package_paths=vec![], floating_base=false))]
    fn from_urdf(
        path: PathBuf,
        sidecar: Option<PathBuf>,
        package_paths: Vec<PathBuf>,
        floating_base: bool,
    ) -> PyResult<Self> {
        Self::load(
            &path.display().to_string(),
            sidecar,
            package_paths,
            floating_base,
        )
    }

    /// Whether the robot's root is free (a floating base).
    #[getter]
    fn floating_base(&self) -> bool {
        self.robot.model.is_floating()
    }

    /// Whether `floating_base` was asked when it was loaded (to load it
    /// again).
    #[getter]
    fn floating_asked(&self) -> bool {
        self.floating_asked
    }

    /// The joints, in the order of every array's columns.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.robot
            .model
            .joint_names()
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    /// The bodies (links, then rotors), in the order of the parameters.
    #[getter]
    fn body_names(&self) -> Vec<String> {
        self.robot.model.body_names()
    }

    /// The regressor's columns: 10 per body, then the friction terms'.
    #[getter]
    fn parameter_names(&self) -> Vec<String> {
        momentlmi::identify::parameter_names(&self.robot.model)
    }

    /// The number of joints n.
    #[getter]
    fn dof(&self) -> usize {
        self.robot.model.dof()
    }

    /// The model's inertial parameters, (bodies, 10), the paper's order.
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let p = self.robot.model.params();
        let bodies = p.len() / 10;
        array(py, p, &[bodies, 10])
    }

    /// Joint torques of the rigid bodies and rotors (no friction), (N, n)
    /// N·m, at joint positions q (rad), velocities v (rad/s) and
    /// accelerations a (rad/s²), each (N, n).
    fn rnea<'py>(
        &self,
        py: Python<'py>,
        q: PyReadonlyArrayDyn<f64>,
        v: PyReadonlyArrayDyn<f64>,
        a: PyReadonlyArrayDyn<f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let (rows, [q, v, a]) = self.states(&q, &v, &a)?;
        let (model, n) = (&self.robot.model, self.robot.model.dof());
        let tau = py.detach(|| {
            let mut data = Data::new(model);
            let mut out = Vec::with_capacity(rows * n);
            for s in 0..rows {
                let at = s * n..(s + 1) * n;
                let t = rnea(model, &mut data, &q[at.clone()], &v[at.clone()], &a[at])?;
                out.extend(t.iter());
            }
            Ok::<_, momentlmi::dynamics::DynamicsError>(out)
        });
        array(py, finite_out("torque", tau.or_py()?, n)?, &[rows, n])
    }

    /// The regressor Y with τ = Y θ (θ: 10 per body, then friction), (N, n, p).
    fn regressor<'py>(
        &self,
        py: Python<'py>,
        q: PyReadonlyArrayDyn<f64>,
        v: PyReadonlyArrayDyn<f64>,
        a: PyReadonlyArrayDyn<f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let (rows, [q, v, a]) = self.states(&q, &v, &a)?;
        let model = &self.robot.model;
        let bytes =
            (rows.checked_mul(model.dof() * model.regressor_columns() * 8)).unwrap_or(usize::MAX);
        if bytes > MAX_REGRESSOR_BYTES {
            let m = format!(
                "q: {rows} samples make a regressor of {:.1} GB (at most {} GB at once; reduce them with Reducer instead)",
                bytes as f64 / 1e9,
                MAX_REGRESSOR_BYTES / 1_000_000_000
            );
            return Err(pyo3::exceptions::PyValueError::new_err(m));
        }
        let y = py.detach(|| regressor_batch(model, &q, &v, &a)).or_py()?;
        let y = finite_out(
            "regressor value",
            y,
            model.dof() * model.regressor_columns(),
        )?;
        array(py, y, &[rows, model.dof(), model.regressor_columns()])
    }

    /// Joint torques (N·m), (N, n), of the model with the identified
    /// parameters `params`: the text of an identification's report or
    /// parameter file, or with `from_file` its path (the package passes a
    /// result's, a dict's, JSON text or a path): links, rotors and every
    /// friction term, as `momentlmi predict --params FILE` predicts them.
    #[pyo3(signature = (params, q, v, a, from_file=false))]
    fn predict<'py>(
        &self,
        py: Python<'py>,
        params: &str,
        q: PyReadonlyArrayDyn<f64>,
        v: PyReadonlyArrayDyn<f64>,
        a: PyReadonlyArrayDyn<f64>,
        from_file: bool,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        use momentlmi::dynamics::params_file::ParamsFile;
        let (rows, [q, v, a]) = self.states(&q, &v, &a)?;
        let file = match from_file {
            true => ParamsFile::read(std::path::Path::new(params))
                .map_err(|e| crate::errors::ModelError::new_err(format!("params: {e}")))?,
            false => serde_json::from_str(params).map_err(|e| {
                MomentlmiError::new_err(format!("params: not a parameter file ({e})"))
            })?,
        };
        let mut model = self.robot.model.clone();
        let friction = file.apply(&mut model, "params").or_py()?;
        let n = model.dof();
        let rows_of = |x: Vec<f64>| {
            momentlmi::data::Samples::from_flat(n, x)
                .unwrap_or_else(|| momentlmi::data::Samples::new(n))
        };
        let (q, v, a) = (rows_of(q), rows_of(v), rows_of(a));
        let tau = py.detach(|| {
            momentlmi::dynamics::predict::predict_torques(&model, &friction, &q, &v, &a)
        });
        array(py, tau.or_py()?.as_flat().to_vec(), &[rows, n])
    }

    fn __repr__(&self) -> String {
        let r = &self.robot;
        format!(
            "Robot('{}', {} joints, {} bodies)",
            r.origin(),
            r.model.dof(),
            r.model.num_bodies()
        )
    }
}
