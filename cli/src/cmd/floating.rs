//! `--floating-base`: `simulate`, `identify` and `predict` of a robot whose
//! root link is free (docs/floating-base.md). Each command routes here when
//! the flag is given or the sidecar has a `[floating_base]` table; options
//! that have no floating-base meaning yet are refused by name.

use momentlmi::data::Dataset;
use momentlmi::dynamics::Model;
use momentlmi::dynamics::sidecar::{Sidecar, SidecarFloating};
use std::path::{Path, PathBuf};

/// How a simulated floating-base robot touches the world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Contacts {
    /// Hung from a harness: one six-axis load cell at the base.
    Suspended,
    /// Standing on force plates: the sidecar's `[floating_base] feet`, in
    /// its `stance`, while the base sways and tilts.
    Standing,
}

/// An effect a simulated floating base's true robot has (its magnitude
/// fixed: [`SimEffect::effects`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
#[value(rename_all = "snake_case")]
pub enum SimEffect {
    /// 0.01 N·m·s/rad viscous and 0.05 N·m Coulomb friction at every joint.
    JointFriction,
    /// Every contact's sensor off by [1, −0.5, 2] N and [0.05, 0.02, −0.03] N·m.
    WrenchOffset,
    /// 0.3 kg on the base at [0.05, 0, 0.03] m (base frame).
    Payload,
}

impl SimEffect {
    /// The library's effects of a list
    /// ([`FloatingEffects::named`](momentlmi::sim::floating::FloatingEffects::named)).
    pub fn effects(
        list: &[SimEffect],
    ) -> Result<momentlmi::sim::floating::FloatingEffects, String> {
        let names: Vec<&str> = (list.iter())
            .map(|s| match s {
                SimEffect::JointFriction => "joint_friction",
                SimEffect::WrenchOffset => "wrench_offset",
                SimEffect::Payload => "payload",
            })
            .collect();
        momentlmi::sim::floating::FloatingEffects::named(&names).map_err(|e| e.to_string())
    }
}

/// A robot given to a floating-base command.
#[derive(Clone, Copy, Debug)]
pub struct Robot<'a> {
    /// The URDF (its root link is the base).
    pub spec: &'a str,
    /// Its sidecar.
    pub sidecar: Option<&'a Path>,
    /// `--floating-base` was given.
    pub flag: bool,
}

impl Robot<'_> {
    /// Whether the command runs on a floating base: the flag, or the
    /// sidecar's `[floating_base]` table.
    pub fn is_floating(&self) -> Result<bool, String> {
        Ok(self.flag || self.facts()?.is_some())
    }

    /// The sidecar's `[floating_base]` table, if any.
    fn facts(&self) -> Result<Option<SidecarFloating>, String> {
        match self.sidecar {
            None => Ok(None),
            Some(p) => Ok(Sidecar::read(p).map_err(|e| e.to_string())?.floating_base),
        }
    }

    /// The sidecar's floating-base facts (an empty table without one).
    pub fn floating_facts(&self) -> Result<SidecarFloating, String> {
        Ok(self.facts()?.unwrap_or_default())
    }

    /// The robot described with a free-flying root (prior, bounding
    /// volumes of every body, the base's from the root link's geometry;
    /// sidecar facts), meshes also looked for in `package_paths`.
    pub fn describe(
        &self,
        package_paths: &[std::path::PathBuf],
    ) -> Result<momentlmi::dynamics::RobotDescription, String> {
        let path = self.urdf()?.to_str().ok_or("a non-UTF-8 URDF path")?;
        super::load_robot_rooted(path, self.sidecar, package_paths, true)
    }

    /// The URDF file, or an error: a floating base is a URDF's root link.
    fn urdf(&self) -> Result<&Path, String> {
        let path = Path::new(self.spec);
        let is_urdf = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("urdf"));
        if !is_urdf {
            return Err(format!(
                "--floating-base needs a URDF file (its root link is the base); '{}' is not one",
                self.spec
            ));
        }
        Ok(path)
    }
}

/// An error for each option given that a floating-base command does not
/// take yet: `(name, given)`.
pub fn refuse(options: &[(&str, bool)]) -> Result<(), String> {
    match options.iter().find(|(_, given)| *given) {
        Some((name, _)) => Err(format!(
            "{name} is not available with --floating-base yet (docs/floating-base.md, \"Not yet built\")"
        )),
        None => Ok(()),
    }
}

/// The reading options a floating-base log does not take yet (it is read
/// by its own CSV reader), as [`refuse`] wants them.
pub fn reading_options(read: &super::ReadChoice) -> [(&'static str, bool); 3] {
    [
        ("--mapping", read.mapping.is_some()),
        ("--cutoff-hz", read.cutoff_hz.is_some()),
        (
            "--velocity file",
            read.velocity != momentlmi::data::Velocity::Differentiate,
        ),
    ]
}

/// Every floating-base log in `paths`
/// ([`read_floating_logs`](momentlmi::data::read_floating_logs)); `what`
/// names the option in errors, `max_gib` the memory allowed.
pub fn read_logs(
    ff: &Model,
    paths: &[PathBuf],
    (what, max_gib): (&str, f64),
) -> Result<Vec<Dataset>, String> {
    let max_bytes = super::gib(max_gib)?;
    let paths: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
    (momentlmi::data::read_floating_logs(ff, &paths, max_bytes)).map_err(|e| match e {
        momentlmi::data::DataError::Option { message, .. } => format!(
            "{what}: {message} of {} GiB (--max-memory-gib)",
            momentlmi::numfmt::short(max_gib)
        ),
        e => format!("{what}: {e}"),
    })
}

/// The regressor's parameter vector: every body's, then each friction
/// term's coefficients per joint (the model's terms; absent ones 0).
pub fn theta_of(ff: &Model, friction: &momentlmi::dynamics::Friction) -> Vec<f64> {
    let mut theta = ff.params();
    for &term in ff.friction_terms() {
        let c = friction.coefficients(term);
        theta.extend((0..ff.dof()).map(|j| c.get(j).copied().unwrap_or(0.0)));
    }
    theta
}

/// The stance's joint positions (n) from the sidecar's table; a joint the
/// robot does not have is an error naming it.
pub fn stance(ff: &Model, facts: &SidecarFloating) -> Result<Vec<f64>, String> {
    let names = ff.joint_names();
    let mut q = vec![0.0; names.len()];
    for (joint, &value) in &facts.stance {
        let i = names.iter().position(|n| n == joint).ok_or_else(|| {
            format!(
                "sidecar [floating_base] stance: joint '{joint}' is not in the robot (joints: {})",
                names.join(", ")
            )
        })?;
        if !value.is_finite() {
            return Err(format!(
                "sidecar [floating_base] stance: joint '{joint}' = {value}"
            ));
        }
        q[i] = value;
    }
    Ok(q)
}

/// The robot with the parameters `choice` names (none or `true`: the
/// URDF's own; `cad`: the description's prior, as `identify --prior cad`
/// takes it; else a parameter file's, e.g. `identify --json`) and their
/// friction (none for `true` and `cad`); `option` names the flag in errors.
pub fn with_params(
    robot: &momentlmi::dynamics::RobotDescription,
    choice: Option<&str>,
    option: &str,
) -> Result<(Model, momentlmi::dynamics::Friction), String> {
    let mut ff = robot.model.clone();
    let friction = match choice {
        None | Some("true") => momentlmi::dynamics::Friction::zeros(ff.dof()),
        Some("cad") => {
            (ff.set_params(&robot.prior_vector())).map_err(|e| format!("{option}: {e}"))?;
            momentlmi::dynamics::Friction::zeros(ff.dof())
        }
        Some(file) => {
            let pf = momentlmi::dynamics::params_file::ParamsFile::read(Path::new(file))
                .map_err(|e| format!("{option}: {e}"))?;
            pf.apply(&mut ff, file)
                .map_err(|e| format!("{option}: {e}"))?
        }
    };
    Ok((ff, friction))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::ValueEnum;

    #[test]
    fn every_simulated_effect_is_one_the_library_knows() {
        for e in SimEffect::value_variants() {
            let name = e.to_possible_value().unwrap().get_name().to_string();
            let effects = SimEffect::effects(&[*e]).unwrap();
            assert_eq!(effects.names(), vec![name.as_str()]);
        }
    }
}
