//! The exceptions: `MomentlmiError` and one subclass per library module,
//! each with the library's message (the CLI's words). A wrong argument
//! (shape, value) is a `ValueError` naming it.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    momentlmi,
    MomentlmiError,
    PyException,
    "Any error of momentlmi."
);
create_exception!(
    momentlmi,
    DataError,
    MomentlmiError,
    "A data file or array."
);
create_exception!(
    momentlmi,
    ModelError,
    MomentlmiError,
    "A robot's description."
);
create_exception!(
    momentlmi,
    InertiaError,
    MomentlmiError,
    "Inertial parameters."
);
create_exception!(momentlmi, UrdfError, MomentlmiError, "A URDF file.");
create_exception!(
    momentlmi,
    IdentifyError,
    MomentlmiError,
    "An identification."
);

pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("MomentlmiError", py.get_type::<MomentlmiError>())?;
    m.add("DataError", py.get_type::<DataError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("InertiaError", py.get_type::<InertiaError>())?;
    m.add("UrdfError", py.get_type::<UrdfError>())?;
    m.add("IdentifyError", py.get_type::<IdentifyError>())?;
    Ok(())
}

/// A library error as its exception.
pub(crate) trait ToPy {
    fn py_err(self) -> PyErr;
}

impl ToPy for momentlmi::dynamics::DynamicsError {
    fn py_err(self) -> PyErr {
        ModelError::new_err(self.to_string())
    }
}

impl ToPy for momentlmi::moments::MomentsError {
    fn py_err(self) -> PyErr {
        InertiaError::new_err(self.to_string())
    }
}

impl ToPy for momentlmi::urdf::UrdfError {
    fn py_err(self) -> PyErr {
        UrdfError::new_err(self.to_string())
    }
}

impl ToPy for momentlmi::identify::IdentifyError {
    fn py_err(self) -> PyErr {
        IdentifyError::new_err(self.to_string())
    }
}

impl ToPy for momentlmi::data::DataError {
    fn py_err(self) -> PyErr {
        DataError::new_err(self.to_string())
    }
}

/// `Result<T, E>` with a library error `E` as a `PyResult`.
pub(crate) trait OrPy<T> {
    fn or_py(self) -> PyResult<T>;
}

impl<T, E: ToPy> OrPy<T> for Result<T, E> {
    fn or_py(self) -> PyResult<T> {
        self.map_err(ToPy::py_err)
    }
}
