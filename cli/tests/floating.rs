//! `--floating-base` end to end on Solo12 (robots/solo12, whose sidecar
//! has a `[floating_base]` table): simulate suspended and standing,
//! identify from the base rows alone, predict with the identified model,
//! and bad floating-base input named with exit 2 and nothing written.

mod common;
use common::{TempDir, bin, ok};
use std::path::{Path, PathBuf};

fn solo() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    root.join("robots/solo12/solo12.urdf").display().to_string()
}

fn simulate(dir: &TempDir, name: &str, extra: &[&str]) -> PathBuf {
    let out = dir.0.join(name);
    let robot = solo();
    let mut args = vec![
        "simulate",
        "--robot",
        &robot,
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    ok(&args);
    out
}

/// A JSON number at a path of keys.
fn num(v: &serde_json::Value, keys: &[&str]) -> f64 {
    keys.iter().fold(v, |v, k| &v[*k]).as_f64().unwrap()
}

#[test]
fn base_rows_alone_identify_solo_and_predict_at_the_floor() {
    let dir = TempDir::new("floating-cli");
    // two minutes: the base moment (floor ≈ 0.011 N·m) needs them (40 s: 22 % above)
    let train = simulate(&dir, "train.csv", &["--seconds", "120", "--seed", "1"]);
    let test = simulate(&dir, "test.csv", &["--seconds", "10", "--seed", "2"]);
    let robot = solo();
    let (train, test) = (train.to_str().unwrap(), test.to_str().unwrap());
    let out = ok(&[
        "identify",
        "--robot",
        &robot,
        "--data",
        train,
        "--validate",
        test,
        "--rows",
        "base",
        "--json",
    ]);
    let fit: serde_json::Value = serde_json::from_slice(&out).unwrap();
    assert_eq!(fit["rows"], "base");
    // the whole robot as the URDF has it: 2.5 kg (its links' masses summed)
    let mass = num(&fit, &["whole_body", "mass"]);
    assert!((mass - 2.5).abs() < 0.01 * 2.5, "mass {mass}");
    for e in fit["min_eigenvalues"].as_array().unwrap() {
        assert!(
            e.as_f64().unwrap() >= -1e-9,
            "a body is not consistent: {e}"
        );
    }
    // held-out base wrench at the floor: the URDF's own model's residual
    let fitted = dir.0.join("fit.json");
    std::fs::write(&fitted, &out).unwrap();
    let predict = |params: Option<&Path>, name: &str| -> serde_json::Value {
        let pred = dir.0.join(name);
        let mut args = vec![
            "predict",
            "--robot",
            &robot,
            "--data",
            test,
            "--out",
            pred.to_str().unwrap(),
            "--json",
        ];
        if let Some(p) = params {
            args.extend(["--params", p.to_str().unwrap()]);
        }
        serde_json::from_slice(&ok(&args)).unwrap()
    };
    let (fit_rms, floor) = (
        predict(Some(&fitted), "pred.csv"),
        predict(None, "floor.csv"),
    );
    for key in ["base_force", "base_moment"] {
        let (a, b) = (num(&fit_rms, &["rms", key]), num(&floor, &["rms", key]));
        assert!(a <= 1.1 * b, "{key}: held-out {a} vs floor {b}");
        assert_eq!(num(&fit["validation_rms"], &[key]), a);
    }
    let text = std::fs::read_to_string(dir.0.join("pred.csv")).unwrap();
    assert!(text.starts_with("t,base_force_x,"), "{}", &text[..80]);
    assert_eq!(text.lines().count(), 1 + 2000);
}

#[test]
fn standing_on_force_plates_writes_one_contact_per_foot() {
    let dir = TempDir::new("floating-standing");
    let log = simulate(
        &dir,
        "stand.csv",
        &["--contacts", "standing", "--seconds", "2"],
    );
    let text = std::fs::read_to_string(&log).unwrap();
    let header = text.lines().next().unwrap();
    for foot in ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"] {
        assert!(
            header.contains(&format!("world_force_{foot}_z")),
            "{header}"
        );
    }
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.0.join("stand.json")).unwrap()).unwrap();
    assert_eq!(record["contacts"], "standing");
    assert_eq!(record["samples"], 400);
}

/// Runs `args`; asserts exit 2 and that stderr contains each of `words`.
fn refused(args: &[&str], words: &[&str]) {
    let o = bin().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{}: {err}", args.join(" "));
    for w in words {
        assert!(err.contains(w), "{}: {err} lacks {w}", args.join(" "));
    }
}

/// A one-second log's text and header, in `dir`.
fn short_log(dir: &TempDir) -> (PathBuf, String, Vec<String>) {
    let log = simulate(dir, "log.csv", &["--seconds", "1"]);
    let text = std::fs::read_to_string(&log).unwrap();
    let header = text
        .lines()
        .next()
        .unwrap()
        .split(',')
        .map(String::from)
        .collect();
    (log, text, header)
}

/// The log without the columns `drop` says.
fn without(text: &str, header: &[String], drop: impl Fn(&str) -> bool) -> String {
    let keep: Vec<usize> = (0..header.len()).filter(|&i| !drop(&header[i])).collect();
    let rows = text.lines().map(|l| {
        let cells: Vec<&str> = l.split(',').collect();
        keep.iter().map(|&i| cells[i]).collect::<Vec<_>>().join(",")
    });
    rows.collect::<Vec<_>>().join("\n")
}

#[test]
fn bad_floating_base_logs_are_named() {
    let dir = TempDir::new("floating-bad-logs");
    let (_, text, header) = short_log(&dir);
    let robot = solo();
    let identify = |name: &str, body: String, words: &[&str]| {
        let p = dir.write(name, &body);
        refused(
            &["identify", "--robot", &robot, "--data", p.to_str().unwrap()],
            words,
        );
    };
    // sample 3's quaternion w (the file's data row 4)
    let qw = header.iter().position(|c| c == "base_qw").unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut cells: Vec<String> = lines[4].split(',').map(String::from).collect();
    cells[qw] = "0.5".into();
    lines[4] = cells.join(",");
    identify(
        "quat.csv",
        lines.join("\n"),
        &["sample 3 (data row 4)", "quaternion", "norm"],
    );
    let renamed = text.replace("force_base_link", "force_harness");
    identify("frame.csv", renamed, &["contact frame 'harness'"]);
    let cut = without(&text, &header, |c| c == "force_base_link_z");
    identify("cut.csv", cut, &["missing column 'force_base_link_z'"]);
    let first = text.lines().next().unwrap().to_string();
    identify("header.csv", first, &["header.csv", "no samples"]);
    let free = without(&text, &header, |c| c.contains("_base_link_"));
    identify("free.csv", free, &["free.csv", "no contact wrench"]);
    // joint rows from a log without torques
    let p = dir.write(
        "notau.csv",
        &without(&text, &header, |c| c.starts_with("tau_")),
    );
    let p = p.to_str().unwrap();
    refused(
        &[
            "identify", "--robot", &robot, "--data", p, "--rows", "joints",
        ],
        &["--rows joints", "no joint torques"],
    );
    // the robot loaded with a fixed base (no sidecar): the base's motion
    // would be lost, so the log is refused by its first base column
    let (log, out) = (dir.0.join("log.csv"), dir.0.join("p.csv"));
    let predict = [
        "predict",
        "--params",
        "true",
        "--out",
        out.to_str().unwrap(),
    ];
    for cmd in [&["identify"][..], &predict[..]] {
        let mut args = cmd.to_vec();
        args.extend([
            "--robot",
            &robot,
            "--no-sidecar",
            "--data",
            log.to_str().unwrap(),
        ]);
        refused(&args, &["column 'base_x'", "free-flying root"]);
    }
    assert!(!out.exists());
}

#[test]
fn options_a_floating_base_cannot_take_are_named() {
    let dir = TempDir::new("floating-bad-options");
    let (log, _, _) = short_log(&dir);
    let (robot, log) = (solo(), log.to_str().unwrap().to_string());
    let out = dir.0.join("out.csv");
    let out = out.to_str().unwrap();
    refused(
        &[
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--floating-base",
            "--out",
            out,
        ],
        &["needs a URDF"],
    );
    let standing = [
        "--no-sidecar",
        "--floating-base",
        "--contacts",
        "standing",
        "--out",
        out,
    ];
    refused(
        &[&["simulate", "--robot", &robot][..], &standing].concat(),
        &["[floating_base] feet"],
    );
    refused(
        &[
            "simulate",
            "--robot",
            &robot,
            "--seconds",
            "1e6",
            "--out",
            out,
        ],
        &["--seconds", "GiB"],
    );
    refused(
        &[
            "identify",
            "--robot",
            "cheetah3-leg",
            "--data",
            &log,
            "--rows",
            "base",
        ],
        &["--rows is for a floating base"],
    );
    refused(
        &["identify", "--robot", &robot, "--data", &log, "--bounds"],
        &["--bounds", "not available with --floating-base"],
    );
    refused(
        &[
            "identify",
            "--robot",
            &robot,
            "--data",
            &log,
            "--velocity",
            "file",
        ],
        &["--velocity file"],
    );
    refused(
        &["predict", "--robot", &robot, "--data", &log, "--out", &log],
        &["log.csv"],
    );
    refused(
        &[
            "diagnose",
            "--robot",
            &robot,
            "--data",
            &log,
            "--nominal-data",
            &log,
        ],
        &["--nominal-data", "not available with --floating-base"],
    );
    let sim_npz = dir.0.join("sim.npz");
    refused(
        &[
            "simulate",
            "--robot",
            &robot,
            "--out",
            sim_npz.to_str().unwrap(),
        ],
        &["sim.npz", "written as CSV"],
    );
    assert!(!sim_npz.exists());
    let npz = dir.write("run.npz", "PK");
    let npz = npz.to_str().unwrap();
    refused(
        &["identify", "--robot", &robot, "--data", npz],
        &["run.npz", "not a NumPy .npz archive"],
    );
    let npy = dir.write("run.npy", "x");
    refused(
        &[
            "identify",
            "--robot",
            &robot,
            "--data",
            npy.to_str().unwrap(),
        ],
        &[
            "run.npy",
            ".npy and MCAP are not read for a floating base yet",
        ],
    );
    assert!(!Path::new(out).exists());
}

#[test]
fn diagnose_finds_a_payload_the_urdf_lacks() {
    let dir = TempDir::new("floating-diagnose");
    let log = simulate(
        &dir,
        "pay.csv",
        &["--seconds", "60", "--floating-effects", "payload"],
    );
    let robot = solo();
    let out = dir.0.join("report");
    let text = ok(&[
        "diagnose",
        "--robot",
        &robot,
        "--data",
        log.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&text);
    assert!(
        text.contains("accepted: payload: +0.29") || text.contains("accepted: payload: +0.30"),
        "{text}"
    );
    let d: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("floating_diagnosis.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(d["accepted"], serde_json::json!(["payload"]));
    // the simulation's record holds the truth: the payload in the base
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.0.join("pay.json")).unwrap()).unwrap();
    assert_eq!(record["effects"][0], "payload");
}

#[test]
fn floating_logs_take_the_readers_limits_and_follow_each_other() {
    let dir = TempDir::new("floating-limits");
    let (log, text, header) = short_log(&dir);
    let robot = solo();
    let out = dir.0.join("pred.csv");
    let out_s = out.to_str().unwrap();
    // a base angular velocity of 1e200 in one row: refused where it is read
    let wx = header.iter().position(|c| c == "base_wx").unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut cells: Vec<String> = lines[7].split(',').map(String::from).collect();
    cells[wx] = "1e200".into();
    lines[7] = cells.join(",");
    let wild = dir.write("wild.csv", &(lines.join("\n") + "\n"));
    let wild = wild.to_str().unwrap();
    for cmd in ["predict", "diagnose", "identify"] {
        let mut args = vec![cmd, "--robot", &robot, "--data", wild];
        if cmd == "predict" {
            args.extend(["--out", out_s]);
        }
        refused(
            &args,
            &["wild.csv", "row 7", "'base_wx'", "1e200 is beyond"],
        );
    }
    assert!(!out.exists());
    // two files: the second laid after the first, as fixed-base files are
    let log = log.to_str().unwrap();
    ok(&[
        "predict", "--robot", &robot, "--data", log, "--data", log, "--out", out_s,
    ]);
    let t: Vec<f64> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(t.len(), 2 * (text.lines().count() - 1));
    assert!(t.windows(2).all(|w| w[1] > w[0]), "t restarts");
}

#[test]
fn export_writes_a_free_root_and_excite_refuses_a_floating_base() {
    let dir = TempDir::new("floating-export-excite");
    let robot = solo();
    let (xml, csv) = (dir.0.join("s.xml"), dir.0.join("s.csv"));
    let urdf = dir.0.join("s.urdf");
    let export = [
        "export",
        "--robot",
        &robot,
        "--params",
        "true",
        "--mjcf-out",
        xml.to_str().unwrap(),
        "--urdf-out",
        urdf.to_str().unwrap(),
    ];
    ok(&export);
    // the MJCF's root body is the base with a free joint and its inertial
    let text = std::fs::read_to_string(&xml).unwrap();
    let root = text
        .find("<body name=\"base_link\">")
        .expect("the base body");
    let free = text
        .find("<freejoint name=\"base_link\"/>")
        .expect("a free joint");
    assert!(root < free && text[free..].find("<inertial").is_some());
    // the URDF's root link holds the base's identified inertial, the
    // sidecar keeps [floating_base]: the round trip predicts the same
    let side = dir.0.join("s.toml");
    assert!(
        std::fs::read_to_string(&side)
            .unwrap()
            .contains("[floating_base]")
    );
    let log = simulate(&dir, "log.csv", &["--seconds", "1"]);
    let predict = |robot: &str, sidecar: Option<&Path>, out: &str| {
        let out = dir.0.join(out);
        let mut args = vec!["predict", "--robot", robot, "--params", "true"];
        args.extend([
            "--data",
            log.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        if let Some(s) = sidecar {
            args.extend(["--sidecar", s.to_str().unwrap()]);
        }
        ok(&args);
        std::fs::read_to_string(out).unwrap()
    };
    let (a, b) = (
        predict(&robot, None, "a.csv"),
        predict(urdf.to_str().unwrap(), Some(&side), "b.csv"),
    );
    assert!(a.lines().next().unwrap().starts_with("t,base_force_x"));
    assert_eq!(
        a, b,
        "the exported URDF and sidecar predict as the original"
    );
    let excite = [
        "excite",
        "--robot",
        &robot,
        "--seconds",
        "1",
        "--out",
        csv.to_str().unwrap(),
    ];
    refused(&excite, &["excite is not built for a floating base"]);
    assert!(!csv.exists());
    // with no sidecar the URDF is a fixed-base robot, as the user said
    std::fs::remove_file(&xml).unwrap();
    let fixed = [&export[..3], &export[5..7], &["--no-sidecar"]].concat();
    ok(&fixed);
    assert!(!std::fs::read_to_string(&xml).unwrap().contains("freejoint"));
}

#[test]
fn a_fit_that_loses_the_robot_and_a_memory_limit_of_nan_are_refused() {
    let dir = TempDir::new("floating-collapse");
    let (_, text, header) = short_log(&dir);
    let robot = solo();
    // one row at the readers' limit in every velocity: the fit collapses
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut cells: Vec<String> = lines[21].split(',').map(String::from).collect();
    for (c, name) in header.iter().enumerate() {
        if name.starts_with("qd_")
            || ["base_vx", "base_wx", "base_wy", "base_wz"].contains(&name.as_str())
        {
            cells[c] = "1e8".into();
        }
    }
    lines[21] = cells.join(",");
    let wild = dir.write("edge.csv", &(lines.join("\n") + "\n"));
    let wild = wild.to_str().unwrap();
    refused(
        &["identify", "--robot", &robot, "--data", wild],
        &["whole robot a mass of", "do not determine it"],
    );
    let log = dir.0.join("log.csv");
    let log = log.to_str().unwrap();
    for g in ["NaN", "inf", "-1", "1e300"] {
        for cmd in ["identify", "diagnose"] {
            refused(
                &[cmd, "--robot", &robot, "--data", log, "--max-memory-gib", g],
                &["--max-memory-gib", "must be a positive number of GiB"],
            );
        }
    }
}

/// The fixed base's identification options on a floating base (one set-up
/// for both): the ellipsoid level bounds every body (the base by its root
/// link's geometry), `--total-mass` and `--equal` constrain the bodies,
/// the entropic regulariser needs a weight.
#[test]
fn the_fixed_base_options_act_on_a_floating_base() {
    let dir = TempDir::new("floating-options");
    let train = simulate(&dir, "train.csv", &["--seconds", "20", "--seed", "3"]);
    let (robot, train) = (solo(), train.to_str().unwrap().to_string());
    let fit = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec![
            "identify", "--robot", &robot, "--data", &train, "--rows", "base", "--json",
        ];
        args.extend(extra);
        serde_json::from_slice(&ok(&args)).unwrap()
    };
    let e = fit(&["--constraints", "ellipsoid"]);
    assert_eq!(e["constraints_satisfied"], true);
    // no friction acts on the base rows: exactly zero, not the solver's 1e-14
    for c in e["friction"]["viscous"].as_array().unwrap() {
        assert_eq!(c.as_f64(), Some(0.0));
    }
    let bodies = e["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 13, "the base and twelve links");
    assert_eq!(bodies[0]["name"], "base_link");
    for b in bodies {
        assert_eq!(b["level"], "ellipsoid", "{}", b["name"]);
        assert_eq!(b["realizability"]["realizable"], true, "{}", b["name"]);
        assert!(
            b["principal_moments"]
                .as_array()
                .is_some_and(|p| p.len() == 3)
        );
    }
    let m = fit(&["--total-mass", "2.6"]);
    let mass = num(&m, &["whole_body", "mass"]);
    assert!((mass - 2.6).abs() < 1e-6, "total mass {mass}");
    let q = fit(&["--equal", "FL_LOWER_LEG,FR_LOWER_LEG"]);
    let params = |name: &str| -> Vec<f64> {
        let b = q["bodies"]
            .as_array()
            .unwrap()
            .iter()
            .find(|b| b["name"] == name);
        let p = b.unwrap()["params"].as_array().unwrap();
        p.iter().map(|x| x.as_f64().unwrap()).collect()
    };
    let (a, b) = (params("FL_LOWER_LEG"), params("FR_LOWER_LEG"));
    assert!(
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-6),
        "{a:?} vs {b:?}"
    );
    let out = bin()
        .args([
            "identify", "--robot", &robot, "--data", &train, "--rows", "base",
        ])
        .args(["--regularizer", "entropic", "--weight", "0"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--regularizer entropic needs --weight > 0"),
        "{err}"
    );
}
