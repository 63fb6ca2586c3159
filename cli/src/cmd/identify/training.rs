//! The training data: streamed into the reduction, or read whole with the
//! raw logs' cut-off chosen on them.

use super::args::{IdentifyArgs, explain};
use momentlmi::dynamics::{FrictionTerm, RobotDescription};
use momentlmi::identify::IdentifyError;
use std::path::Path;

/// The training data: reduced while read (prepared CSV logs, when neither
/// `--weight auto` nor a load friction term needs the samples again), or
/// read whole.
pub(super) enum Training {
    Streamed(momentlmi::identify::StreamedLogs),
    Whole(momentlmi::data::Reading),
}

impl Training {
    pub(super) fn files(&self) -> &[momentlmi::data::FileReport] {
        match self {
            Self::Streamed(t) => &t.files,
            Self::Whole(t) => &t.files,
        }
    }

    pub(super) fn into_files(self) -> Vec<momentlmi::data::FileReport> {
        match self {
            Self::Streamed(t) => t.files,
            Self::Whole(t) => t.files,
        }
    }

    /// Reading's and filtering's times (s) and whether it was streamed.
    pub(super) fn times(&self) -> (f64, f64, bool) {
        match self {
            Self::Streamed(t) => (t.read_s, 0.0, true),
            Self::Whole(t) => (t.read_s, t.filter_s, false),
        }
    }

    pub(super) fn samples(&self) -> usize {
        match self {
            Self::Streamed(t) => t.reduced.samples,
            Self::Whole(t) => t.data.len(),
        }
    }
}

/// Reads `--data`: streamed into the reduction where it can be
/// ([`Training`]), else whole, the raw logs' cut-off chosen on them when
/// none is given ([`momentlmi::identify::cutoff::read_training`]).
pub(super) fn training(
    a: &IdentifyArgs,
    robot: &RobotDescription,
    opts: &momentlmi::data::ReadOptions,
) -> Result<(Training, Option<momentlmi::identify::cutoff::CutoffCurve>), String> {
    let load = robot.model.friction_terms().contains(&FrictionTerm::Load);
    if a.weight()?.is_some() && !load && a.with_effects.as_deref().is_none() && !a.friction_auto() {
        let p: Vec<&Path> = a.data.iter().map(|p| p.as_path()).collect();
        match momentlmi::identify::reduce_logs(&robot.model, &p, opts) {
            Ok(Some(t)) => return Ok((Training::Streamed(t), None)),
            Ok(None) => {}
            Err(IdentifyError::Data(e)) => {
                return Err(super::super::explain_data(
                    e,
                    a.robot.robot.as_str(),
                    a.robot.sidecar.as_deref(),
                ));
            }
            Err(e) => return Err(explain(e)),
        }
    }
    let names = robot.model.joint_names();
    let p: Vec<&Path> = a.data.iter().map(|p| p.as_path()).collect();
    match momentlmi::identify::cutoff::read_training(&p, &names, opts, &robot.model) {
        Ok((r, c)) => Ok((Training::Whole(r), c)),
        Err(IdentifyError::Data(e)) => Err(super::super::explain_data(
            e,
            a.robot.robot.as_str(),
            a.robot.sidecar.as_deref(),
        )),
        Err(e) => Err(format!(
            "choosing the low-pass cut-off (give one with --cutoff-hz): {e}"
        )),
    }
}
