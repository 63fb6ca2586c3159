//! The `momentlmi._native` extension module: the library's checks,
//! dynamics and fleet reduction for Python, NumPy arrays in and out. The
//! package `momentlmi` (python/momentlmi) wraps it: it turns array-likes
//! into float arrays and JSON reports into dicts.

mod arrays;
mod check;
mod diagnose;
mod errors;
mod excite;
mod identify;
mod identify_logs;
mod inertia;
mod notes;
mod reducer;
mod robot;
mod setup;
mod simulate;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::add(m)?;
    inertia::add(m)?;
    check::add(m)?;
    simulate::add(m)?;
    identify::add(m)?;
    identify_logs::add(m)?;
    diagnose::add(m)?;
    excite::add(m)?;
    m.add_class::<robot::Robot>()?;
    m.add_class::<reducer::Reducer>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "REDUCED_FORMAT_VERSION",
        momentlmi::identify::fleet::REDUCED_FORMAT_VERSION,
    )?;
    Ok(())
}
