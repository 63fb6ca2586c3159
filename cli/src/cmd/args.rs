//! Argument groups the commands share (flattened into them by clap).

use clap::Args;
use momentlmi::data::Velocity;
use momentlmi::effects::Library;
use std::path::PathBuf;

/// Which robot: a built-in name or a URDF with its sidecar.
#[derive(Args, Debug, Clone)]
pub struct RobotArgs {
    /// Built-in robot (cheetah3-leg) or a URDF file.
    #[arg(long)]
    pub robot: String,
    /// TOML sidecar for a URDF: rotors, locked joints, prior, bounding
    /// ellipsoids, friction, tool point (docs/robots.md).
    /// [default: NAME.toml beside NAME.urdf, if there is one]
    #[arg(long, conflicts_with = "no_sidecar")]
    pub sidecar: Option<PathBuf>,
    /// Use no sidecar, not even the one beside the URDF.
    #[arg(long)]
    pub no_sidecar: bool,
    /// A folder where a URDF's `package://NAME/…` meshes are found (repeatable; searched after
    /// the folders above the URDF, before ROS_PACKAGE_PATH); meshes outside the URDF's folder
    /// and these folders are not read.
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_path: Vec<PathBuf>,
}

impl RobotArgs {
    /// `--sidecar` made the sidecar the command uses: the one given, else
    /// (unless `--no-sidecar`) the one beside the URDF ([`own_sidecar`],
    /// said once, here).
    pub fn resolve(&mut self) {
        self.sidecar = own_sidecar(&self.robot, self.sidecar.take(), self.no_sidecar);
    }

    /// The robot (its sidecar's `[effects]` names checked:
    /// [`super::load_robot_rooted`]).
    pub fn load(&self) -> Result<momentlmi::dynamics::RobotDescription, String> {
        self.load_rooted(false)
    }

    /// [`Self::load`] with the URDF's root link a free-flying base when
    /// `free_flyer`.
    pub fn load_rooted(
        &self,
        free_flyer: bool,
    ) -> Result<momentlmi::dynamics::RobotDescription, String> {
        let (spec, sidecar) = (&self.robot, self.sidecar.as_deref());
        super::load_robot_rooted(spec, sidecar, &self.package_path, free_flyer)
    }

    /// The files loading this robot reads, which none of the command's
    /// outputs may be: the URDF, the meshes it names, the sidecar and the
    /// sidecar's `[data] mapping`. A file that cannot be read now is left
    /// out (loading it names the problem).
    pub fn input_files(&self) -> Vec<PathBuf> {
        use momentlmi::urdf::mesh::{MeshPaths, mesh_files};
        let mut out = vec![];
        let urdf = std::path::Path::new(&self.robot);
        if urdf.is_file() {
            out.push(urdf.to_path_buf());
            if let Ok((_, robot)) = momentlmi::urdf::read_file(urdf) {
                out.extend(mesh_files(
                    &robot,
                    &MeshPaths::for_urdf(urdf, &self.package_path),
                ));
            }
        }
        if let Some(s) = &self.sidecar {
            out.push(s.clone());
            let sidecar = momentlmi::dynamics::sidecar::Sidecar::read(s).ok();
            out.extend(sidecar.and_then(|sc| sc.mapping_path(Some(s))));
        }
        out
    }

    /// The files a command reads, to protect from its outputs: this
    /// robot's ([`Self::input_files`]), `files` (logs, `--mapping`,
    /// trajectories, repeats, …), and each of `specs` (a parameter choice:
    /// `cad`, `true` or a path) that names an existing file.
    pub fn inputs_with(&self, files: &[&std::path::Path], specs: &[&str]) -> Vec<PathBuf> {
        let named = (specs.iter().map(std::path::Path::new)).filter(|p| p.is_file());
        let given = files
            .iter()
            .copied()
            .chain(named)
            .map(std::path::Path::to_path_buf);
        self.input_files().into_iter().chain(given).collect()
    }

    /// The logs `paths` read for the joints `names` ([`super::read_data`]:
    /// a data error hints at this robot's sidecar when it may explain it).
    pub fn read(
        &self,
        paths: &[PathBuf],
        names: &[&str],
        opts: &momentlmi::data::ReadOptions,
    ) -> Result<momentlmi::data::Reading, String> {
        let p: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
        super::read_data(&p, names, opts, &self.robot, self.sidecar.as_deref())
    }
}

/// The sidecar: the one given, else (unless `--no-sidecar`) `NAME.toml`
/// beside a `NAME.urdf`, said on stderr.
pub(crate) fn own_sidecar(robot: &str, given: Option<PathBuf>, none: bool) -> Option<PathBuf> {
    if none || given.is_some() {
        return given;
    }
    let beside = super::sidecar_beside(robot)?;
    eprintln!(
        "note: using the sidecar beside the URDF, {} (--sidecar FILE for another, --no-sidecar for none)",
        beside.display()
    );
    Some(beside)
}

/// How log files are read (docs/inputs.md).
#[derive(Args, Debug, Clone)]
pub struct ReadArgs {
    /// Column mapping (TOML): which array, column or field is q, q̇, q̈, τ of which joint, and
    /// units [default: the sidecar's [data] mapping, else each format's own names]
    /// (docs/inputs.md, "Column mappings").
    #[arg(long, value_name = "FILE")]
    pub mapping: Option<PathBuf>,
    /// Low-pass cut-off (Hz) applied to q and τ alike of raw logs (files without q̈)
    /// [default: chosen from the data's spectrum, and reported].
    #[arg(long, value_name = "HZ", allow_hyphen_values = true)]
    pub cutoff_hz: Option<f64>,
    /// Where a raw log's q̇ comes from: differentiate (the filtered q; a logged velocity is
    /// often filtered by the drive and lags) or file (the file's, through the same low-pass).
    #[arg(long, value_enum, default_value_t = Velocity::Differentiate)]
    pub velocity: Velocity,
}

impl ReadArgs {
    pub fn choice(&self) -> super::ReadChoice<'_> {
        super::ReadChoice {
            mapping: self.mapping.as_deref(),
            cutoff_hz: self.cutoff_hz,
            velocity: self.velocity,
        }
    }
}

/// `simulate --help`'s list of effect parameters.
pub(crate) fn effect_param_help() -> String {
    format!(
        "Effect parameter override NAME=VALUE (repeatable), e.g. `stiffness=300`; a parameter of an effect that is not switched on is an error. The robot's sidecar [effects] table replaces the built-in defaults below.\n{}",
        Library::builtin().param_help()
    )
}

/// The built-in effects' names, each with its summary, for `--effects`.
pub(crate) fn effect_names() -> clap::builder::PossibleValuesParser {
    let lib = Library::builtin();
    clap::builder::PossibleValuesParser::new(
        lib.effects()
            .iter()
            .map(|e| clap::builder::PossibleValue::new(e.name()).help(e.summary())),
    )
}

/// Whether the robot's root link is free (docs/floating-base.md).
#[derive(Args, Debug, Clone)]
pub struct FloatingArgs {
    /// Load the URDF's root link as a floating base (a legged robot, a drone): its six base
    /// rows balanced by the contact wrenches; the data are floating-base logs
    /// (docs/floating-base.md) [default: on when the sidecar has a [floating_base] table].
    #[arg(long)]
    pub floating_base: bool,
}
