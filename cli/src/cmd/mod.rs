//! One module per command; each `run` returns the process exit code (0
//! success, 1 a negative finding or an unsolved problem, 2 bad input).

pub mod check;
pub mod demo;
pub mod diagnose;
pub mod identify;
pub mod predict;
pub mod sdpa;
pub mod simulate;

/// Prints what the robot description filled in (placeholder friction, …).
pub(crate) fn warn_robot(robot: &momentlmi::dynamics::RobotDescription) {
    for w in &robot.warnings {
        eprintln!("warning: {}: {w}", robot.source);
    }
}
