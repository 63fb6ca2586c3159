//! `simulate` and `identify` from the command line: files, JSON fields,
//! exit codes and bad input.

use std::process::Command;

mod common;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_momentlmi"))
}

#[test]
fn simulate_then_identify_then_predict() {
    let dir = std::env::temp_dir().join(format!("momentlmi-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let data = dir.join("leg.csv");
    let o = bin()
        .args([
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--seconds",
            "4",
            "--effects",
            "rotor_inertia,coulomb,viscous",
            "--seed",
            "5",
            "--out",
            data.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("leg.json")).unwrap()).unwrap();
    assert_eq!(record["samples"], 4000);
    assert_eq!(record["config"]["seed"], 5);
    assert_eq!(record["config"]["effects"]["on"][1], "coulomb");
    // split into training and validation halves
    let text = std::fs::read_to_string(&data).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].contains("qdd_knee") && lines[0].contains("tau_abad"));
    std::fs::write(dir.join("train.csv"), lines[..2001].join("\n")).unwrap();
    std::fs::write(
        dir.join("val.csv"),
        [&lines[..1], &lines[2001..]].concat().join("\n"),
    )
    .unwrap();
    let o = bin()
        .args([
            "identify",
            "--robot",
            "cheetah3-leg",
            "--constraints",
            "ellipsoid",
            "--json",
        ])
        .args([
            "--data",
            dir.join("train.csv").to_str().unwrap(),
            "--validate",
            dir.join("val.csv").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["bodies"].as_array().unwrap().len(), 6);
    assert!(
        v["bodies"]
            .as_array()
            .unwrap()
            .iter()
            .all(|b| b["consistent"] == true && b["params"].as_array().unwrap().len() == 10)
    );
    assert_eq!(v["validation_rms"].as_array().unwrap().len(), 3);
    assert!(
        v["solve_time_s"].as_f64().unwrap() > 0.0
            && v["total_time_s"].as_f64().unwrap() >= v["solve_time_s"].as_f64().unwrap()
    );
    // each stage timed; the friction law chosen by default (the simulated
    // leg's viscous + Coulomb), so the prepared training file was read whole
    // (a listed law streams it: tests/friction_auto.rs)
    let t = &v["timings"];
    let s = |k: &str| t[k].as_f64().unwrap_or_else(|| panic!("timings.{k}: {t}"));
    assert!(t["streamed"] == false, "{t}");
    let sel = &v["model_selection"];
    let chosen = &sel["laws"][sel["chosen"].as_u64().unwrap() as usize]["terms"];
    assert_eq!(chosen, &serde_json::json!(["viscous", "coulomb"]), "{sel}");
    assert!(
        ["read_s", "reduce_s", "solve_s", "validate_s"]
            .iter()
            .all(|k| s(k) > 0.0),
        "{t}"
    );
    assert!(s("filter_s") >= 0.0 && s("check_s") >= 0.0, "{t}");
    assert!(s("total_s") >= s("reduce_s") + s("solve_s"), "{t}");
    assert_eq!(v["friction"]["coulomb"].as_array().unwrap().len(), 3);
    std::fs::write(dir.join("model.json"), &o.stdout).unwrap();
    // the JSON is a model file for predict and a prior for identify
    let o = bin()
        .args([
            "predict",
            "--robot",
            "cheetah3-leg",
            "--params",
            dir.join("model.json").to_str().unwrap(),
        ])
        .args([
            "--data",
            dir.join("val.csv").to_str().unwrap(),
            "--out",
            dir.join("pred.csv").to_str().unwrap(),
            "--json",
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let p: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rms: Vec<f64> = p["rms_vs_measured"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let vr: Vec<f64> = v["validation_rms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    for (a, b) in rms.iter().zip(&vr) {
        assert!((a - b).abs() < 1e-6, "predict {a} vs identify {b}");
    }
    let o = bin()
        .args([
            "identify",
            "--robot",
            "cheetah3-leg",
            "--constraints",
            "consistent",
            "--prior",
            dir.join("model.json").to_str().unwrap(),
        ])
        .args(["--data", dir.join("train.csv").to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // bad input: exit 2, message, nothing written
    let never = dir.join("never.csv");
    for args in [
        vec![
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--effects",
            "warp_drive",
            "--out",
            never.to_str().unwrap(),
        ],
        vec![
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--seconds",
            "-1",
            "--out",
            never.to_str().unwrap(),
        ],
        vec![
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--effect-param",
            "offset=x",
            "--out",
            never.to_str().unwrap(),
        ],
    ] {
        let o = bin().args(&args).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!never.exists());
    }
    for c in ["bogus"] {
        let o = bin()
            .args([
                "identify",
                "--robot",
                "cheetah3-leg",
                "--constraints",
                c,
                "--data",
                dir.join("train.csv").to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2));
        assert!(
            String::from_utf8_lossy(&o.stderr)
                .contains("not one of none, semi, consistent, ellipsoid")
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// An unknown effect or effect parameter is an error listing the valid names.
#[test]
fn unknown_effect_names_list_the_valid_ones() {
    let dir = std::env::temp_dir().join(format!("momentlmi-cli-fx-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("x.csv");
    let run = |extra: &[&str]| {
        let o = bin()
            .args(["simulate", "--robot", "cheetah3-leg", "--seconds", "0.5"])
            .args(extra)
            .args(["--out", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        assert!(!out.exists(), "nothing written");
        String::from_utf8_lossy(&o.stderr).to_string()
    };
    let e = run(&["--effects", "coulomb,warp_drive"]);
    assert!(
        e.contains("warp_drive") && e.contains("rotor_inertia") && e.contains("backlash"),
        "{e}"
    );
    let e = run(&["--effects", "stribeck", "--effect-param", "stribek_force=2"]);
    assert!(
        e.contains("stribek_force") && e.contains("stribeck_force") && e.contains("gain_error"),
        "{e}"
    );
    let e = run(&["--effects", "offset", "--effect-param", "delay=0.01"]);
    assert!(
        e.contains("time_delay") && e.contains("not switched on"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A URDF robot with a sidecar: simulate, then identify at the ellipsoid
/// level with the sidecar's prior and ellipsoids, as for the leg.
#[test]
fn urdf_robot_with_a_sidecar_end_to_end() {
    let dir = std::env::temp_dir().join(format!("momentlmi-cli-urdf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("pend.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="pend"><link name="base"/>
<link name="arm"><inertial><origin xyz="0.2 0 0"/><mass value="1.5"/>
<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
<link name="tip"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/>
<inertia ixx="0.0005" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
<limit lower="-2" upper="2" effort="10" velocity="5"/></joint>
<joint name="j2" type="revolute"><parent link="arm"/><child link="tip"/><origin xyz="0.4 0 0"/>
<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="5"/></joint></robot>"#,
    )
    .unwrap();
    let sidecar = dir.join("pend.toml");
    std::fs::write(
        &sidecar,
        r#"[[joint]]
name = "j1"
coulomb = 0.4
viscous = 0.05
[[joint]]
name = "j2"
coulomb = 0.3
viscous = 0.02
[[body]]
name = "arm"
prior = { mass = 1.4, com = [0.2, 0.0, 0.0], box = [0.4, 0.05, 0.05] }
bounding = [{ center = [0.2, 0.0, 0.0], semi_axes = [0.3, 0.06, 0.06] }]
[[body]]
name = "tip"
bounding = [{ center = [0.1, 0.0, 0.0], semi_axes = [0.2, 0.08, 0.08] }]
"#,
    )
    .unwrap();
    let data = dir.join("pend.csv");
    let o = bin()
        .args(["simulate", "--robot", urdf.to_str().unwrap()])
        .args(["--sidecar", sidecar.to_str().unwrap()])
        .args([
            "--seconds",
            "10",
            "--effects",
            "coulomb,viscous",
            "--noise",
            "0.02",
        ])
        .args(["--out", data.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("pend.json")).unwrap()).unwrap();
    assert_eq!(record["nominal_friction"]["coulomb"][1], 0.3);
    let o = bin()
        .args(["identify", "--robot", urdf.to_str().unwrap()])
        .args(["--sidecar", sidecar.to_str().unwrap()])
        .args([
            "--data",
            data.to_str().unwrap(),
            "--constraints",
            "ellipsoid",
            "--json",
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["constraints_satisfied"], true);
    for b in v["bodies"].as_array().unwrap() {
        assert_eq!(b["realizability"]["realizable"], true, "{}", b["name"]);
    }
    let c: Vec<f64> = v["friction"]["coulomb"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(
        (c[0] - 0.4).abs() < 0.03 && (c[1] - 0.3).abs() < 0.03,
        "{c:?}"
    );
    // without the sidecar the ellipsoid level names the body that has none
    let o = bin()
        .args([
            "identify",
            "--robot",
            urdf.to_str().unwrap(),
            "--no-sidecar",
        ])
        .args([
            "--data",
            data.to_str().unwrap(),
            "--constraints",
            "ellipsoid",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("body 'arm' has no bounding ellipsoid"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A known total mass and two bodies forced equal, from flags and from a
/// sidecar; the knee alone at the ellipsoid level.
#[test]
fn identify_with_a_known_mass_and_equal_bodies_from_the_command_line() {
    let dir = std::env::temp_dir().join(format!("momentlmi-cli-known-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let data = dir.join("leg.csv");
    let o = bin()
        .args(["simulate", "--robot", "cheetah3-leg", "--seconds", "6"])
        .args(["--effects", "rotor_inertia,coulomb,viscous", "--seed", "9"])
        .args(["--out", data.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = bin()
        .args(["identify", "--robot", "cheetah3-leg", "--json"])
        .args(["--data", data.to_str().unwrap()])
        .args(["--total-mass", "5.25", "--equal", "hip_rotor,knee_rotor"])
        .args(["--level", "knee=ellipsoid"])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let bodies = v["bodies"].as_array().unwrap();
    let total: f64 = bodies.iter().map(|b| b["mass"].as_f64().unwrap()).sum();
    assert!((total - 5.25).abs() < 1e-6, "{total}");
    let params = |name: &str| -> Vec<f64> {
        bodies.iter().find(|b| b["name"] == name).unwrap()["params"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let (a, b) = (params("hip_rotor"), params("knee_rotor"));
    assert!(
        a.iter()
            .zip(&b)
            .all(|(x, y)| (x - y).abs() < 1e-7 * (1.0 + x.abs()))
    );
    let knee = bodies.iter().find(|b| b["name"] == "knee").unwrap();
    assert_eq!(knee["level"], "ellipsoid");
    assert_eq!(knee["realizability"]["realizable"], true);
    // bad names are errors naming the valid ones
    let o = bin()
        .args(["identify", "--robot", "cheetah3-leg"])
        .args([
            "--data",
            data.to_str().unwrap(),
            "--equal",
            "hip_rotor,shin",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("'shin'"));
    // the same facts from a URDF robot's sidecar
    let urdf = dir.join("two.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="two"><link name="base"/>
<link name="l1"><inertial><origin xyz="0.15 0 0"/><mass value="1.0"/>
<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.008" iyz="0" izz="0.008"/></inertial></link>
<link name="l2"><inertial><origin xyz="0.15 0 0"/><mass value="1.0"/>
<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.008" iyz="0" izz="0.008"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 1 0"/>
<limit lower="-2" upper="2" effort="10" velocity="5"/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/>
<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="5"/></joint></robot>"#,
    )
    .unwrap();
    let sidecar = dir.join("two.toml");
    std::fs::write(
        &sidecar,
        "[identify]\ntotal_mass = 2.0\nequal = [[\"l1\", \"l2\"]]\nprior_mass_weight = 0.5\n\n[[body]]\nname = \"l2\"\nlevel = \"semi\"\n",
    )
    .unwrap();
    let d2 = dir.join("two.csv");
    let o = bin()
        .args(["simulate", "--robot", urdf.to_str().unwrap()])
        .args(["--sidecar", sidecar.to_str().unwrap(), "--seconds", "6"])
        .args(["--effects", "coulomb,viscous", "--noise", "0.02"])
        .args(["--out", d2.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = bin()
        .args(["identify", "--robot", urdf.to_str().unwrap()])
        .args(["--sidecar", sidecar.to_str().unwrap(), "--json"])
        .args(["--data", d2.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let bodies = v["bodies"].as_array().unwrap();
    let m: Vec<f64> = bodies.iter().map(|b| b["mass"].as_f64().unwrap()).collect();
    assert!(
        (m[0] + m[1] - 2.0).abs() < 1e-6 && (m[0] - m[1]).abs() < 1e-7,
        "{m:?}"
    );
    assert_eq!(bodies[1]["level"], "semi");
    // the sidecar's masses' weight: taken with the Euclidean prior on, not
    // with the default's entropic one, overridden by the flag, not taken
    // with --weight 0; a bad one named with its file
    assert_eq!(v["regularizer"], "entropic");
    assert_eq!(v["prior_mass_weight"], serde_json::json!(0.0));
    let mass_weight = |extra: &[&str]| -> serde_json::Value {
        let o = bin()
            .args(["identify", "--robot", urdf.to_str().unwrap()])
            .args(["--sidecar", sidecar.to_str().unwrap(), "--json"])
            .args(["--data", d2.to_str().unwrap()])
            .args(extra)
            .output()
            .unwrap();
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        v["prior_mass_weight"].clone()
    };
    assert_eq!(
        mass_weight(&["--regularizer", "euclidean"]),
        serde_json::json!(0.5)
    );
    assert_eq!(
        mass_weight(&["--prior-mass-weight", "0"]),
        serde_json::json!(0.0)
    );
    assert_eq!(mass_weight(&["--weight", "0"]), serde_json::json!(0.0));
    let over = ["--prior-mass-weight", "2"];
    assert_eq!(mass_weight(&over), serde_json::json!(2.0));
    let own = ["--weight", "0", "--prior-mass-weight", "2"];
    assert_eq!(mass_weight(&own), serde_json::json!(2.0));
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[identify]\nprior_mass_weight = -1.0\n").unwrap();
    let o = bin()
        .args(["identify", "--robot", urdf.to_str().unwrap()])
        .args(["--sidecar", bad.to_str().unwrap()])
        .args(["--data", d2.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("bad.toml") && err.contains("[identify] prior_mass_weight = -1"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Panda from ../shared (when present, with its meshes beside it):
/// simulated, then identified at the ellipsoid level with bounding
/// ellipsoids from its collision meshes; every body satisfies its level.
#[test]
fn the_panda_identifies_at_the_ellipsoid_level_from_its_meshes() {
    let urdf =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/reference/panda.urdf");
    if !urdf.exists() || !urdf.with_file_name("example-robot-data").exists() {
        eprintln!("skipped: {} or its meshes are not here", urdf.display());
        return;
    }
    let dir = std::env::temp_dir().join(format!("momentlmi-panda-ell-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (u, data) = (urdf.to_str().unwrap(), dir.join("panda.csv"));
    let d = data.to_str().unwrap();
    common::ok(&["simulate", "--robot", u, "--seconds", "3", "--out", d]);
    let json = common::ok(&[
        "identify",
        "--robot",
        u,
        "--data",
        d,
        "--constraints",
        "ellipsoid",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
    assert_eq!(v["constraints_satisfied"], true);
    let bodies = v["bodies"].as_array().unwrap();
    assert!(bodies.len() >= 7);
    for b in bodies {
        assert_eq!(b["realizability"]["realizable"], true, "{}", b["name"]);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--regularizer entropic` from the command line: the text report names
/// it and each body's divergence from the prior; an inconsistent prior
/// body is a warning with the Euclidean prior and an error naming the body
/// with the entropic one; weight 0 with entropic is refused.
#[test]
fn the_entropic_prior_from_the_command_line() {
    let dir = common::TempDir::new("entropic");
    let data = dir.0.join("leg.csv");
    common::ok(&[
        "simulate",
        "--robot",
        "cheetah3-leg",
        "--seconds",
        "3",
        "--seed",
        "9",
        "--out",
        data.to_str().unwrap(),
    ]);
    let identify = |extra: &[&str]| {
        let mut args = vec![
            "identify",
            "--robot",
            "cheetah3-leg",
            "--data",
            data.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        bin().args(&args).output().unwrap()
    };
    let o = identify(&["--regularizer", "entropic", "--weight", "1e-2"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(text.contains("entropic prior with weight 1e-2"), "{text}");
    assert!(text.contains("d(J‖Ĵ)"), "{text}");
    // a prior whose knee has a negative Ixx
    let mut pf: serde_json::Value = serde_json::from_slice(&identify(&["--json"]).stdout).unwrap();
    let knee = pf["bodies"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|b| b["name"] == "knee")
        .unwrap();
    knee["params"][4] = serde_json::json!(-0.01);
    let prior = dir.write("prior.json", &pf.to_string());
    let o = identify(&["--prior", prior.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--prior: body 'knee' is not physically consistent"),
        "{err}"
    );
    let o = identify(&[
        "--prior",
        prior.to_str().unwrap(),
        "--regularizer",
        "entropic",
        "--weight",
        "1e-2",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("body 'knee'") && err.contains("not positive definite"),
        "{err}"
    );
    let o = identify(&["--regularizer", "entropic", "--weight", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("needs --weight > 0"));
    // the masses' extra weight: in the report and the JSON, a bad value named
    let o = identify(&["--prior-mass-weight", "1e-2"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("(masses 1e-2)"));
    let js: serde_json::Value =
        serde_json::from_slice(&identify(&["--prior-mass-weight", "1e-2", "--json"]).stdout)
            .unwrap();
    assert_eq!(js["prior_mass_weight"], serde_json::json!(1e-2));
    let o = identify(&["--prior-mass-weight", "-1"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--prior-mass-weight") && err.contains("≥ 0"),
        "{err}"
    );
}

/// Data of the Panda simulated with its sidecar (fingers locked), read
/// without it: the missing finger column is named, with a hint naming the
/// sidecar the data's JSON records (a general one without that JSON); exit
/// 2. A built-in robot's missing column gets no hint.
#[test]
fn data_made_with_a_sidecar_read_without_it_hints_at_the_sidecar() {
    let dir = common::TempDir::new("hint-sidecar");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/panda");
    let (urdf, sidecar) = (root.join("panda.urdf"), root.join("panda.toml"));
    let (u, data) = (urdf.to_str().unwrap(), dir.0.join("arm.csv"));
    let d = data.to_str().unwrap();
    let sc = sidecar.to_str().unwrap();
    common::ok(&[
        "simulate",
        "--robot",
        u,
        "--sidecar",
        sc,
        "--seconds",
        "1",
        "--out",
        d,
    ]);
    let out = dir.0.join("pred.csv");
    for cmd in ["identify", "diagnose", "predict"] {
        let mut c = bin();
        c.args([cmd, "--robot", u, "--no-sidecar", "--data", d]);
        if cmd == "predict" {
            c.args(["--out", out.to_str().unwrap()]);
        }
        let o = c.output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {err}");
        // the data's JSON says which sidecar made them
        let named = format!("simulated with --sidecar {sc}");
        assert!(
            err.contains("missing column 'q_panda_finger_joint") && err.contains(&named),
            "{cmd}: {err}"
        );
    }
    // without that JSON, the hint is general
    std::fs::remove_file(data.with_extension("json")).unwrap();
    let err = identify_fails(u, d);
    assert!(err.contains("pass it with --sidecar FILE"), "{err}");
    let err = identify_fails("cheetah3-leg", d);
    assert!(
        err.contains("missing column") && !err.contains("--sidecar"),
        "{err}"
    );
}

/// `identify --robot ROBOT --data DATA`'s standard error, asserting exit 2.
fn identify_fails(robot: &str, data: &str) -> String {
    let o = bin()
        .args(["identify", "--robot", robot, "--no-sidecar", "--data", data])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    err
}

/// A recording without torques, read by `identify` for a URDF robot without
/// `--sidecar`: the missing torque column is named, and no hint at a
/// sidecar (the joints are all there).
#[test]
fn a_missing_torque_column_gets_no_sidecar_hint() {
    let dir = common::TempDir::new("no-tau-hint");
    let urdf = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/panda/panda.urdf");
    let (u, data) = (urdf.to_str().unwrap(), dir.0.join("arm.csv"));
    common::ok(&[
        "simulate",
        "--robot",
        u,
        "--no-sidecar",
        "--seconds",
        "1",
        "--out",
        data.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&data).unwrap();
    let keep: Vec<usize> = text
        .lines()
        .next()
        .unwrap()
        .split(',')
        .enumerate()
        .filter(|(_, c)| !c.starts_with("tau_"))
        .map(|(i, _)| i)
        .collect();
    let stripped: String = text
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&i| f[i]).collect::<Vec<_>>().join(",") + "\n"
        })
        .collect();
    let no_tau = dir.0.join("no_tau.csv");
    std::fs::write(&no_tau, stripped).unwrap();
    let err = identify_fails(u, no_tau.to_str().unwrap());
    assert!(
        err.contains("missing column 'tau_") && !err.contains("--sidecar"),
        "{err}"
    );
}
