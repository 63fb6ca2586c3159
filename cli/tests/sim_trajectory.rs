//! `simulate --trajectory FILE`: the arm's own multi-sine sampled at 200 Hz
//! for one period and given as a file gives the torques of simulating the
//! multi-sine itself; the record stays small; bad files exit 2 naming the
//! file.

use momentlmi::sim::trajectory::Trajectory;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_momentlmi"))
}

fn panda() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/panda/panda.urdf")
}

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("momentlmi-cli-traj-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The exact (q, q̇, q̈) of a Fourier trajectory at `t`.
fn exact(tr: &Trajectory, t: f64) -> [Vec<f64>; 3] {
    tr.exact_state(t).expect("a Fourier trajectory")
}

/// The arm's default excitation for seed 1 (what `simulate` drives it
/// along without --trajectory) and its period, `rows` samples of it at
/// 200 Hz from `t0` written to `name`.
fn write_excitation(name: &str, t0: f64, rows: usize) -> (PathBuf, f64) {
    let sidecar = panda().with_extension("toml");
    let robot =
        momentlmi::dynamics::robots::load_robot(panda().to_str().unwrap(), Some(&sidecar)).unwrap();
    let tr = Trajectory::for_excitation(&robot.excitation, &robot.model, 1);
    let Trajectory::Fourier { omega, .. } = &tr else {
        panic!("{tr:?}")
    };
    let period = 2.0 * std::f64::consts::PI / omega;
    let joints = robot.model.joint_names();
    let mut s = "t".to_string();
    for p in ["q", "qd", "qdd"] {
        for j in &joints {
            s += &format!(",{p}_{j}");
        }
    }
    s.push('\n');
    for k in 0..rows {
        let t = t0 + k as f64 / 200.0;
        s += &format!("{t}");
        for x in exact(&tr, t) {
            for v in x {
                s += &format!(",{v:e}");
            }
        }
        s.push('\n');
    }
    let p = dir().join(name);
    std::fs::write(&p, s).unwrap();
    (p, period)
}

fn simulate(extra: &[&str], out: &Path) -> Output {
    bin()
        .args(["simulate", "--robot", panda().to_str().unwrap()])
        .args(["--seconds", "6", "--noise", "0", "--effects", "viscous"])
        .args(["--out", out.to_str().unwrap()])
        .args(extra)
        .output()
        .unwrap()
}

/// The tau_ columns of a data CSV.
fn torques(p: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(p).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let cols: Vec<usize> = (0..header.len())
        .filter(|&c| header[c].starts_with("tau_"))
        .collect();
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            cols.iter().map(|&c| f[c].parse().unwrap()).collect()
        })
        .collect()
}

#[test]
fn a_sampled_period_gives_the_excitation_torques() {
    let (traj, period) = write_excitation("period.csv", 0.0, 1000);
    assert!((period - 5.0).abs() < 1e-12, "{period}");
    let (a, b) = (dir().join("direct.csv"), dir().join("sampled.csv"));
    let o = simulate(&[], &a);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = simulate(&["--trajectory", traj.to_str().unwrap()], &b);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let (want, got) = (torques(&a), torques(&b));
    assert_eq!(want.len(), 6000);
    assert_eq!(got.len(), want.len());
    let mut worst = 0.0f64;
    for (w, g) in want.iter().zip(&got) {
        for (x, y) in w.iter().zip(g) {
            worst = worst.max((x - y).abs());
        }
    }
    assert!(worst < 1e-5, "torques differ by {worst} N·m");
    // the record names the file, not its samples
    let json = std::fs::read_to_string(dir().join("sampled.json")).unwrap();
    let record: serde_json::Value = serde_json::from_str(&json).unwrap();
    let t = &record["config"]["trajectory"];
    assert_eq!(t["kind"], "sampled");
    assert_eq!(t["source"], traj.to_str().unwrap());
    assert_eq!(t["samples"], 1000);
    assert_eq!(t["wraps"], true);
    assert!((t["rate_hz"].as_f64().unwrap() - 200.0).abs() < 1e-6);
    assert_eq!(record["config"]["cutoff_hz"], 30.0);
    assert!(json.len() < 20_000, "{} bytes", json.len());
}

#[test]
fn bad_trajectories_exit_2_naming_the_file() {
    // 4 s, not periodic: 6 s and the edges do not fit
    let (short, _) = write_excitation("short.csv", 0.3, 801);
    let out = dir().join("never.csv");
    let o = simulate(&["--trajectory", short.to_str().unwrap()], &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--trajectory") && err.contains("short.csv"),
        "{err}"
    );
    assert!(
        err.contains("not periodic") && err.contains("spans"),
        "{err}"
    );
    assert!(!out.exists());
    // with --noise 0 the data are not processed: no edges, 4 s fit 3.5 s
    let o = bin()
        .args(["simulate", "--robot", panda().to_str().unwrap()])
        .args(["--seconds", "3.5", "--noise", "0"])
        .args(["--trajectory", short.to_str().unwrap()])
        .args(["--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // a joint the arm does not have
    let text = std::fs::read_to_string(&short).unwrap();
    let bad = dir().join("unknown.csv");
    std::fs::write(&bad, text.replacen("qd_panda_joint2", "qd_elbow", 1)).unwrap();
    let o = simulate(&["--trajectory", bad.to_str().unwrap()], &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("unknown.csv") && err.contains("'qd_elbow'"),
        "{err}"
    );
    // the trajectory file is an input: never the output
    let o = simulate(&["--trajectory", short.to_str().unwrap()], &short);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&short).unwrap(), text);
    // not a file
    let o = simulate(&["--trajectory", "/nonexistent/x.csv"], &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("x.csv"), "{err}");
}
