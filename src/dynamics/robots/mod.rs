//! Loading a robot by name or path: the built-in robots (one file each in
//! this folder, each joining the registry `BUILT_IN` with its entry) and
//! URDF files with an optional sidecar, both into a [`RobotDescription`]
//! through [`RobotDescription::new`].

pub mod cheetah3;
mod entry;

pub use entry::BuiltIn;

use super::description::RobotDescription;
use super::error::DynamicsError;
use super::sidecar::Sidecar;
use super::urdf::model_from_robot;
use crate::urdf::mesh::MeshPaths;
use std::path::Path;

/// The registry of built-in robots: one line per robot.
const BUILT_IN: &[BuiltIn] = &[cheetah3::ENTRY];

/// The built-in robots' names.
pub fn built_in_names() -> Vec<&'static str> {
    BUILT_IN.iter().map(|b| b.name).collect()
}

/// The built-in robot named `name`, if there is one.
pub fn built_in(name: &str) -> Option<&'static BuiltIn> {
    BUILT_IN.iter().find(|b| b.name == name)
}

/// A built-in robot (`cheetah3-leg`) or a path to a URDF file (with an
/// optional TOML sidecar), described; a URDF body without a sidecar
/// bounding ellipsoid gets one from its geometry
/// ([`RobotDescription::with_urdf_geometry`], meshes found beside the URDF
/// and in `ROS_PACKAGE_PATH`).
pub fn load_robot(spec: &str, sidecar: Option<&Path>) -> Result<RobotDescription, DynamicsError> {
    load_robot_with(spec, sidecar, &[])
}

/// [`load_robot`] with folders where a URDF's `package://` meshes are found
/// (searched after the folders above the URDF, before `ROS_PACKAGE_PATH`).
pub fn load_robot_with(
    spec: &str,
    sidecar: Option<&Path>,
    package_paths: &[std::path::PathBuf],
) -> Result<RobotDescription, DynamicsError> {
    load_rooted(spec, sidecar, package_paths, false)
}

/// [`load_robot_with`] for a URDF whose root link is a free-flying base
/// ([`RootJoint::FreeFlyer`](super::RootJoint::FreeFlyer)): the base is
/// body 0 of the description (its prior, its bounding volume from the
/// root link's geometry, its sidecar `[[body]]` entry by the root link's
/// name). A built-in robot has a fixed base.
pub fn load_free_flyer(
    spec: &str,
    sidecar: Option<&Path>,
    package_paths: &[std::path::PathBuf],
) -> Result<RobotDescription, DynamicsError> {
    if BUILT_IN.iter().any(|b| b.name == spec) {
        return Err(DynamicsError::File {
            path: spec.into(),
            message: "a built-in robot has a fixed base; a floating base needs a URDF file (its root link is the base)".into(),
        });
    }
    load_rooted(spec, sidecar, package_paths, true)
}

fn load_rooted(
    spec: &str,
    sidecar: Option<&Path>,
    package_paths: &[std::path::PathBuf],
    free_flyer: bool,
) -> Result<RobotDescription, DynamicsError> {
    if let Some(b) = BUILT_IN.iter().find(|b| b.name == spec) {
        if sidecar.is_some() {
            return Err(DynamicsError::File {
                path: spec.into(),
                message: "a sidecar applies to URDF models only (a built-in robot has its own)"
                    .into(),
            });
        }
        return (b.describe)();
    }
    let p = Path::new(spec);
    if !p.exists() {
        return Err(DynamicsError::File {
            path: spec.into(),
            message: format!(
                "no such file, and not a built-in model (built in: {})",
                built_in_names().join(", ")
            ),
        });
    }
    let (_, robot) = crate::urdf::read_file(p)?;
    let sc = sidecar.map(Sidecar::read).transpose()?.unwrap_or_default();
    let model = match free_flyer {
        false => model_from_robot(&robot, spec, Some(&sc)),
        true => super::urdf::free_flyer_from_robot(&robot, spec, Some(&sc)),
    };
    let model = model.map_err(|e| name_the_sidecar(e, spec, sidecar))?;
    let described = RobotDescription::new(spec, model, &sc, Some(&robot));
    let mut described = described
        .map_err(|e| name_the_sidecar(e, spec, sidecar))?
        .with_urdf_geometry(&robot, MeshPaths::for_urdf(p, package_paths));
    described.sidecar = sidecar.map(|s| s.display().to_string());
    described.data_mapping = sc.mapping_path(sidecar);
    Ok(described)
}

/// An error building or describing a URDF robot with a sidecar names both
/// files (the entry at fault is the sidecar's, or the URDF's that it
/// describes: a lock, a rotor, a limit, a body).
fn name_the_sidecar(e: DynamicsError, spec: &str, sidecar: Option<&Path>) -> DynamicsError {
    let Some(sc) = sidecar else { return e };
    let both = format!("{spec} (sidecar {})", sc.display());
    match e {
        DynamicsError::Description { message, .. } => DynamicsError::Description {
            source_name: both,
            message,
        },
        DynamicsError::File { path, message } if path == spec => DynamicsError::File {
            path: both,
            message,
        },
        e => e,
    }
}
