//! The `momentlmi` command line: argument parsing and thin calls into the
//! library. Every command returns an exit code; errors are printed, never
//! panicked.

use crate::cmd::{check, demo, route, sdpa};
use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Physically consistent inertial parameter identification and SDP tools.
#[derive(Parser, Debug)]
#[command(name = "momentlmi", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the bundled demonstration.
    Demo {
        /// Folder for the demo's outputs.
        #[arg(long, default_value = "momentlmi-demo")]
        out: PathBuf,
    },
    /// Check the inertias of a URDF for physical consistency.
    ///
    /// Exit codes: 0 every inertial consistent (or a zero placeholder); 1 some
    /// are not (a negative mass included), no link has an inertial (nothing
    /// to check), or with --strict a link is degenerate; 2 an invalid file
    /// (unreadable, too large or deep, duplicate names, not one tree) or a
    /// refused or failed --repair. See docs/inputs.md.
    Check(crate::cmd::check::CheckArgs),
    /// Model joint torques for every sample of a data file (the "sim" side).
    Predict(crate::cmd::predict::PredictArgs),
    /// Simulate a robot with switchable unmodelled effects and write a data file.
    Simulate(crate::cmd::simulate::SimulateArgs),
    /// Design an exciting trajectory: a periodic Fourier series per joint within the joint
    /// limits, optimised for the base parameters' information (docs/identification.md).
    Excite(crate::cmd::excite::ExciteArgs),
    /// Identify link and rotor inertias and friction from data (the paper's SDP (25)).
    Identify(crate::cmd::identify::IdentifyArgs),
    /// Diagnose the gap between a nominal model and measured data: where it lies, which unmodelled
    /// effect explains it, how far it shrinks (docs/diagnosis.md).
    Diagnose(crate::cmd::diagnose::DiagnoseArgs),
    /// Write a model for a simulator: a copy of the robot's URDF with the parameters (and a
    /// sidecar beside it), and/or a MuJoCo model (docs/export.md).
    Export(crate::cmd::export::ExportArgs),
    /// Solve an SDPA sparse file (.dat-s) and print the result.
    Sdpa(crate::cmd::sdpa::SdpaArgs),
}

/// Parses `std::env::args` and runs the command; returns the exit code.
pub fn main() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return code;
        }
    };
    match cli.command {
        Command::Demo { out } => demo::run(&out),
        Command::Check(a) => check::run(&a),
        Command::Predict(mut a) => {
            a.robot.resolve();
            route::predict(&a)
        }
        Command::Simulate(mut a) => {
            a.robot.resolve();
            route::simulate(&a)
        }
        Command::Excite(mut a) => {
            a.robot.resolve();
            route::excite(&a)
        }
        Command::Identify(mut a) => {
            a.robot.resolve();
            route::identify(&a)
        }
        Command::Diagnose(mut a) => {
            a.robot.resolve();
            route::diagnose(&a)
        }
        Command::Export(mut a) => {
            a.robot.resolve();
            route::export(&a)
        }
        Command::Sdpa(a) => sdpa::run(&a),
    }
}
