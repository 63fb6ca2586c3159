//! `momentlmi excite`: its file, read back, keeps every limit its report
//! states, and `simulate --trajectory` replays it; bad settings exit 2 with
//! the setting named and nothing written.

use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_momentlmi"))
}

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("momentlmi-cli-excite-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn the_written_file_keeps_the_limits_and_simulate_replays_it() {
    let d = dir();
    let out = d.join("ex.csv");
    let r = bin()
        .args([
            "excite",
            "--robot",
            "cheetah3-leg",
            "--seconds",
            "4",
            "--seeds",
            "2",
            "--rate",
            "500",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("ex.json")).unwrap()).unwrap();
    let limits = report["limits"].as_array().unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let mut rows = 0;
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        for (j, l) in limits.iter().enumerate() {
            let name = l["joint"].as_str().unwrap();
            let col = |p: &str| {
                header
                    .iter()
                    .position(|h| *h == format!("{p}_{name}"))
                    .unwrap()
            };
            let (lo, hi) = (
                l["position"][0].as_f64().unwrap(),
                l["position"][1].as_f64().unwrap(),
            );
            let q = v[col("q")];
            assert!(
                lo <= q && q <= hi,
                "row {rows} joint {j}: {q} outside [{lo}, {hi}]"
            );
            assert!(
                v[col("qd")].abs() <= l["velocity"].as_f64().unwrap(),
                "row {rows} joint {j}"
            );
            assert!(
                v[col("qdd")].abs() <= l["acceleration"].as_f64().unwrap(),
                "row {rows} joint {j}"
            );
        }
        rows += 1;
    }
    assert_eq!(rows, 2000);
    let sim = d.join("sim.csv");
    let r = bin()
        .args([
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--seconds",
            "6",
            "--trajectory",
        ])
        .arg(&out)
        .arg("--out")
        .arg(&sim)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(std::fs::read_to_string(&sim).unwrap().lines().count(), 6001);
}

#[test]
fn bad_settings_exit_2_naming_them() {
    let d = dir();
    let out = d.join("bad.csv");
    for (args, word) in [
        (vec!["--criterion", "x"], "--criterion"),
        (vec!["--seconds", "-1"], "seconds"),
        (vec!["--rate", "0"], "rate_hz"),
    ] {
        let r = bin()
            .args(["excite", "--robot", "cheetah3-leg", "--seeds", "1", "--out"])
            .arg(&out)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(word), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote a file");
    }
}

/// The route: `identify --friction none --json` on the Panda (the
/// sidecar locks the fingers) reports 43 base parameters of 70 columns, the
/// count a rank on random states gives (tests/identifiability.rs) and
/// Pinocchio's regressor gives too.
#[test]
fn the_panda_identified_by_the_command_reports_43_base_parameters() {
    let d = dir();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/panda");
    let (urdf, sidecar) = (root.join("panda.urdf"), root.join("panda.toml"));
    let data = d.join("panda3.csv");
    let sim = bin()
        .arg("simulate")
        .arg("--robot")
        .arg(&urdf)
        .arg("--sidecar")
        .arg(&sidecar)
        .args(["--seconds", "3", "--out"])
        .arg(&data)
        .output()
        .unwrap();
    assert!(
        sim.status.success(),
        "{}",
        String::from_utf8_lossy(&sim.stderr)
    );
    let r = bin()
        .arg("identify")
        .arg("--robot")
        .arg(&urdf)
        .arg("--sidecar")
        .arg(&sidecar)
        .arg("--data")
        .arg(&data)
        .args(["--friction", "none", "--json"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let id = &v["identifiability"];
    assert_eq!(
        (id["rank"].as_u64(), id["columns"].as_u64()),
        (Some(43), Some(70))
    );
    assert_eq!(id["base_parameters"].as_array().unwrap().len(), 43);
    // one summary line on stderr, not one per unexcited direction
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(
        err.lines()
            .filter(|l| l.contains("parameter directions"))
            .count(),
        1,
        "{err}"
    );
}

/// `--separate A,B` on the leg: the motion's report says how much of each
/// effect the other cannot fit; the search does not end below its best
/// random start; a payload lies within a change of the links' inertia on
/// every motion (the payload's columns are the last link's).
#[test]
fn separate_designs_a_motion_that_tells_two_effects_apart() {
    let run = |pair: &str| -> serde_json::Value {
        let o = bin()
            .args(["excite", "--robot", "cheetah3-leg", "--seconds", "2"])
            .args(["--seeds", "1", "--separate", pair, "--json"])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let r = run("viscous,time_delay");
    let s = &r["separation"];
    assert_eq!(s["effects"][0], "viscous");
    let (a, b) = (
        s["first_not_fitted_by_second"].as_f64().unwrap(),
        s["second_not_fitted_by_first"].as_f64().unwrap(),
    );
    assert!(s["separable"].as_bool().unwrap());
    assert!(a > 0.0 && a <= 1.0 && b > 0.0 && b <= 1.0, "{a} {b}");
    assert!((r["value"].as_f64().unwrap() - a.min(b)).abs() < 1e-12);
    assert!(a.min(b) >= s["best_start"].as_f64().unwrap());
    let r = run("payload,link_inertia");
    let s = &r["separation"];
    assert!(!s["separable"].as_bool().unwrap(), "{s}");
    assert!(s["first_not_fitted_by_second"].as_f64().unwrap() < 1e-6);
    assert!(s["second_not_fitted_by_first"].as_f64().unwrap() > 0.1);
}

/// `excite --separate PAIR` on the leg.
fn separate(pair: &str) -> Command {
    let mut c = bin();
    c.args(["excite", "--robot", "cheetah3-leg", "--separate", pair]);
    c
}

/// `--separate` with an unknown effect, one name, the same name twice, or
/// beside `--pool`: exit 2, the problem named, nothing written.
#[test]
fn separate_with_bad_names_is_refused_and_nothing_written() {
    let d = dir();
    for (i, (pair, needle)) in [
        ("viscous,nope", "nope"),
        ("viscous", "two effect names"),
        ("viscous,viscous", "two different effects"),
    ]
    .into_iter()
    .enumerate()
    {
        let out = d.join(format!("sep{i}.csv"));
        let o = separate(pair).arg("--out").arg(&out).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{pair}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{pair}: {err}");
        assert!(!out.exists() && !d.join(format!("sep{i}.json")).exists());
    }
    let o = separate("viscous,coulomb")
        .args(["--pool", "4"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--pool"));
}
