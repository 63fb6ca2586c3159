//! `momentlmi excite --robot R [--seconds T] [--criterion d|e|cond]
//! [--pool N] [--separate A,B] [--out traj.csv] [--json]`: a designed
//! excitation, or a motion that tells two effects apart.

use super::args::RobotArgs;
use momentlmi::data::{Staged, record_path, stage_with_record};
use momentlmi::effects::Library;
use momentlmi::excite::{Criterion, Designed, ExciteOptions, design, samples, separate};
use std::path::{Path, PathBuf};

/// `momentlmi excite`'s options, declared once: clap parses them and the
/// command reads them (the robot's sidecar resolved first,
/// [`RobotArgs::resolve`]).
#[derive(clap::Args, Debug, Clone)]
pub struct ExciteArgs {
    #[command(flatten)]
    pub robot: RobotArgs,
    /// Length (s): a whole number of periods.
    #[arg(long, default_value_t = 10.0, allow_hyphen_values = true)]
    pub seconds: f64,
    /// What is maximised: d (log det of the information), e (its smallest eigenvalue) or
    /// cond (minus the log of its condition number).
    #[arg(long, default_value = "d")]
    pub criterion: String,
    /// Harmonics per joint.
    #[arg(long, default_value_t = 5, allow_hyphen_values = true)]
    pub harmonics: usize,
    /// The wished base frequency (Hz), rounded so that --seconds holds whole periods.
    #[arg(long, default_value_t = 0.2, allow_hyphen_values = true)]
    pub base_hz: f64,
    /// Random seeds the search starts from.
    #[arg(long, default_value_t = 8, allow_hyphen_values = true)]
    pub seeds: usize,
    /// The first seed.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true)]
    pub seed: u64,
    /// Random candidate motions of the convex D- or E-optimal pool design (0: none).
    #[arg(long, default_value_t = 0, allow_hyphen_values = true)]
    pub pool: usize,
    /// Two effects A,B the diagnosis reported as tied: design the motion that tells them
    /// apart (the smaller share of one's predicted torques the other cannot fit, maximised)
    /// instead of an information criterion.
    #[arg(long, value_name = "A,B")]
    pub separate: Option<String>,
    /// Output CSV (t, q, qd, qdd per joint) and a JSON report beside it.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Sample rate of --out (Hz).
    #[arg(long, default_value_t = 1000.0, allow_hyphen_values = true)]
    pub rate: f64,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

impl ExciteArgs {
    /// The search's settings (the library's [`ExciteOptions`]).
    fn options(&self) -> ExciteOptions {
        ExciteOptions {
            seconds: self.seconds,
            harmonics: self.harmonics,
            base_hz: self.base_hz,
            seeds: self.seeds,
            seed: self.seed,
            pool: self.pool,
            ..Default::default()
        }
    }
}

/// Exit codes: 0 designed (and written), 2 bad input or failure.
pub fn run(a: &ExciteArgs) -> i32 {
    match run_inner(a) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

fn run_inner(a: &ExciteArgs) -> Result<(), String> {
    let criterion = Criterion::parse(a.criterion.as_str()).ok_or_else(|| {
        format!(
            "--criterion: '{}' is not one of d, e, cond",
            a.criterion.as_str()
        )
    })?;
    let library = Library::builtin();
    let pair = a
        .separate
        .as_deref()
        .map(|s| pair_of(s, &library))
        .transpose()?;
    if pair.is_some() && a.pool > 0 {
        return Err("--separate designs a motion by the separation of two effects; --pool bounds an information criterion: give one of them".into());
    }
    let mut staged = Staged::protecting(a.robot.inputs_with(&[], &[]));
    if let Some(out) = a.out.as_deref() {
        for p in [out, &record_path(out)] {
            staged.claim(p).map_err(|e| e.to_string())?;
        }
    }
    let robot = a.robot.load()?;
    super::warn_robot(&robot);
    let opts = ExciteOptions {
        criterion,
        ..a.options()
    };
    let d = match &pair {
        Some([x, y]) => separate(&robot, &library, [x, y], &opts),
        None => design(&robot, &opts),
    }
    .map_err(|e| e.to_string())?;
    if let Some(out) = a.out.as_deref() {
        let data = samples(&d, a.rate).map_err(|e| e.to_string())?;
        stage_with_record(&mut staged, &data, out, &d).map_err(|e| e.to_string())?;
        staged.commit().map_err(|e| e.to_string())?;
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&d).map_err(|e| e.to_string())?
        );
    } else {
        print_report(&d, a.out.as_deref());
    }
    warn_torques(&d);
    if let Some(s) = d.separation.as_ref().filter(|s| !s.separable) {
        eprintln!(
            "warning: no motion found separates {} and {}: one's columns lie within the other's (the data can never tell them apart; prefer the leaner)",
            s.effects[0], s.effects[1]
        );
    }
    Ok(())
}

/// What a separating motion gives, in one line.
fn separation_line(s: &momentlmi::excite::Separation) -> String {
    let [a, b] = &s.effects;
    let (x, y) = (s.first_not_fitted_by_second, s.second_not_fitted_by_first);
    let verdict = match (s.separable, x < y) {
        (true, _) => "separates them".to_string(),
        (false, true) => format!(
            "does not separate them: {a} lies within what {b} fits on every motion searched"
        ),
        (false, false) => format!(
            "does not separate them: {b} lies within what {a} fits on every motion searched"
        ),
    };
    format!(
        "{verdict}: {:.1} % of {a}'s predicted torques are beyond what {b} fits, {:.1} % of {b}'s beyond {a} (best random start {:.1} %)",
        100.0 * x,
        100.0 * y,
        100.0 * s.best_start
    )
}

/// The two effect names of `--separate A,B`, each one of `library`'s.
fn pair_of(s: &str, library: &Library) -> Result<[String; 2], String> {
    let names: Vec<&str> = s.split(',').map(str::trim).collect();
    let [x, y] = names[..] else {
        return Err(format!(
            "--separate '{s}': two effect names separated by a comma are needed (A,B)"
        ));
    };
    for name in [x, y] {
        library.get(name).map_err(|e| format!("--separate: {e}"))?;
    }
    if x == y {
        return Err(format!(
            "--separate '{s}': two different effects are needed"
        ));
    }
    Ok([x.to_string(), y.to_string()])
}

/// A warning per joint whose effort limit the motion passes.
fn warn_torques(d: &Designed) {
    for (l, m) in d.limits.iter().zip(&d.torque_margins) {
        if let Some(m) = m.filter(|m| *m < 0.0) {
            eprintln!(
                "warning: joint '{}' needs {:.0} % more torque than its effort limit {} along the motion (the description's model; checked, not enforced)",
                l.joint,
                -100.0 * m,
                l.effort.unwrap_or(f64::NAN)
            );
        }
    }
}

fn print_report(d: &Designed, out: Option<&Path>) {
    let hz = match &d.trajectory {
        momentlmi::sim::trajectory::Trajectory::Fourier { omega, .. } => {
            omega / (2.0 * std::f64::consts::PI)
        }
        _ => f64::NAN,
    };
    let what = match &d.separation {
        Some(sep) => separation_line(sep),
        None => format!(
            "{:?}-optimal on {} base parameters: value {:.4} (best random start {:.4})",
            d.options.criterion, d.base_parameters, d.value, d.best_seed_value
        ),
    };
    println!(
        "{}: {} s ({} periods of {:.4} Hz, {} harmonics), {what}, log det {:.4}, condition number {:.3e}",
        d.robot,
        d.options.seconds,
        (d.options.seconds * hz).round(),
        hz,
        d.options.harmonics,
        d.log_det,
        d.condition_number
    );
    println!("method: {}", d.method);
    println!(
        "{:<20} {:>22} {:>10} {:>10} {:>10}   margins: position, velocity, acceleration, torque",
        "joint", "position [lo, hi]", "|q̇| max", "|q̈| max", "|τ| max"
    );
    for ((l, m), t) in d.limits.iter().zip(&d.margins).zip(&d.torque_margins) {
        let effort = l
            .effort
            .map_or_else(|| "-".to_string(), |e| format!("{e:.1}"));
        let torque = t.map_or_else(|| "-".to_string(), |t| format!("{:.1} %", 100.0 * t));
        println!(
            "{:<20} [{:>9.4}, {:>9.4}] {:>10.4} {:>10.4} {:>10}   {:.1} %, {:.1} %, {:.1} %, {torque}",
            l.joint,
            l.position.0,
            l.position.1,
            l.velocity,
            l.acceleration,
            effort,
            100.0 * m[0],
            100.0 * m[1],
            100.0 * m[2]
        );
    }
    let from: Vec<String> = (d.limits.iter())
        .map(|l| {
            format!(
                "{}: velocity from the {}, acceleration from the {}",
                l.joint, l.velocity_from, l.acceleration_from
            )
        })
        .collect();
    println!("limits: {}", from.join("; "));
    if let Some(p) = &d.pool {
        println!(
            "convex pool design over {} candidates (the design among them): bound {:.4}, design {:.4}, efficiency {:.1} %",
            p.candidates,
            p.bound,
            p.designed,
            100.0 * p.efficiency
        );
    }
    if let Some(out) = out {
        println!("wrote {} and {}", out.display(), record_path(out).display());
    }
}
