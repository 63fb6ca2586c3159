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

/// Each library error type as its exception.
macro_rules! to_py {
    ($($error:ty => $exception:ident),* $(,)?) => {$(
        impl ToPy for $error {
            fn py_err(self) -> PyErr {
                $exception::new_err(self.to_string())
            }
        }
    )*};
}

to_py! {
    momentlmi::dynamics::DynamicsError => ModelError,
    momentlmi::moments::MomentsError => InertiaError,
    momentlmi::urdf::UrdfError => UrdfError,
    momentlmi::identify::IdentifyError => IdentifyError,
    momentlmi::data::DataError => DataError,
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
