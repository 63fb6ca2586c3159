//! NumPy arguments checked and read, NumPy results made: a wrong shape or
//! a value that is not finite is a `ValueError` naming the argument.

use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A shape as Python prints it: `(3, 2)`, `(4,)`.
fn shape_of(shape: &[usize]) -> String {
    match shape {
        [k] => format!("({k},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|k| k.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The samples of `a` (argument `what`): shape `(N, k)`, or `(k,)` for
/// one; every value finite. Returns N and the values, sample by sample.
pub(crate) fn samples(
    what: &str,
    a: &PyReadonlyArrayDyn<f64>,
    k: usize,
) -> PyResult<(usize, Vec<f64>)> {
    let rows = match a.shape() {
        [c] if *c == k => 1,
        [n, c] if *c == k => *n,
        s => {
            let m = format!("{what}: shape {}, expected (N, {k}) or ({k},)", shape_of(s));
            return Err(PyValueError::new_err(m));
        }
    };
    let values: Vec<f64> = a.as_array().iter().copied().collect();
    finite(what, &values, k)?;
    Ok((rows, values))
}

/// Time stamps: shape `(N,)`, every value finite.
pub(crate) fn times(what: &str, a: &PyReadonlyArrayDyn<f64>) -> PyResult<Vec<f64>> {
    if a.shape().len() != 1 {
        let m = format!("{what}: shape {}, expected (N,)", shape_of(a.shape()));
        return Err(PyValueError::new_err(m));
    }
    let values: Vec<f64> = a.as_array().iter().copied().collect();
    finite(what, &values, 1)?;
    Ok(values)
}

/// A vector of exactly `K` finite values (argument `what`).
pub(crate) fn vector<const K: usize>(
    what: &str,
    a: &PyReadonlyArrayDyn<f64>,
) -> PyResult<[f64; K]> {
    if a.shape() != [K] {
        let m = format!("{what}: shape {}, expected ({K},)", shape_of(a.shape()));
        return Err(PyValueError::new_err(m));
    }
    let mut out = [0.0; K];
    out.iter_mut()
        .zip(a.as_array().iter())
        .for_each(|(o, v)| *o = *v);
    finite(what, &out, K)?;
    Ok(out)
}

/// A `K × K` matrix of finite values (argument `what`), row by row.
pub(crate) fn matrix<const K: usize>(
    what: &str,
    a: &PyReadonlyArrayDyn<f64>,
) -> PyResult<[[f64; K]; K]> {
    if a.shape() != [K, K] {
        let m = format!("{what}: shape {}, expected ({K}, {K})", shape_of(a.shape()));
        return Err(PyValueError::new_err(m));
    }
    let v: Vec<f64> = a.as_array().iter().copied().collect();
    finite(what, &v, K)?;
    Ok(std::array::from_fn(|i| {
        std::array::from_fn(|j| v[i * K + j])
    }))
}

/// A `ValueError` at the first value that is not finite, by its index
/// (`[i, j]` in rows of `k`).
fn finite(what: &str, values: &[f64], k: usize) -> PyResult<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => {
            let m = format!(
                "{what}: value {} at [{}, {}] is not finite",
                values[i],
                i / k,
                i % k
            );
            Err(PyValueError::new_err(m))
        }
    }
}

/// `values` as an array of `shape`.
pub(crate) fn array<'py>(
    py: Python<'py>,
    values: Vec<f64>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    PyArray1::from_vec(py, values).reshape(shape)
}
