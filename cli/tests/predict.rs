//! `momentlmi predict`: the leg with true parameters and friction, and the
//! Panda against reference torques.

use momentlmi::dynamics::{Data, cheetah3, crba, energy};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("momentlmi-dp-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Torques from the Euler–Lagrange equations with finite differences of the
/// energies (T from the mass matrix, U from the bodies' heights): an
/// algorithm independent of the RNEA recursion, with the rotors included.
fn lagrange_torque(q: &[f64; 3], qd: &[f64; 3], qdd: &[f64; 3]) -> [f64; 3] {
    let m = cheetah3::model();
    let mut d = Data::new(&m);
    let mass = |d: &mut Data, q: &[f64; 3]| crba(&m, d, q).unwrap().clone();
    let h = 1e-6;
    let mq = mass(&mut d, q);
    let mut tau = [0.0; 3];
    for i in 0..3 {
        // d/dt(M q̇)_i = (M q̈)_i + Σ_k (∂M/∂q_k q̇_k q̇)_i ; ∂L/∂q_i = ½ q̇ᵀ ∂M/∂q_i q̇ − ∂U/∂q_i
        let mut t = 0.0;
        for k in 0..3 {
            t += mq[(i, k)] * qdd[k];
        }
        for k in 0..3 {
            let (mut qp, mut qm) = (*q, *q);
            qp[k] += h;
            qm[k] -= h;
            let dm = (mass(&mut d, &qp) - mass(&mut d, &qm)) / (2.0 * h);
            for l in 0..3 {
                t += dm[(i, l)] * qd[k] * qd[l];
            }
        }
        let (mut qp, mut qm) = (*q, *q);
        qp[i] += h;
        qm[i] -= h;
        let dmi = (mass(&mut d, &qp) - mass(&mut d, &qm)) / (2.0 * h);
        let mut half = 0.0;
        for k in 0..3 {
            for l in 0..3 {
                half += 0.5 * qd[k] * dmi[(k, l)] * qd[l];
            }
        }
        let up = energy(&m, &mut d, &qp, &[0.0; 3]).unwrap().1;
        let um = energy(&m, &mut d, &qm, &[0.0; 3]).unwrap().1;
        tau[i] = t - half + (up - um) / (2.0 * h);
    }
    tau
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_momentlmi"))
}

#[test]
fn predict_cli_on_cheetah_with_true_params_and_friction() {
    let dir = tmp("leg");
    let states = [
        ([0.3, -0.9, 1.7], [1.0, -2.0, 3.0], [5.0, -3.0, 10.0]),
        ([-1.0, 2.0, -0.5], [-4.0, 0.5, 8.0], [0.0, 20.0, -7.0]),
    ];
    let mut s =
        String::from("t,q_abad,q_hip,q_knee,qd_abad,qd_hip,qd_knee,qdd_abad,qdd_hip,qdd_knee\n");
    for (k, (q, qd, qdd)) in states.iter().enumerate() {
        s += &format!(
            "{k},{},{},{},{},{},{},{},{},{}\n",
            q[0], q[1], q[2], qd[0], qd[1], qd[2], qdd[0], qdd[1], qdd[2]
        );
    }
    let data = dir.join("in.csv");
    std::fs::write(&data, s).unwrap();
    let out = dir.join("pred.csv");
    let o = bin()
        .args([
            "predict",
            "--robot",
            "cheetah3-leg",
            "--params",
            "true",
            "--data",
            data.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "t,tau_abad,tau_hip,tau_knee");
    for (line, (q, qd, qdd)) in lines.zip(states) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let l = lagrange_torque(&q, &qd, &qdd);
        for i in 0..3 {
            let want = l[i] + cheetah3::VISCOUS[i] * qd[i] + cheetah3::COULOMB[i] * qd[i].signum();
            assert!(
                (v[1 + i] - want).abs() < 1e-5 * (1.0 + want.abs()),
                "{} vs {want}",
                v[1 + i]
            );
        }
    }
    // errors: unknown robot, bad params, bad data → exit 2 and nothing written
    let out2 = dir.join("never.csv");
    for args in [
        vec![
            "predict",
            "--robot",
            "no-such-robot",
            "--data",
            data.to_str().unwrap(),
            "--out",
            out2.to_str().unwrap(),
        ],
        vec![
            "predict",
            "--robot",
            "cheetah3-leg",
            "--params",
            "/nonexistent.json",
            "--data",
            data.to_str().unwrap(),
            "--out",
            out2.to_str().unwrap(),
        ],
        vec![
            "predict",
            "--robot",
            "cheetah3-leg",
            "--data",
            "/nonexistent.csv",
            "--out",
            out2.to_str().unwrap(),
        ],
    ] {
        let o = bin().args(&args).output().unwrap();
        assert_eq!(o.status.code(), Some(2));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"));
        assert!(!out2.exists());
        // the flag is named, and a missing file once
        if args.contains(&"--params") {
            assert!(err.contains("--params: "), "{err}");
            assert_eq!(err.matches("/nonexistent.json").count(), 1, "{err}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn predict_cli_on_panda_reproduces_reference_torques() {
    let refdir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/reference");
    let (Ok(json), true) = (
        std::fs::read_to_string(refdir.join("rnea_panda.json")),
        refdir.join("panda.urdf").exists(),
    ) else {
        println!("skipping: ../shared/reference not found");
        return;
    };
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let dir = tmp("panda");
    let names: Vec<String> = (1..=7).map(|i| format!("panda_joint{i}")).collect();
    let mut s = String::from("t");
    for p in ["q", "qd", "qdd"] {
        for n in &names {
            s += &format!(",{p}_{n}");
        }
    }
    s.push('\n');
    let cases = v["cases"].as_array().unwrap();
    for (k, c) in cases.iter().enumerate() {
        s += &k.to_string();
        for p in ["q", "qd", "qdd"] {
            for x in c[p].as_array().unwrap() {
                s += &format!(",{}", x.as_f64().unwrap());
            }
        }
        s.push('\n');
    }
    std::fs::write(dir.join("in.csv"), s).unwrap();
    std::fs::write(
        dir.join("lock.toml"),
        "lock = [\"panda_finger_joint1\", \"panda_finger_joint2\"]\n",
    )
    .unwrap();
    let o = bin()
        .args([
            "predict",
            "--robot",
            refdir.join("panda.urdf").to_str().unwrap(),
            "--sidecar",
            dir.join("lock.toml").to_str().unwrap(),
        ])
        .args([
            "--data",
            dir.join("in.csv").to_str().unwrap(),
            "--out",
            dir.join("pred.csv").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(dir.join("pred.csv")).unwrap();
    for (line, c) in text.lines().skip(1).zip(cases) {
        let got: Vec<f64> = line
            .split(',')
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect();
        for (g, w) in got.iter().zip(c["tau"].as_array().unwrap()) {
            assert!((g - w.as_f64().unwrap()).abs() < 1e-9);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
