//! Sampled trajectories (`sim::sampled`): a multi-sine sampled at 200 Hz,
//! written as a trajectory file and read back, is the multi-sine between
//! samples and across the wrap; simulating it gives the multi-sine's
//! torques; bad files are named errors.

use momentlmi::data::DataError;
use momentlmi::dynamics::cheetah3;
use momentlmi::effects::Library;
use momentlmi::sim::trajectory::Trajectory;
use momentlmi::sim::{
    Effects, SampledTrajectory, SimConfig, SimError, TrajectoryProblem, simulate_with,
};
use std::path::{Path, PathBuf};

const RATE: f64 = 200.0;

/// The exact (q, q̇, q̈) of a Fourier trajectory at `t`.
fn exact(tr: &Trajectory, t: f64) -> [Vec<f64>; 3] {
    tr.exact_state(t).expect("a Fourier trajectory")
}

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("momentlmi-traj-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `rows` samples of `tr` at 200 Hz from `t0` as a trajectory file's
/// text: columns q̈, q, q̇ with the joints in reverse order (any order is
/// read), then a column the reader ignores.
fn csv_text(tr: &Trajectory, joints: &[&str], t0: f64, rows: usize) -> String {
    let mut cols = vec!["t".to_string()];
    for p in ["qdd", "q", "qd"] {
        for j in joints.iter().rev() {
            cols.push(format!("{p}_{j}"));
        }
    }
    cols.push("note".into());
    let mut s = cols.join(",") + "\n";
    for k in 0..rows {
        let t = t0 + k as f64 / RATE;
        let x = exact(tr, t);
        s += &format!("{t}");
        for i in [2, 0, 1] {
            for j in (0..joints.len()).rev() {
                s += &format!(",{:e}", x[i][j]);
            }
        }
        s += ",0\n";
    }
    s
}

fn write(name: &str, text: &str) -> PathBuf {
    let p = dir().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn leg_fourier() -> (Trajectory, f64) {
    let tr = Trajectory::fourier_for(&cheetah3::model(), 2);
    let Trajectory::Fourier { omega, .. } = &tr else {
        unreachable!()
    };
    let period = 2.0 * std::f64::consts::PI / omega;
    (tr, period)
}

fn leg_joints() -> Vec<String> {
    cheetah3::model()
        .joint_names()
        .iter()
        .map(|s| s.to_string())
        .collect()
}

fn read(p: &Path) -> Result<SampledTrajectory, SimError> {
    let names = leg_joints();
    let joints: Vec<&str> = names.iter().map(String::as_str).collect();
    SampledTrajectory::read(p, &joints)
}

/// One period sampled at 200 Hz (1000 rows of a 5 s period), written as
/// `name`.
fn one_period(name: &str) -> (Trajectory, f64, PathBuf) {
    let (tr, period) = leg_fourier();
    let rows = (period * RATE).round() as usize;
    let names = leg_joints();
    let joints: Vec<&str> = names.iter().map(String::as_str).collect();
    let p = write(name, &csv_text(&tr, &joints, 0.0, rows));
    (tr, period, p)
}

/// The largest error of the interpolated state against the exact one at
/// `times`, per quantity.
fn worst(s: &SampledTrajectory, tr: &Trajectory, times: &[f64], shift: f64) -> [f64; 3] {
    let mut e = [0.0f64; 3];
    for &t in times {
        let (q, qd, qdd) = s.state(t).unwrap_or_else(|| panic!("no state at {t}"));
        let x = exact(tr, t + shift);
        for (i, got) in [q, qd, qdd].iter().enumerate() {
            for j in 0..got.len() {
                e[i] = e[i].max((got[j] - x[i][j]).abs());
            }
        }
    }
    e
}

#[test]
fn one_period_is_the_multisine_between_samples_and_across_the_wrap() {
    let (tr, period, p) = one_period("period.csv");
    let s = read(&p).unwrap();
    assert!(s.wraps, "one period is periodic");
    assert_eq!(s.samples, 1000);
    assert!((s.rate_hz - RATE).abs() < 1e-6, "{}", s.rate_hz);
    assert_eq!(s.joints(), 3);
    let h = 1.0 / RATE;
    // between samples, at awkward fractions of a step
    let inside: Vec<f64> = (0..997)
        .step_by(7)
        .map(|k| (k as f64 + 0.137 + 0.7 * (k % 3) as f64 / 3.0) * h)
        .collect();
    // across the wrap: the last interval (last sample → first one period
    // on), later periods and before the first sample
    let wrap: Vec<f64> = [
        period - 0.5 * h,
        period - 0.01 * h,
        period + 0.3 * h,
        2.0 * period + 0.123,
        7.0 * period - 0.37 * h,
        -0.25 * h,
        -1.7,
    ]
    .to_vec();
    for times in [inside, wrap] {
        let e = worst(&s, &tr, &times, 0.0);
        // (measured: 7e-15, 5e-12, 6e-9)
        assert!(e[0] < 1e-12, "q error {e:?}");
        assert!(e[1] < 1e-9, "q̇ error {e:?}");
        assert!(e[2] < 1e-6, "q̈ error {e:?}");
    }
    // at the samples themselves: exact
    let e = worst(&s, &tr, &[0.0, 10.0 * h, 999.0 * h], 0.0);
    assert!(e.iter().all(|x| *x < 1e-12), "{e:?}");
    // q̇ and q̈ are the interpolant's derivatives: central differences of q
    let d = 1e-5;
    for t in [0.3 * h, period - 0.4 * h] {
        let (ahead, behind, now) = (
            s.state(t + d).unwrap(),
            s.state(t - d).unwrap(),
            s.state(t).unwrap(),
        );
        for (i, (x, dx)) in [(&ahead.0, &now.1), (&ahead.1, &now.2)]
            .into_iter()
            .enumerate()
        {
            let back = if i == 0 { &behind.0 } else { &behind.1 };
            for ((a, b), want) in x.iter().zip(back).zip(dx) {
                let fd = (a - b) / (2.0 * d);
                assert!(
                    (fd - want).abs() < 1e-5 * (1.0 + want.abs()),
                    "{fd} vs {want}"
                );
            }
        }
    }
}

#[test]
fn a_period_written_with_both_ends_wraps_without_the_repeat() {
    let (tr, period) = leg_fourier();
    let names = leg_joints();
    let joints: Vec<&str> = names.iter().map(String::as_str).collect();
    let p = write("inclusive.csv", &csv_text(&tr, &joints, 0.0, 1001));
    let s = read(&p).unwrap();
    assert!(s.wraps);
    assert_eq!(s.samples, 1000);
    let e = worst(&s, &tr, &[period - 0.3 / RATE, period + 0.2, -0.4], 0.0);
    assert!(e[0] < 1e-12 && e[2] < 1e-6, "{e:?}");
    // one more sample is not a period
    let p = write("longer.csv", &csv_text(&tr, &joints, 0.0, 1002));
    assert!(!read(&p).unwrap().wraps);
}

#[test]
fn part_of_a_period_does_not_wrap_and_ends_at_its_last_sample() {
    let (tr, _) = leg_fourier();
    let names = leg_joints();
    let joints: Vec<&str> = names.iter().map(String::as_str).collect();
    // 2.5 s from t = 1 s
    let p = write("part.csv", &csv_text(&tr, &joints, 1.0, 501));
    let s = read(&p).unwrap();
    assert!(!s.wraps);
    assert!((s.span_s() - 2.5).abs() < 1e-9);
    let e = worst(&s, &tr, &[0.0, 0.01234, 1.3, 2.5], 1.0);
    assert!(e[0] < 1e-12 && e[2] < 1e-6, "{e:?}");
    assert!(s.state(2.5 + 1e-3).is_none() && s.state(-1e-3).is_none());
}

/// The leg with `effects`, noise-free and unprocessed, along `tr`.
fn simulate_leg(tr: Trajectory, seconds: f64, effects: &str) -> momentlmi::data::Dataset {
    let leg = cheetah3::description();
    let fx = Effects::parse(effects, &[]).unwrap();
    let mut cfg = SimConfig::for_robot(&leg, seconds, fx, 1).with_trajectory(tr);
    cfg.noise_sigma = 0.0;
    cfg.encoder_counts = 0.0;
    cfg.processed = false;
    let truth = Library::builtin().true_robot(&leg, &cfg.effects).unwrap();
    simulate_with(&leg, &truth, &cfg, |_, _| {}).unwrap()
}

#[test]
fn simulating_the_file_gives_the_multisine_torques() {
    let (tr, period, p) = one_period("period_sim.csv");
    let sampled = Trajectory::Sampled(read(&p).unwrap());
    // longer than a period: the simulation wraps; a delay reads before t = 0
    let seconds = period + 1.5;
    for effects in ["viscous,rotor_inertia", "time_delay"] {
        let want = simulate_leg(tr.clone(), seconds, effects);
        let got = simulate_leg(sampled.clone(), seconds, effects);
        assert_eq!(got.len(), want.len());
        let mut worst = 0.0f64;
        for k in 0..want.len() {
            for j in 0..3 {
                worst = worst.max((got.tau[k][j] - want.tau[k][j]).abs());
                assert!((got.q[k][j] - want.q[k][j]).abs() < 1e-9);
            }
        }
        // (measured: 2e-7 N·m, the multi-sine's own finite differences)
        assert!(worst < 1e-5, "{effects}: torques differ by {worst} N·m");
        let scale = want
            .tau
            .as_flat()
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(scale > 1.0, "the torques are not trivially zero: {scale}");
    }
}

#[test]
fn a_non_periodic_file_starts_after_the_edge_and_must_be_long_enough() {
    let (tr, _) = leg_fourier();
    let names = leg_joints();
    let joints: Vec<&str> = names.iter().map(String::as_str).collect();
    let p = write("short.csv", &csv_text(&tr, &joints, 1.0, 501)); // 2.5 s
    let s = read(&p).unwrap();
    let leg = cheetah3::description();
    let cfg = |seconds: f64| {
        let mut c = SimConfig::for_robot(&leg, seconds, Effects::default(), 1)
            .with_trajectory(Trajectory::Sampled(s.clone()));
        (c.noise_sigma, c.encoder_counts) = (0.0, 0.0);
        c
    };
    assert_eq!(cfg(1.0).cutoff_hz, 30.0);
    // 2 s of data and 0.5 s edges need 3 s
    match cfg(2.0).validate(&leg.model) {
        Err(
            e @ SimError::TrajectoryFile {
                problem: TrajectoryProblem::TooShort { .. },
                ..
            },
        ) => {
            let m = e.to_string();
            assert!(m.contains("short.csv") && m.contains("2.5 s"), "{m}");
            assert!(m.contains("needs 2.999 s"), "{m}");
        }
        other => panic!("{other:?}"),
    }
    // 1.4 s fit; the data start 0.5 s after the file's first sample (t = 1.5)
    let c = cfg(1.4);
    let truth = Library::builtin().true_robot(&leg, &c.effects).unwrap();
    let d = simulate_with(&leg, &truth, &c, |_, _| {}).unwrap();
    let x = exact(&tr, 1.5 + 0.7);
    for (got, want) in d.q[700].iter().zip(&x[0]) {
        assert!((got - want).abs() < 1e-3, "{got} vs {want}");
    }
    // a delay needs more before the data: refused by the simulation
    let mut c = cfg(1.5); // 2.499 s without the delay, 2.504 s with its 5 ms
    c.effects = Effects::parse("time_delay", &[]).unwrap();
    let truth = Library::builtin().true_robot(&leg, &c.effects).unwrap();
    assert!(c.validate(&leg.model).is_ok());
    assert!(matches!(
        simulate_with(&leg, &truth, &c, |_, _| {}),
        Err(SimError::TrajectoryFile {
            problem: TrajectoryProblem::TooShort { .. },
            ..
        })
    ));
}

/// The one-period file's text with `edit` applied to its lines.
fn edited(name: &str, edit: impl Fn(Vec<String>) -> Vec<String>) -> PathBuf {
    let (_, _, p) = one_period(&format!("from_{name}"));
    let text = std::fs::read_to_string(p).unwrap();
    let lines = edit(text.lines().map(str::to_string).collect());
    write(name, &(lines.join("\n") + "\n"))
}

/// The lines without column `col`.
fn drop_column(lines: Vec<String>, col: &str) -> Vec<String> {
    let c = lines[0].split(',').position(|h| h == col).unwrap();
    lines
        .into_iter()
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f.remove(c);
            f.join(",")
        })
        .collect()
}

#[test]
fn bad_files_are_named_errors() {
    // a time stamp off the grid: its row named
    let p = edited("jitter.csv", |mut l| {
        let f: Vec<String> = l[101].split(',').map(str::to_string).collect();
        let t: f64 = f[0].parse().unwrap();
        l[101] = [format!("{}", t + 0.3 / RATE)]
            .into_iter()
            .chain(f[1..].iter().cloned())
            .collect::<Vec<_>>()
            .join(",");
        l
    });
    let e = read(&p).unwrap_err();
    assert!(
        matches!(
            e,
            SimError::TrajectoryFile {
                problem: TrajectoryProblem::NotUniform { row: 101, .. },
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("jitter.csv") && e.to_string().contains("row 101"));
    // a step twice as long (a dropped row): the row after it
    let p = edited("gap.csv", |mut l| {
        l.remove(400);
        l
    });
    assert!(
        matches!(
            read(&p),
            Err(SimError::TrajectoryFile {
                problem: TrajectoryProblem::NotUniform { row: 400, .. },
                ..
            })
        ),
        "{:?}",
        read(&p)
    );
    // one joint without its q̈ column
    let p = edited("noqdd.csv", |l| drop_column(l, "qdd_knee"));
    match read(&p) {
        Err(SimError::Data(DataError::MissingColumn { column, .. })) => {
            assert_eq!(column, "qdd_knee")
        }
        other => panic!("{other:?}"),
    }
    // no q̈ at all
    let p = edited("noacc.csv", |l| {
        ["qdd_abad", "qdd_hip", "qdd_knee"]
            .iter()
            .fold(l, |l, c| drop_column(l, c))
    });
    assert!(matches!(
        read(&p),
        Err(SimError::TrajectoryFile {
            problem: TrajectoryProblem::NoAccelerations,
            ..
        })
    ));
    // a joint the robot does not have
    let p = edited("unknown.csv", |mut l| {
        l[0] = l[0].replacen("qd_knee", "qd_elbow", 1);
        l
    });
    match read(&p) {
        Err(
            e @ SimError::TrajectoryFile {
                problem: TrajectoryProblem::UnknownJoint { .. },
                ..
            },
        ) => assert!(e.to_string().contains("'qd_elbow'"), "{e}"),
        other => panic!("{other:?}"),
    }
    // a joint missing altogether
    let p = edited("missing.csv", |l| {
        ["q_hip", "qd_hip", "qdd_hip"]
            .iter()
            .fold(l, |l, c| drop_column(l, c))
    });
    match read(&p) {
        Err(SimError::Data(DataError::MissingColumn { column, .. })) => {
            assert_eq!(column, "q_hip")
        }
        other => panic!("{other:?}"),
    }
}

/// One period at `rate` Hz with 9 significant digits, the last row's first
/// joint's q moved by `jump` rad.
fn rounded_period(rate: f64, jump: f64) -> String {
    let (tr, period) = leg_fourier();
    let names = leg_joints();
    let rows = (period * rate).round() as usize;
    let mut s = String::from("t");
    for p in ["q", "qd", "qdd"] {
        for j in &names {
            s += &format!(",{p}_{j}");
        }
    }
    s += "\n";
    for k in 0..rows {
        let t = k as f64 / rate;
        let mut x = exact(&tr, t);
        if k + 1 == rows {
            x[0][0] += jump;
        }
        s += &format!("{t}");
        for q in &x {
            for v in q {
                s += &format!(",{v:.8e}");
            }
        }
        s += "\n";
    }
    s
}

#[test]
fn rounding_in_the_digits_wraps_and_a_jump_does_not() {
    // 9 digits at 1 kHz: the extrapolated q̈ was off by ~0.4 rad/s² and the
    // file was called not periodic
    let p = write("rounded.csv", &rounded_period(1000.0, 0.0));
    assert!(
        read(&p).unwrap().wraps,
        "a period written with 9 digits does not wrap"
    );
    // a last sample 2.5 mrad off (0.8 % of the range): the wrap would carry
    // a q̈ of ~1.5e4 rad/s²
    let p = write("jump.csv", &rounded_period(1000.0, 2.5e-3));
    assert!(!read(&p).unwrap().wraps, "a jump of 2.5 mrad wraps");
}
