//! `momentlmi export --robot MODEL --params true|cad|FILE [--urdf-out F.urdf
//! [--sidecar-out F.toml]] [--mjcf-out F.xml]`: a model into the formats
//! simulators read (docs/export.md).

use super::args::RobotArgs;
use momentlmi::data::Staged;
use momentlmi::dynamics::{Friction, Model, ParamChoice, RobotDescription};
use momentlmi::export::mjcf::{Shapes, mjcf};
use momentlmi::export::{
    MujocoView, UrdfSource, sidecar_with_params, urdf_of_model, urdf_with_params,
};
use momentlmi::sim::trajectory::Trajectory;
use momentlmi::urdf::mesh::MeshPaths;
use std::path::{Path, PathBuf};

/// Where the exports go.
#[derive(Clone, Copy, Default)]
pub struct Outputs<'a> {
    /// The URDF copy.
    pub urdf: Option<&'a Path>,
    /// Its sidecar (default: beside it, `NAME.toml`).
    pub sidecar: Option<&'a Path>,
    /// The MuJoCo model.
    pub mjcf: Option<&'a Path>,
}

impl Outputs<'_> {
    /// Whether any export is asked for.
    pub fn any(&self) -> bool {
        self.urdf.is_some() || self.mjcf.is_some()
    }

    /// The sidecar's path: the one given, else beside the URDF.
    fn sidecar_path(&self) -> Option<PathBuf> {
        self.sidecar
            .map(Path::to_path_buf)
            .or_else(|| self.urdf.map(|u| u.with_extension("toml")))
    }

    /// Every output claimed in `staged` (refused early: an input, a folder,
    /// twice the same file).
    pub fn claim(&self, staged: &Staged) -> Result<(), String> {
        if self.sidecar.is_some() && self.urdf.is_none() {
            return Err("--sidecar-out goes with --urdf-out".into());
        }
        let side = self.sidecar_path();
        for p in [self.urdf, side.as_deref(), self.mjcf]
            .into_iter()
            .flatten()
        {
            staged.claim(p).map_err(|e| e.to_string())?;
        }
        Ok(())
    }
}

/// `momentlmi export`'s options, declared once: clap parses them and the
/// command reads them (the robot's sidecar resolved first,
/// [`RobotArgs::resolve`]).
#[derive(clap::Args, Debug, Clone)]
pub struct ExportArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// `true` (own parameters + nominal friction), `cad` (the description's prior), or a
    /// parameter file (the JSON `identify --json` prints); default: the model's own, no
    /// friction.
    #[arg(long)]
    pub params: Option<String>,
    #[command(flatten)]
    pub out: ExportOutArgs,
}

/// Exit codes: 0 written, 2 bad input or a model a format cannot hold.
pub fn run(a: &ExportArgs, free_flyer: bool) -> i32 {
    match run_inner(a, free_flyer) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

fn run_inner(a: &ExportArgs, free_flyer: bool) -> Result<(), String> {
    if !a.out.outputs().any() {
        return Err("nothing to write: give --urdf-out and/or --mjcf-out".into());
    }
    let staged = Staged::protecting(
        a.robot
            .inputs_with(&[], &[a.params.as_deref().unwrap_or("")]),
    );
    a.out.outputs().claim(&staged)?;
    let robot = a.robot.load_rooted(free_flyer)?;
    if a.params.as_deref().is_some_and(|p| p == "true") {
        // placeholder friction would otherwise be written as if it were known
        super::warn_robot(&robot);
    }
    let (model, friction) = super::parameters_without_effects_for(
        &robot,
        "--params",
        a.params.as_deref(),
        ParamChoice::Own,
        "a URDF, MJCF or sidecar has no place for them",
    )?;
    write(
        staged,
        &robot,
        (&model, &friction),
        a.out.outputs(),
        &a.robot.package_path,
    )
}

/// Writes the exports of `model` (of `robot`) through `staged` (outputs
/// claimed) and commits them together; says what MuJoCo leaves out.
pub fn write(
    mut staged: Staged,
    robot: &RobotDescription,
    (model, friction): (&Model, &Friction),
    out: Outputs,
    package_paths: &[PathBuf],
) -> Result<(), String> {
    let urdf = urdf_source(robot)?;
    if let Some(path) = out.urdf {
        let text = match &urdf {
            Some((text, read)) => {
                let src = UrdfSource {
                    text,
                    robot: read,
                    path: &robot.source,
                };
                urdf_with_params(&src, model, friction)
            }
            None => urdf_of_model(model, friction),
        }
        .map_err(|e| e.to_string())?;
        staged.add_text(path, &text).map_err(|e| e.to_string())?;
        let given = sidecar_text(robot)?;
        let given = given.as_ref().map(|(t, p)| (t.as_str(), p.as_str()));
        let side =
            sidecar_with_params(given, model, friction, &robot.prior).map_err(|e| e.to_string())?;
        let side_path = out.sidecar_path().expect("with --urdf-out");
        staged
            .add_text(&side_path, &side)
            .map_err(|e| e.to_string())?;
    }
    if let Some(path) = out.mjcf {
        let view = MujocoView::new(model, friction).map_err(|e| e.to_string())?;
        let meshes = MeshPaths::for_urdf(Path::new(&robot.source), package_paths);
        let shapes = urdf.as_ref().map(|(_, read)| Shapes {
            robot: read,
            meshes: &meshes,
        });
        let written = mjcf(&view, model, shapes.as_ref()).map_err(|e| e.to_string())?;
        staged
            .add_text(path, &written.text)
            .map_err(|e| e.to_string())?;
        report_view(robot, model, &view, &written.notes)?;
    }
    for p in staged.commit().map_err(|e| e.to_string())? {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

/// The robot's URDF text and its reading, or `None` for a built-in robot.
fn urdf_source(
    robot: &RobotDescription,
) -> Result<Option<(String, momentlmi::urdf::Robot)>, String> {
    if momentlmi::dynamics::robots::built_in(&robot.source).is_some() {
        return Ok(None);
    }
    let (text, read) =
        momentlmi::urdf::read_file(Path::new(&robot.source)).map_err(|e| e.to_string())?;
    Ok(Some((text, read)))
}

/// The sidecar the robot was described with (text, path): its file, or a
/// built-in robot's own.
fn sidecar_text(robot: &RobotDescription) -> Result<Option<(String, String)>, String> {
    if let Some(b) = momentlmi::dynamics::robots::built_in(&robot.source) {
        return Ok(Some((
            b.sidecar.to_string(),
            format!("{} (built in)", b.name),
        )));
    }
    let Some(path) = &robot.sidecar else {
        return Ok(None);
    };
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    Ok(Some((text, path.clone())))
}

/// What the MuJoCo model leaves out: the notes, and the torques the
/// rotors' coupling carries over 10 s of the robot's default excitation.
fn report_view(
    robot: &RobotDescription,
    model: &Model,
    view: &MujocoView,
    notes: &[String],
) -> Result<(), String> {
    for n in notes {
        eprintln!("note: MuJoCo model: {n}");
    }
    if model.rotors.is_empty() {
        return Ok(());
    }
    let motion = Trajectory::for_excitation(&robot.excitation, model, 1);
    let d = view
        .dropped(model, &motion, 10.0)
        .map_err(|e| e.to_string())?;
    eprintln!(
        "note: MuJoCo model: torque left out (RMS over 10 s of the default excitation, against the full model's RMS):"
    );
    for (j, joint) in model.joints.iter().enumerate() {
        eprintln!(
            "  {:<12} {:.4} of {:.4} N·m",
            joint.name, d.rms[j], d.rms_full[j]
        );
    }
    Ok(())
}

/// Where a model is exported (docs/export.md).
#[derive(clap::Args, Debug, Clone)]
pub struct ExportOutArgs {
    /// A URDF to write: the robot's own with each body's <inertial> and each joint's
    /// <dynamics> replaced (a built-in robot: one written from its model).
    #[arg(long, value_name = "OUT.urdf")]
    pub urdf_out: Option<PathBuf>,
    /// The sidecar written with --urdf-out (rotors, friction, the prior)
    /// [default: beside it, OUT.toml].
    #[arg(long, value_name = "OUT.toml", requires = "urdf_out")]
    pub sidecar_out: Option<PathBuf>,
    /// A MuJoCo model (MJCF) to write: rotors as joint armature, viscous friction as
    /// damping, Coulomb as frictionloss.
    #[arg(long, value_name = "OUT.xml")]
    pub mjcf_out: Option<PathBuf>,
}

impl ExportOutArgs {
    pub fn outputs(&self) -> Outputs<'_> {
        Outputs {
            urdf: self.urdf_out.as_deref(),
            sidecar: self.sidecar_out.as_deref(),
            mjcf: self.mjcf_out.as_deref(),
        }
    }
}
