//! Which pipeline a command runs: a floating base (the `--floating-base`
//! flag, or the sidecar's `[floating_base]` table) goes to the
//! `floating_*` command, a fixed base to the command of its name. The
//! choice is made here, above both, so that neither command file needs
//! the other.

use super::floating::Robot;
use super::{diagnose, floating_diagnose, floating_identify, floating_predict, floating_simulate};
use super::{excite, export, identify, predict, simulate};

/// The robot a command names, as its floating-base test sees it.
fn robot<'a>(spec: &'a str, sidecar: Option<&'a std::path::Path>, flag: bool) -> Robot<'a> {
    Robot {
        spec,
        sidecar,
        flag,
    }
}

/// Exit code 2, the error printed.
fn failed(e: String) -> i32 {
    eprintln!("error: {e}");
    2
}

/// `momentlmi identify`; `--rows` only for a floating base.
pub fn identify(a: &identify::IdentifyArgs) -> i32 {
    let r = &a.robot;
    let robot = robot(&r.robot, r.sidecar.as_deref(), a.floating.floating_base);
    match robot.is_floating() {
        Ok(true) => floating_identify::run(a, robot),
        Ok(false) if a.rows.is_some() => {
            failed("--rows is for a floating base (--floating-base)".into())
        }
        Ok(false) => identify::run(a),
        Err(e) => failed(e),
    }
}

/// `momentlmi diagnose`.
pub fn diagnose(a: &diagnose::DiagnoseArgs) -> i32 {
    let r = &a.robot;
    let robot = robot(&r.robot, r.sidecar.as_deref(), a.floating.floating_base);
    match robot.is_floating() {
        Ok(true) => floating_diagnose::run(a, robot),
        Ok(false) => diagnose::run(a),
        Err(e) => failed(e),
    }
}

/// `momentlmi predict`.
pub fn predict(a: &predict::PredictArgs) -> i32 {
    let r = &a.robot;
    let robot = robot(&r.robot, r.sidecar.as_deref(), a.floating.floating_base);
    match robot.is_floating() {
        Ok(true) => match floating_predict::run(a, robot) {
            Ok(()) => 0,
            Err(e) => failed(e),
        },
        Ok(false) => predict::run(a),
        Err(e) => failed(e),
    }
}

/// `momentlmi simulate`.
pub fn simulate(a: &simulate::SimulateArgs) -> i32 {
    let r = &a.robot;
    let robot = robot(&r.robot, r.sidecar.as_deref(), a.floating.floating_base);
    match robot.is_floating() {
        Ok(true) => match floating_simulate::run(a, robot) {
            Ok(()) => 0,
            Err(e) => failed(e),
        },
        Ok(false) => simulate::run(a),
        Err(e) => failed(e),
    }
}

/// A command that has no floating-base form yet: a floating base (the
/// sidecar's `[floating_base]` table) is refused by name before anything
/// runs, rather than treated as fixed to the world.
fn fixed_only(command: &str, r: &super::args::RobotArgs) -> Result<(), String> {
    match robot(&r.robot, r.sidecar.as_deref(), false).is_floating()? {
        true => Err(format!(
            "{command} is not built for a floating base yet ('{}' has a [floating_base] table in its sidecar; docs/floating-base.md, \"Not yet built\"); it would weld the base to the world",
            r.robot
        )),
        false => Ok(()),
    }
}

/// `momentlmi export`: a floating base (the sidecar's `[floating_base]`
/// table) exported with a free-flying root.
pub fn export(a: &export::ExportArgs) -> i32 {
    match robot(&a.robot.robot, a.robot.sidecar.as_deref(), false).is_floating() {
        Ok(floating) => export::run(a, floating),
        Err(e) => failed(e),
    }
}

/// `momentlmi excite`: a fixed base only.
pub fn excite(a: &excite::ExciteArgs) -> i32 {
    match fixed_only("excite", &a.robot) {
        Ok(()) => excite::run(a),
        Err(e) => failed(e),
    }
}
