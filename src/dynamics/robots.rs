//! Loading a robot by name or path, and choosing its parameters.

use super::cheetah3;
use super::error::DynamicsError;
use super::model::Model;
use super::params_file::{Friction, ParamsFile};
use super::urdf::model_from_urdf_file;
use std::path::Path;

/// `cheetah3-leg` (built in) or a path to a URDF file (with an optional
/// TOML sidecar).
pub fn load_robot(spec: &str, sidecar: Option<&Path>) -> Result<Model, DynamicsError> {
    match spec {
        "cheetah3-leg" => {
            if sidecar.is_some() {
                return Err(DynamicsError::File {
                    path: spec.into(),
                    message: "a sidecar applies to URDF models only".into(),
                });
            }
            Ok(cheetah3::model())
        }
        path => {
            let p = Path::new(path);
            if !p.exists() {
                return Err(DynamicsError::File {
                    path: path.into(),
                    message: "no such file, and not a built-in model (built in: cheetah3-leg)"
                        .into(),
                });
            }
            model_from_urdf_file(p, sidecar)
        }
    }
}

/// Applies a parameter choice: `true` / `cad` (cheetah3-leg only), a
/// parameter file, or `None` (the model's own). Returns the friction to use
/// (`true`: the simulated leg's Coulomb and viscous values; `cad` and own: none).
pub fn apply_params(model: &mut Model, choice: Option<&str>) -> Result<Friction, DynamicsError> {
    let n = model.dof();
    let zero = Friction {
        viscous: vec![0.0; n],
        coulomb: vec![0.0; n],
    };
    match choice {
        None => Ok(zero),
        Some(c @ ("true" | "cad")) => {
            if model.name != "cheetah3-leg" {
                return Err(DynamicsError::File {
                    path: c.into(),
                    message: format!(
                        "--params {c} is defined for cheetah3-leg only; give a parameter file for '{}'",
                        model.name
                    ),
                });
            }
            if c == "true" {
                *model = cheetah3::model();
                Ok(Friction {
                    viscous: cheetah3::VISCOUS.to_vec(),
                    coulomb: cheetah3::COULOMB.to_vec(),
                })
            } else {
                *model = cheetah3::model_with(&cheetah3::cad_params())?;
                Ok(zero)
            }
        }
        Some(path) => {
            let f = ParamsFile::read(Path::new(path))?;
            f.apply(model, path)
        }
    }
}
