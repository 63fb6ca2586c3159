//! One body's inertial parameters π (the paper's order, `[m, hx, hy, hz,
//! Ixx, Ixy, Ixz, Iyy, Iyz, Izz]`, about the body frame's origin, SI):
//! the pseudo-inertia, consistency, realizability in an ellipsoid, four
//! point masses, the nearest consistent π, Pinocchio's order.

use crate::arrays::{array, matrix, vector};
use crate::errors::OrPy;
use momentlmi::moments::{
    Ellipsoid, InertialParams, NearestOptions, check_consistency, check_realizable,
    four_point_masses, nearest_consistent,
};
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;

pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(pseudo_inertia, m)?)?;
    m.add_function(wrap_pyfunction!(consistency, m)?)?;
    m.add_function(wrap_pyfunction!(realizability, m)?)?;
    m.add_function(wrap_pyfunction!(point_masses, m)?)?;
    m.add_function(wrap_pyfunction!(nearest, m)?)?;
    m.add_function(wrap_pyfunction!(from_pinocchio, m)?)?;
    m.add_function(wrap_pyfunction!(to_pinocchio, m)?)?;
    m.add("CHECK_TOL", momentlmi::identify::CHECK_TOL)?;
    Ok(())
}

/// A tolerance: finite and ≥ 0.
fn tolerance(tol: f64) -> PyResult<f64> {
    if tol.is_finite() && tol >= 0.0 {
        Ok(tol)
    } else {
        Err(pyo3::exceptions::PyValueError::new_err(format!(
            "tol: {tol} is not a finite number ≥ 0"
        )))
    }
}

fn params(pi: &PyReadonlyArrayDyn<f64>) -> PyResult<InertialParams> {
    Ok(InertialParams(vector::<10>("pi", pi)?))
}

/// J(π), 4 × 4 (kg, kg·m, kg·m²).
#[pyfunction]
fn pseudo_inertia<'py>(
    py: Python<'py>,
    pi: PyReadonlyArrayDyn<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let j = params(&pi)?.pseudo_inertia();
    array(py, (0..16).map(|k| j[(k / 4, k % 4)]).collect(), &[4, 4])
}

/// The consistency report (JSON): verdict, margins, `consistent`.
#[pyfunction]
fn consistency(pi: PyReadonlyArrayDyn<f64>, tol: f64) -> PyResult<String> {
    let r = check_consistency(&params(&pi)?, tolerance(tol)?);
    Ok(serde_json::to_string(&r).unwrap_or_default())
}

/// The realizability report (JSON) in the ellipsoid of `center` (m),
/// `semi_axes` (m) and `rotation` (its axes as columns).
#[pyfunction]
fn realizability(
    pi: PyReadonlyArrayDyn<f64>,
    center: PyReadonlyArrayDyn<f64>,
    semi_axes: PyReadonlyArrayDyn<f64>,
    rotation: PyReadonlyArrayDyn<f64>,
    tol: f64,
) -> PyResult<String> {
    let c = Vector3::from(vector::<3>("center", &center)?);
    let a = Vector3::from(vector::<3>("semi_axes", &semi_axes)?);
    let r = matrix::<3>("rotation", &rotation)?;
    let r = Matrix3::from_fn(|i, j| r[i][j]);
    let e = Ellipsoid::with_rotation(c, a, r).or_py()?;
    let rep = check_realizable(&params(&pi)?, &e, tolerance(tol)?);
    Ok(serde_json::to_string(&rep).unwrap_or_default())
}

/// Four point masses with the same π: masses (4,) kg and positions (4, 3) m.
#[pyfunction]
fn point_masses<'py>(
    py: Python<'py>,
    pi: PyReadonlyArrayDyn<f64>,
) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyArrayDyn<f64>>)> {
    let pts = four_point_masses(&params(&pi)?).or_py()?;
    let masses = pts.iter().map(|p| p.mass).collect();
    let xyz = pts
        .iter()
        .flat_map(|p| p.position.iter().copied())
        .collect();
    Ok((array(py, masses, &[4])?, array(py, xyz, &[4, 3])?))
}

/// The nearest consistent π′ (margin `eps`, mass kept if positive when
/// `keep_mass`) and its distance in the documented metric.
#[pyfunction]
fn nearest<'py>(
    py: Python<'py>,
    pi: PyReadonlyArrayDyn<f64>,
    eps: f64,
    keep_mass: bool,
) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, f64)> {
    let opts = NearestOptions {
        eps,
        keep_mass,
        ..NearestOptions::default()
    };
    let n = nearest_consistent(&params(&pi)?, &opts).or_py()?;
    Ok((array(py, n.params.0.to_vec(), &[10])?, n.distance))
}

/// π from Pinocchio's `Inertia.toDynamicParameters()` order
/// `[m, hx, hy, hz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
#[pyfunction]
fn from_pinocchio<'py>(
    py: Python<'py>,
    p: PyReadonlyArrayDyn<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let pi = InertialParams::from_pinocchio(vector::<10>("p", &p)?);
    array(py, pi.0.to_vec(), &[10])
}

/// π in Pinocchio's order.
#[pyfunction]
fn to_pinocchio<'py>(
    py: Python<'py>,
    pi: PyReadonlyArrayDyn<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    array(py, params(&pi)?.to_pinocchio().to_vec(), &[10])
}
