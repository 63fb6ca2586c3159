//! A URDF's inertias checked against its geometry, and repaired: the
//! reports `momentlmi check --json` prints.

use crate::errors::{MomentlmiError, OrPy};
use momentlmi::dynamics::sidecar::Sidecar;
use momentlmi::moments::cache::SolveCache;
use momentlmi::moments::geometry::Meshes;
use momentlmi::moments::urdf_check::{
    RepairOptions, RepairTarget, check_urdf_file_with, repair_urdf,
};
use momentlmi::urdf::mesh::MeshPaths;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_urdf, m)?)?;
    m.add_function(wrap_pyfunction!(repair_urdf_text, m)?)?;
    Ok(())
}

/// The meshes and bounding volumes the check uses, as the CLI finds them.
fn meshes(path: &Path, sidecar: Option<PathBuf>, package_paths: &[PathBuf]) -> PyResult<Meshes> {
    let mut meshes = Meshes::new(MeshPaths::for_urdf(path, package_paths));
    if let Some(cache) = SolveCache::from_env() {
        meshes = meshes.with_cache(cache);
    }
    let Some(sc) = sidecar else {
        return Ok(meshes);
    };
    let file = Sidecar::read(&sc).or_py()?;
    for b in file.bodies.iter().filter(|b| !b.bounding.is_empty()) {
        let es = b
            .ellipsoids()
            .map_err(|e| MomentlmiError::new_err(format!("{}: {e}", sc.display())))?;
        meshes = meshes.with_bounding(&b.name, es);
    }
    Ok(meshes)
}

/// `check --json`'s report of the URDF at `path` (JSON), and its warnings.
#[pyfunction]
#[pyo3(signature = (path, sidecar=None, package_paths=vec![]))]
fn check_urdf(
    path: PathBuf,
    sidecar: Option<PathBuf>,
    package_paths: Vec<PathBuf>,
) -> PyResult<(String, Vec<String>)> {
    let mut meshes = meshes(&path, sidecar, &package_paths)?;
    let (_, _, report) = check_urdf_file_with(&path, &mut meshes).or_py()?;
    let warnings = report
        .warnings
        .iter()
        .map(|w| format!("{}: {w}", path.display()))
        .collect();
    let json =
        serde_json::to_string(&report).map_err(|e| MomentlmiError::new_err(e.to_string()))?;
    Ok((json, warnings))
}

/// The URDF's text with its inconsistent inertials (`target="geometry"`:
/// also those not realizable in their geometry) repaired, and the links
/// repaired, as `check --repair` writes them.
#[pyfunction]
#[pyo3(signature = (path, target="consistent", margin=1e-6, sidecar=None, package_paths=vec![]))]
fn repair_urdf_text(
    path: PathBuf,
    target: &str,
    margin: f64,
    sidecar: Option<PathBuf>,
    package_paths: Vec<PathBuf>,
) -> PyResult<(String, Vec<String>)> {
    let target = match target {
        "consistent" => RepairTarget::Consistent,
        "geometry" => RepairTarget::Geometry,
        t => {
            return Err(PyValueError::new_err(format!(
                "target: '{t}' is not one of consistent, geometry"
            )));
        }
    };
    if !(margin.is_finite() && (0.0..0.1).contains(&margin)) {
        return Err(PyValueError::new_err(format!(
            "margin: {margin} is not in [0, 0.1)"
        )));
    }
    let mut meshes = meshes(&path, sidecar, &package_paths)?;
    let (text, _, report) = check_urdf_file_with(&path, &mut meshes).or_py()?;
    let opts = RepairOptions { target, margin };
    repair_urdf(&text, &report, &path.display().to_string(), &opts).or_py()
}
