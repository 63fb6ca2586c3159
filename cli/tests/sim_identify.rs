//! `simulate` and `identify` from the command line: files, JSON fields,
//! exit codes and bad input.

use std::process::Command;

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
