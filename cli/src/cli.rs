//! The `momentlmi` command line: argument parsing and thin calls into the
//! library. Every command returns an exit code; errors are printed, never
//! panicked.

use crate::args::{
    ExportOutArgs, FloatingArgs, ReadArgs, RobotArgs, effect_names, effect_param_help, own_sidecar,
};
use crate::cmd::{check, demo, diagnose, excite, export, predict, route, sdpa, simulate};
use clap::{Parser, Subcommand};
use momentlmi::moments::urdf_check::{RepairOptions, RepairTarget};
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
    Check {
        /// The URDF file.
        urdf: PathBuf,
        /// Print one JSON object with a `links` array.
        #[arg(long)]
        json: bool,
        /// Write a copy with every inconsistent inertial replaced by the nearest consistent one
        /// (never the input itself; nothing is written unless the copy checks clean).
        #[arg(long, value_name = "OUT.urdf")]
        repair: Option<PathBuf>,
        /// What --repair projects onto: `consistent` (the inconsistent inertials, inside their
        /// geometry where possible) or `geometry` (also every consistent inertial that is not
        /// density realizable in its link's bounding volume).
        #[arg(long, value_enum, default_value = "consistent", requires = "repair")]
        repair_to: RepairTarget,
        /// The repair's relative margin ε: 1e-6 lands next to the boundary (often a rod or a thin
        /// plate); 1e-3 keeps the thinnest direction at about 3 % of the link's length scale.
        #[arg(long, default_value_t = 1e-6, requires = "repair", value_name = "EPS")]
        repair_margin: f64,
        /// Bounding ellipsoids for links by name, from a sidecar's `[[body]] name, bounding`
        /// (link frame); they replace the ones of the link's shapes.
        #[arg(long, value_name = "SIDECAR.toml")]
        sidecar: Option<PathBuf>,
        /// Folder for one SVG per link: its shapes' points, bounding and covariance ellipsoids,
        /// CoM and four point masses, in three views.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// A folder where `package://NAME/…` meshes are found: a package itself or a folder of
        /// packages (repeatable; searched after the folders above the URDF, before ROS_PACKAGE_PATH);
        /// meshes outside the URDF's folder and these folders are not read.
        #[arg(long = "package-path", value_name = "DIR")]
        package_path: Vec<PathBuf>,
        /// Degenerate links (consistent, but J singular: a point mass, rod or thin plate) make
        /// the exit code 1 too.
        #[arg(long)]
        strict: bool,
    },
    /// Model joint torques for every sample of a data file (the "sim" side).
    Predict {
        #[command(flatten)]
        robot: RobotArgs,
        /// `true` (own parameters + nominal friction), `cad` (the description's
        /// prior), or a parameter file (the JSON `identify --json` prints);
        /// default: the model's own, no friction.
        #[arg(long)]
        params: Option<String>,
        /// Data file (CSV: t, q_<joint>[, qd_<joint>][, qdd_<joint>]; extra columns are
        /// ignored; or NumPy .npz/.npy, or a ROS 2 .mcap bag, docs/inputs.md); repeatable:
        /// each file is a segment, predicted in order into one output.
        #[arg(long, required = true)]
        data: Vec<PathBuf>,
        #[command(flatten)]
        read: ReadArgs,
        /// Output CSV: t, tau_<joint>…
        #[arg(long)]
        out: PathBuf,
        /// Print a JSON summary.
        #[arg(long)]
        json: bool,
        /// The torques of the model as its MuJoCo export holds it (`export --mjcf-out`): rotors
        /// as joint armature, no friction: what MuJoCo's inverse dynamics gives without
        /// passive and constraint forces.
        #[arg(long)]
        mujoco_view: bool,
        #[command(flatten)]
        floating: FloatingArgs,
    },
    /// Simulate a robot with switchable unmodelled effects and write a data file.
    Simulate {
        #[command(flatten)]
        robot: RobotArgs,
        /// Duration in seconds (1 kHz sampling; 200 Hz for a floating base).
        #[arg(long, default_value_t = 20.0)]
        seconds: f64,
        /// Drive the robot along the trajectory in FILE instead of its default excitation:
        /// a CSV with columns t, q_<joint>…, qd_<joint>…, qdd_<joint>… for every joint of the
        /// robot (s, rad, rad/s, rad/s²; m for prismatic joints), uniformly sampled,
        /// interpolated by quintic Hermite polynomials. If its last sample continues into its
        /// first one step later it is periodic and repeats (write one period, t = 0 … T − dt);
        /// otherwise it must span --seconds plus the 0.5 s edges simulated before and after
        /// the data (none with --noise 0), and the data start that far after its first sample
        /// (a delay or compliance effect needs a little more). The cut-off default becomes
        /// 30 Hz. Columns, units and tolerances: docs/inputs.md, "Trajectory files".
        #[arg(long, value_name = "FILE")]
        trajectory: Option<PathBuf>,
        /// Comma-separated effects the true robot has (`momentlmi::effects`).
        #[arg(long, value_parser = effect_names(), value_delimiter = ',')]
        effects: Vec<String>,
        /// Output CSV (a JSON record of how it was made is written beside it).
        #[arg(long)]
        out: PathBuf,
        /// Random seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Torque noise σ in N·m (default 0.3; a floating base's joint torques 0.02); 0 writes
        /// exact, unprocessed states (a floating base: every sensor exact).
        #[arg(long)]
        noise: Option<f64>,
        /// Cut-off (Hz) of the offline filter of q, q̇, q̈ (default: 30 Hz, or 10× the top
        /// frequency of a multi-sine excitation when lower, at least 5 Hz; 30 Hz with
        /// --trajectory).
        #[arg(long, value_name = "HZ")]
        cutoff: Option<f64>,
        /// Bits per turn of the link-side encoders of revolute joints without a rotor
        /// (default 19; joints with a rotor have 2^14 counts per motor turn).
        #[arg(long, value_name = "BITS")]
        link_encoder_bits: Option<f64>,
        /// Effect parameter override NAME=VALUE (repeatable), e.g. `stiffness=300`;
        /// the defaults come from the robot's description.
        #[arg(long = "effect-param", value_name = "NAME=VALUE", long_help = effect_param_help())]
        effect_param: Vec<String>,
        #[command(flatten)]
        floating: FloatingArgs,
        /// A floating base's contacts: suspended (a load cell at the base, the default) or
        /// standing (the sidecar's [floating_base] feet on force plates, in its stance).
        #[arg(long, value_enum)]
        contacts: Option<crate::cmd::floating::Contacts>,
        /// Effects a floating base's true robot has (comma-separated): joint_friction (0.01
        /// N·m·s/rad viscous, 0.05 N·m Coulomb per joint), wrench_offset (every contact's
        /// sensor off by [1, −0.5, 2] N, [0.05, 0.02, −0.03] N·m), payload (0.3 kg on the base
        /// at [0.05, 0, 0.03] m).
        #[arg(long, value_enum, value_delimiter = ',')]
        floating_effects: Vec<crate::cmd::floating::SimEffect>,
    },
    /// Design an exciting trajectory: a periodic Fourier series per joint within the joint
    /// limits, optimised for the base parameters' information (docs/identification.md).
    Excite {
        #[command(flatten)]
        robot: RobotArgs,
        /// Length (s): a whole number of periods.
        #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
        seconds: f64,
        /// What is maximised: d (log det of the information), e (its smallest eigenvalue) or
        /// cond (minus the log of its condition number).
        #[arg(long, default_value = "d")]
        criterion: String,
        /// Harmonics per joint.
        #[arg(long, default_value_t = 5)]
        harmonics: usize,
        /// The wished base frequency (Hz), rounded so that --seconds holds whole periods.
        #[arg(long, default_value_t = 0.2)]
        base_hz: f64,
        /// Random seeds the search starts from.
        #[arg(long, default_value_t = 8)]
        seeds: usize,
        /// The first seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Random candidate motions of the convex D- or E-optimal pool design (0: none).
        #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
        pool: usize,
        /// Two effects A,B the diagnosis reported as tied: design the motion that tells them
        /// apart (the smaller share of one's predicted torques the other cannot fit, maximised)
        /// instead of an information criterion.
        #[arg(long, value_name = "A,B")]
        separate: Option<String>,
        /// Output CSV (t, q, qd, qdd per joint) and a JSON report beside it.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Sample rate of --out (Hz).
        #[arg(long, default_value_t = 1000.0)]
        rate: f64,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Identify link and rotor inertias and friction from data (the paper's SDP (25)).
    Identify(crate::cmd::identify::IdentifyArgs),
    /// Diagnose the gap between a nominal model and measured data: where it lies, which unmodelled
    /// effect explains it, how far it shrinks (docs/diagnosis.md).
    Diagnose {
        #[command(flatten)]
        robot: RobotArgs,
        /// Measured data (a CSV, NumPy .npz/.npy or ROS 2 .mcap log); repeatable: each
        /// file is a segment that no filter, difference or spectrum crosses.
        #[arg(long, required = true)]
        data: Vec<PathBuf>,
        #[command(flatten)]
        read: ReadArgs,
        /// Nominal model: cad | true or a parameter file (e.g. from identify --json);
        /// default: the model's own parameters, no friction.
        #[arg(long)]
        nominal: Option<String>,
        /// The data the nominal model was identified on (read like --data; repeatable): its
        /// bodies are then refit with the friction law, on these data and the fitting part
        /// together, so that what these data could not determine is not named an effect
        /// (link_inertia and rotor_inertia are then not proposed) [default: the bodies are
        /// held as given].
        #[arg(long, value_name = "FILE")]
        nominal_data: Vec<PathBuf>,
        /// Two runs of one trajectory (read like --data) whose torque difference, once
        /// aligned by positions, is the noise floor: RMS(τ₁ − τ₂)/√2 per joint [default:
        /// the residual's first differences, a lower bound on low-pass filtered data].
        #[arg(long, num_args = 2, value_names = ["RUN1", "RUN2"])]
        repeats: Vec<PathBuf>,
        /// Print the JSON report.
        #[arg(long)]
        json: bool,
        /// Also write diagnosis.json into this folder (a floating base: floating_diagnosis.json).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write the diagnosis' model — the nominal with its friction law refit and the
        /// accepted effects, fitted on the fitting part — as a parameter file that predict,
        /// identify --prior and export take (predict with it gives the held-out error reported).
        #[arg(long, value_name = "FILE")]
        model_out: Option<PathBuf>,
        /// Blocks of time the data are cut in for cross-validation when they are one or two
        /// files (3 to 10 files: one fold each).
        #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(3..=50))]
        folds: u64,
        /// The memory the diagnosis may plan for (GiB): beyond it the compliance searches are skipped, or the diagnosis refused.
        #[arg(long, default_value_t = 8.0)]
        max_memory_gib: f64,
        #[command(flatten)]
        floating: FloatingArgs,
    },
    /// Write a model for a simulator: a copy of the robot's URDF with the parameters (and a
    /// sidecar beside it), and/or a MuJoCo model (docs/export.md).
    Export {
        #[command(flatten)]
        robot: RobotArgs,
        /// `true` (own parameters + nominal friction), `cad` (the description's prior), or a
        /// parameter file (the JSON `identify --json` prints); default: the model's own, no
        /// friction.
        #[arg(long)]
        params: Option<String>,
        #[command(flatten)]
        out: ExportOutArgs,
    },
    /// Solve an SDPA sparse file (.dat-s) and print the result.
    Sdpa {
        /// The .dat-s file.
        file: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
        /// Clarabel's chordal decomposition of sparse PSD blocks: `verified`
        /// checks the decomposed result against the original problem and
        /// solves again without it when the check fails (Clarabel 0.11 can end
        /// "solved" at a wrong optimum, e.g. SDPLIB control1), unless that
        /// undecomposed solve would exceed --max-memory-gib (then an error);
        /// `unchecked` returns the decomposed result as it is; `off` never
        /// decomposes.
        #[arg(long, value_enum, default_value_t = sdpa::DecompositionArg::Verified)]
        decomposition: sdpa::DecompositionArg,
        /// Use QDLDL instead of faer's supernodal LDLᵀ for the KKT systems.
        #[arg(long)]
        qdldl: bool,
        /// Print the solver's iteration log.
        #[arg(long)]
        verbose: bool,
        /// Refuse files whose reading or solve would need more than this
        /// many GiB by the reader's estimate (docs/inputs.md); a dense PSD
        /// block of side n needs about 14·n⁴ bytes, a sparse one decomposed
        /// that of its cliques.
        #[arg(long, value_name = "GIB", default_value_t = momentlmi::sdpa::DEFAULT_MAX_MEMORY_GIB)]
        max_memory_gib: f64,
    },
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
        Command::Check {
            urdf,
            json,
            repair,
            repair_to,
            repair_margin,
            sidecar,
            out,
            package_path,
            strict,
        } => check::run(
            &urdf,
            &check::CheckArgs {
                json,
                repair: repair.as_deref().map(|p| {
                    (
                        p,
                        RepairOptions {
                            target: repair_to,
                            margin: repair_margin,
                        },
                    )
                }),
                sidecar: sidecar.as_deref(),
                out: out.as_deref(),
                package_paths: &package_path,
                strict,
            },
        ),
        Command::Predict {
            robot:
                RobotArgs {
                    robot,
                    sidecar,
                    package_path,
                    no_sidecar,
                },
            params,
            data,
            read,
            out,
            json,
            mujoco_view,
            floating,
        } => route::predict(&predict::PredictArgs {
            floating_base: floating.floating_base,
            mujoco_view,
            read: read.choice(),
            robot: &robot,
            sidecar: own_sidecar(&robot, sidecar, no_sidecar).as_deref(),
            package_paths: &package_path,
            params: params.as_deref(),
            data: &data,
            out: &out,
            json,
        }),
        Command::Simulate {
            robot:
                RobotArgs {
                    robot,
                    sidecar,
                    package_path,
                    no_sidecar,
                },
            seconds,
            trajectory,
            effects,
            out,
            seed,
            noise,
            cutoff,
            link_encoder_bits,
            effect_param,
            floating,
            contacts,
            floating_effects,
        } => route::simulate(&simulate::SimulateArgs {
            floating_effects: &floating_effects,
            floating_base: floating.floating_base,
            contacts,
            robot: &robot,
            sidecar: own_sidecar(&robot, sidecar, no_sidecar).as_deref(),
            package_paths: &package_path,
            seconds,
            trajectory: trajectory.as_deref(),
            effects: &effects,
            effect_params: &effect_param,
            out: &out,
            seed,
            noise,
            cutoff,
            link_encoder_bits,
        }),
        Command::Excite {
            robot:
                RobotArgs {
                    robot,
                    sidecar,
                    package_path,
                    no_sidecar,
                },
            seconds,
            criterion,
            harmonics,
            base_hz,
            seeds,
            seed,
            pool,
            separate,
            out,
            rate,
            json,
        } => excite::run(&excite::ExciteArgs {
            robot: &robot,
            sidecar: own_sidecar(&robot, sidecar, no_sidecar).as_deref(),
            package_paths: &package_path,
            options: momentlmi::excite::ExciteOptions {
                seconds,
                harmonics,
                base_hz,
                seeds,
                seed,
                pool,
                ..Default::default()
            },
            criterion: &criterion,
            separate: separate.as_deref(),
            out: out.as_deref(),
            rate_hz: rate,
            json,
        }),
        Command::Identify(mut a) => {
            a.robot.resolve();
            route::identify(&a)
        }
        Command::Diagnose {
            robot:
                RobotArgs {
                    robot,
                    sidecar,
                    package_path,
                    no_sidecar,
                },
            data,
            read,
            nominal,
            nominal_data,
            repeats,
            json,
            out,
            model_out,
            folds,
            max_memory_gib,
            floating,
        } => route::diagnose(&diagnose::DiagnoseArgs {
            nominal_data: &nominal_data,
            model_out: model_out.as_deref(),
            folds: folds as usize,
            floating_base: floating.floating_base,
            read: read.choice(),
            robot: &robot,
            sidecar: own_sidecar(&robot, sidecar, no_sidecar).as_deref(),
            package_paths: &package_path,
            data: &data,
            nominal: nominal.as_deref(),
            repeats: &repeats,
            json,
            out: out.as_deref(),
            max_memory_gib,
        }),
        Command::Export {
            robot:
                RobotArgs {
                    robot,
                    sidecar,
                    package_path,
                    no_sidecar,
                },
            params,
            out,
        } => export::run(&export::ExportArgs {
            robot: &robot,
            sidecar: own_sidecar(&robot, sidecar, no_sidecar).as_deref(),
            package_paths: &package_path,
            params: params.as_deref(),
            out: out.outputs(),
        }),
        Command::Sdpa {
            file,
            json,
            decomposition,
            qdldl,
            verbose,
            max_memory_gib,
        } => sdpa::run(&sdpa::SdpaArgs {
            file: &file,
            json,
            decomposition,
            qdldl,
            verbose,
            max_memory_gib,
        }),
    }
}
