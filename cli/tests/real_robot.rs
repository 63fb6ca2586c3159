//! The KUKA LWR4+ runs as published (robots/kuka-lwr4): `identify` reads
//! them with no flag but the files, at every constraint level, the missing
//! collision mesh a warning (issue 33).

mod common;
use common::bin;

#[test]
fn the_kuka_runs_identify_as_published_at_every_level() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4");
    let s = |p: &str| root.join(p).to_str().unwrap().to_string();
    for level in ["none", "semi", "consistent", "ellipsoid"] {
        let o = bin()
            .args(["identify", "--robot", &s("kuka_lwr4.urdf")])
            .args(["--data", &s("data/measurements_1.npz")])
            .args(["--data", &s("data/measurements_2.npz")])
            .args(["--validate", &s("data/measurements_3.npz")])
            .args(["--constraints", level, "--json"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{level}: {err}");
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert!(v["training_samples"].as_u64().unwrap() > 9000, "{level}");
        assert_eq!(
            v["data_preparation"]["training"].as_array().unwrap().len(),
            2
        );
        let f = &v["data_preparation"]["training"][0];
        assert_eq!(f["rows"], 5027);
        assert!(
            f["cutoff_from"]
                .as_str()
                .unwrap()
                .contains("by held-out torque error")
        );
        let c = &v["data_preparation"]["cutoff_choice"];
        let (chosen, top) = (
            c["chosen_hz"].as_f64().unwrap(),
            c["spectrum_hz"].as_f64().unwrap(),
        );
        assert!(chosen > 1.0 && chosen <= top, "{level}: {c}");
        assert_eq!(
            c["mean_rms"].as_array().unwrap().len(),
            c["cutoffs_hz"].as_array().unwrap().len()
        );
        let rms: Vec<f64> = serde_json::from_value(v["validation_rms"].clone()).unwrap();
        assert_eq!(rms.len(), 7);
        assert!(
            rms.iter().all(|x| x.is_finite() && *x < 3.0),
            "{level}: {rms:?}"
        );
        // the mesh the repository never shipped: a warning, at the level that reads meshes
        let warned = err.contains("arm_wrist_convex.stl") && err.contains("link_6.STL");
        assert_eq!(warned, level == "ellipsoid", "{level}: {err}");
        // every body's consistency, whatever the level
        match level {
            "none" => assert_eq!(
                v["all_bodies_consistent"], false,
                "the unconstrained fit is not physical"
            ),
            "consistent" | "ellipsoid" => assert_eq!(v["all_bodies_consistent"], true),
            _ => assert!(v["all_bodies_consistent"].is_boolean()),
        }
    }
}

/// The default on the KUKA's runs 1–2 (training only, no held-out run): the
/// runs repeat one trajectory, so the law and the weight are chosen over
/// blocks of time; the prior is the entropic one and no body collapses,
/// where the Euclidean prior at the weight it chooses leaves them point
/// masses, rods or plates (issue 56: no degenerate body by default).
#[test]
fn the_kukas_default_holds_every_body_off_the_boundary() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4");
    let s = |p: &str| root.join(p).to_str().unwrap().to_string();
    let run = |extra: &[&str]| -> serde_json::Value {
        let o = bin()
            .args(["identify", "--robot", &s("kuka_lwr4.urdf")])
            .args(["--data", &s("data/measurements_1.npz")])
            .args(["--data", &s("data/measurements_2.npz"), "--json"])
            .args(extra)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{err}");
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let v = run(&[]);
    assert_eq!(
        v["model_selection"]["folds"], "time",
        "runs 1–2 are repeats"
    );
    assert_eq!(v["model_selection"]["k"], 5);
    assert_eq!(v["regularizer"], "entropic");
    assert_eq!(v["all_bodies_consistent"], true);
    assert_eq!(v["degenerate_bodies"], serde_json::json!([]));
    let w = v["weight"].as_f64().unwrap();
    assert!((1e-6..=1.0).contains(&w), "the weight is the grid's: {w}");
    let e = run(&["--regularizer", "euclidean"]);
    assert_eq!(e["regularizer"], "euclidean");
    assert!(
        e["degenerate_bodies"].as_array().unwrap().len() >= 4,
        "{}",
        e["degenerate_bodies"]
    );
}

/// `predict` on a log with a 1 s pause and no q̈: the pause is a segment
/// boundary that no filter crosses, so the torques near it are those of the
/// same log without the pause (before issue 33 a hip torque of 63.6 N·m
/// appeared where the log without the pause says −2.4).
#[test]
fn predict_does_not_filter_across_a_pause() {
    let dir = common::TempDir::new("predict-gap");
    let sim = dir.0.join("leg.csv");
    common::ok(&[
        "simulate",
        "--robot",
        "cheetah3-leg",
        "--seconds",
        "4",
        "--out",
        sim.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&sim).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !header[i].starts_with("qdd_"))
        .collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let write = |name: &str, pause: f64| {
        let mut s = keep
            .iter()
            .map(|&i| header[i])
            .collect::<Vec<_>>()
            .join(",")
            + "\n";
        for (k, r) in rows.iter().enumerate() {
            let t = r[0] + if k >= rows.len() / 2 { pause } else { 0.0 };
            let mut f = vec![t.to_string()];
            f.extend(keep[1..].iter().map(|&i| r[i].to_string()));
            s += &(f.join(",") + "\n");
        }
        dir.write(name, &s)
    };
    let (plain, paused) = (write("plain.csv", 0.0), write("paused.csv", 1.0));
    // the paused log's halves as two files: the same two segments
    let (head, tail) = paused_text_halves(&std::fs::read_to_string(&paused).unwrap());
    let (first, second) = (
        dir.write("first.csv", &head),
        dir.write("second.csv", &tail),
    );
    let predict = |data: &[&std::path::Path], out: &str| {
        let out = dir.0.join(out);
        let mut args = vec!["predict", "--robot", "cheetah3-leg", "--params", "true"];
        for d in data {
            args.extend(["--data", d.to_str().unwrap()]);
        }
        args.extend(["--cutoff-hz", "20", "--out", out.to_str().unwrap()]);
        common::ok(&args);
        let text = std::fs::read_to_string(out).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                l.split(',')
                    .map(|x| x.parse::<f64>().unwrap())
                    .collect::<Vec<f64>>()
            })
            .collect::<Vec<_>>()
    };
    let (a, b) = (predict(&[&plain], "a.csv"), predict(&[&paused], "b.csv"));
    let c = predict(&[&first, &second], "c.csv");
    assert_eq!(b.len(), c.len());
    let most = (b.iter().zip(&c))
        .flat_map(|(x, y)| x.iter().zip(y).map(|(u, v)| (u - v).abs()))
        .fold(0.0, f64::max);
    assert!(
        most < 1e-9,
        "two files differ from one paused file by {most}"
    );
    // the diagnosis of the two files is the paused file's: no spectrum,
    // difference or rate spans the pause
    let diagnose = |data: &[&std::path::Path]| {
        let mut args = vec!["diagnose", "--robot", "cheetah3-leg", "--json"];
        for d in data {
            args.extend(["--data", d.to_str().unwrap()]);
        }
        args.extend(["--cutoff-hz", "20"]);
        let v: serde_json::Value = serde_json::from_slice(&common::ok(&args)).unwrap();
        v["where"].clone()
    };
    let (one, two) = (diagnose(&[&paused]), diagnose(&[&first, &second]));
    assert_eq!(one, two);
    // the bands reach the sampling rate's Nyquist frequency, the log's
    // without the pause (its rate, not samples over a span with a pause)
    let top = |w: &serde_json::Value| w[0]["spectrum"][3][0].as_str().unwrap().to_string();
    assert_eq!(top(&one), top(&diagnose(&[&plain])));
    let peak = |v: &[Vec<f64>]| {
        v.iter()
            .flat_map(|r| r[1..].iter().map(|x| x.abs()))
            .fold(0.0, f64::max)
    };
    // the paused log loses the ends of its two segments, nothing more, and
    // no torque appears that the log without the pause does not have
    assert!(
        b.len() < a.len() && b.len() > a.len() - 200,
        "{} vs {}",
        b.len(),
        a.len()
    );
    assert!(
        peak(&b) <= 1.05 * peak(&a),
        "peak |τ| {} with the pause, {} without",
        peak(&b),
        peak(&a)
    );
}

/// A CSV's header and rows split at the pause (the largest step) into two
/// files' texts.
fn paused_text_halves(text: &str) -> (String, String) {
    let lines: Vec<&str> = text.lines().collect();
    let t: Vec<f64> = (lines[1..].iter())
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    let at = (1..t.len())
        .max_by(|&i, &j| (t[i] - t[i - 1]).total_cmp(&(t[j] - t[j - 1])))
        .unwrap();
    let part = |rows: &[&str]| format!("{}\n{}\n", lines[0], rows.join("\n"));
    (part(&lines[1..=at]), part(&lines[at + 1..]))
}

/// The sidecar's mapping is a default: a log `simulate` wrote for the KUKA
/// (the CSV format's own names) still reads without flags; a mapping given
/// with `--mapping` is held to.
#[test]
fn a_simulated_kuka_log_reads_past_the_robots_default_mapping() {
    let dir = common::TempDir::new("kuka-sim");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4");
    let (urdf, csv) = (root.join("kuka_lwr4.urdf"), dir.0.join("k.csv"));
    let (u, c) = (urdf.to_str().unwrap(), csv.to_str().unwrap());
    common::ok(&["simulate", "--robot", u, "--seconds", "3", "--out", c]);
    common::ok(&["identify", "--robot", u, "--data", c]);
    let m = root.join("kuka_lwr4_mapping.toml");
    let o = bin()
        .args([
            "identify",
            "--robot",
            u,
            "--data",
            c,
            "--mapping",
            m.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("missing column 'times'"));
}

/// `--friction viscous,coulomb,offset,load,stribeck` on the KUKA (issue
/// 35): the torque sensors' offsets are identified (either sign) and cut
/// joint 0's held-out error (1.06 N·m without them at the ellipsoid level);
/// the model file, with every term and a Stribeck velocity that is not the
/// default, goes back into `predict`, which reproduces identify's held-out
/// RMS on every joint; an unknown term is refused by name.
#[test]
fn the_kukas_torque_offsets_are_identified_and_predicted() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4");
    let s = |p: &str| root.join(p).to_str().unwrap().to_string();
    let identify = |friction: &str| {
        bin()
            .args(["identify", "--robot", &s("kuka_lwr4.urdf")])
            .args(["--data", &s("data/measurements_1.npz")])
            .args(["--validate", &s("data/measurements_3.npz")])
            .args([
                "--constraints",
                "ellipsoid",
                "--json",
                "--friction",
                friction,
                "--stribeck-velocity",
                "0.1",
            ])
            .output()
            .unwrap()
    };
    let o = identify("viscous,coulomb,offset,load,stribeck");
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let offset: Vec<f64> = serde_json::from_value(v["friction"]["offset"].clone()).unwrap();
    assert!(
        offset.iter().any(|&c| c < -0.05) && offset.iter().any(|&c| c > 0.05),
        "{offset:?}"
    );
    assert_eq!(v["friction"]["stribeck_velocity"], 0.1, "{}", v["friction"]);
    for term in ["load", "stribeck"] {
        let c: Vec<f64> = serde_json::from_value(v["friction"][term].clone()).unwrap();
        assert!(c.iter().any(|&c| c != 0.0), "{term}: {c:?}");
    }
    let rms: Vec<f64> = serde_json::from_value(v["validation_rms"].clone()).unwrap();
    assert!(rms[0] < 0.9, "{rms:?}");
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.json");
    std::fs::write(&model, &o.stdout).unwrap();
    let p = bin()
        .args(["predict", "--robot", &s("kuka_lwr4.urdf")])
        .args(["--params", model.to_str().unwrap()])
        .args(["--data", &s("data/measurements_3.npz")])
        .args(["--out", dir.path().join("p.csv").to_str().unwrap()])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&p.stdout).to_string() + &String::from_utf8_lossy(&p.stderr);
    assert_eq!(p.status.code(), Some(0), "{out}");
    for (i, want) in rms.iter().enumerate() {
        let joint = format!("lwr_{i}_joint");
        let line = out.lines().find(|l| l.contains(&joint)).expect(&out);
        let got: f64 = line.split_whitespace().last().unwrap().parse().unwrap();
        assert!((got - want).abs() < 1e-3, "{joint}: {got} vs {want}");
    }
    let bad = identify("viscous,stiction");
    let err = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        err.contains("--friction: unknown friction term 'stiction'"),
        "{err}"
    );
}

/// `diagnose` on run 3 against the KUKA model of the recommended options
/// (docs/real-robot.md), with `--repeats` runs 1 and 2 (issue 35): the
/// noise floor is the runs' repeatability (RMS(τ₁ − τ₂)/√2, measured
/// 2026-12-04: 0.146 0.179 0.186 0.156 0.055 0.024 0.010 N·m), the gap
/// closed is within [0, 1] on every joint, and every joint whose remainder
/// is above twice the floor has a line saying where it lies. Without
/// `--repeats` the floor comes from first differences, named a lower bound
/// on every joint (the reader low-passed the runs).
#[test]
fn the_kukas_diagnosis_measures_against_its_repeatability() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4");
    let s = |p: &str| root.join(p).to_str().unwrap().to_string();
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.json");
    let o = bin()
        .args(["identify", "--robot", &s("kuka_lwr4.urdf")])
        .args(["--data", &s("data/measurements_1.npz")])
        .args(["--data", &s("data/measurements_2.npz")])
        .args(["--constraints", "ellipsoid", "--regularizer", "entropic"])
        .args(["--weight", "1e-2", "--json"])
        .args(["--friction", "viscous,coulomb,offset,load,stribeck"])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::write(&model, &o.stdout).unwrap();
    let diagnose = |repeats: bool| {
        let mut c = bin();
        c.args(["diagnose", "--robot", &s("kuka_lwr4.urdf"), "--json"])
            .args(["--nominal", model.to_str().unwrap()])
            .args(["--data", &s("data/measurements_3.npz")]);
        if repeats {
            c.args([
                "--repeats",
                &s("data/measurements_1.npz"),
                &s("data/measurements_2.npz"),
            ]);
        }
        let o = c.output().unwrap();
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let v = diagnose(true);
    assert_eq!(
        v["noise_floor_source"]["kind"], "repeats",
        "{}",
        v["noise_floor_source"]
    );
    let floor: Vec<f64> = serde_json::from_value(v["noise_floor"].clone()).unwrap();
    let want = [0.146, 0.179, 0.186, 0.156, 0.055, 0.024, 0.010];
    for (f, w) in floor.iter().zip(want) {
        assert!((f - w).abs() < 0.005, "{floor:?} vs {want:?}");
    }
    let gap: Vec<f64> = serde_json::from_value(v["gap_closed"].clone()).unwrap();
    assert!(gap.iter().all(|g| (0.0..=1.0).contains(g)), "{gap:?}");
    let last: Vec<f64> = serde_json::from_value(v["heldout_rms_final"].clone()).unwrap();
    let lines: Vec<String> = serde_json::from_value(v["unexplained_where"].clone()).unwrap();
    for (i, (l, f)) in last.iter().zip(&floor).enumerate() {
        let joint = format!("lwr_{i}_joint");
        assert!(
            *l <= 2.0 * f || lines.iter().any(|x| x.starts_with(&joint)),
            "{joint}: {lines:?}"
        );
    }
    let v = diagnose(false);
    let low: Vec<String> =
        serde_json::from_value(v["noise_floor_source"]["low_passed"].clone()).unwrap();
    assert_eq!(low.len(), 7, "{}", v["noise_floor_source"]);
}

/// The diagnosis' claim holds on the real KUKA: against the default model
/// identified on runs 1–2, with runs 1, 2 and 3 as files (fitted on runs
/// 1–2, held out on run 3), the effects it accepts — its model file's
/// friction terms, and its fitted effects held (`--with-effects`) — added
/// to `identify` on runs 1–2 (against a viscous + Coulomb nominal) lower run 3's error by at least 75 % of the
/// reduction the diagnosis claimed (measured 2026-12-06: claimed 0.549 →
/// 0.402 N·m mean, `offset` and `link_inertia` accepted; identify with the
/// offset term 0.393, 106 % of it; docs/diagnosis.md).
#[test]
fn the_diagnosis_claim_holds_when_its_effects_are_added_to_identify() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4");
    let s = |p: &str| root.join(p).to_str().unwrap().to_string();
    let dir = std::env::temp_dir().join(format!("momentlmi-claim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |k: u32| s(&format!("data/measurements_{k}.npz"));
    let json = |args: &[&str]| -> serde_json::Value {
        let o = bin().args(args).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let urdf = s("kuka_lwr4.urdf");
    let (r1, r2, r3) = (run(1), run(2), run(3));
    let identify = |extra: &[&str]| -> f64 {
        let mut a = vec!["identify", "--robot", &urdf, "--data", &r1, "--data", &r2];
        a.extend(["--validate", &r3, "--json"]);
        a.extend(extra);
        let v = json(&a);
        let rms = v["validation_rms"].as_array().unwrap();
        rms.iter().map(|x| x.as_f64().unwrap()).sum::<f64>() / rms.len() as f64
    };
    let nominal = dir.join("default.json");
    // the nominal a user wrote: viscous + Coulomb (the default chooses its
    // law from the data, and leaves a diagnosis less to find)
    let vc = ["--friction", "viscous,coulomb"];
    let mut a = vec![
        "identify", "--robot", &urdf, "--data", &r1, "--data", &r2, "--json",
    ];
    a.extend(vc);
    std::fs::write(&nominal, json(&a).to_string()).unwrap();
    let model_out = dir.join("claim.json");
    let (nom, out) = (nominal.to_str().unwrap(), model_out.to_str().unwrap());
    a = vec!["diagnose", "--robot", &urdf, "--nominal", nom, "--json"];
    a.extend(["--data", &r1, "--data", &r2, "--data", &r3]);
    a.extend(["--repeats", &r1, &r2, "--model-out", out]);
    let d = json(&a);
    assert_eq!(d["folds"], "3 files");
    let mean = |k: &str| {
        let v = d[k].as_array().unwrap();
        v.iter().map(|x| x.as_f64().unwrap()).sum::<f64>() / v.len() as f64
    };
    let claimed = mean("heldout_rms_nominal") - mean("heldout_rms_final");
    assert!(claimed > 0.05, "the diagnosis claims {claimed} N·m");
    // the model file's friction terms, and its fitted effects held
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&model_out).unwrap()).unwrap();
    let terms: Vec<&str> = (m["friction"].as_object().unwrap().keys())
        .map(String::as_str)
        .filter(|k| *k != "stribeck_velocity")
        .collect();
    let terms = terms.join(",");
    let mut extra = vec!["--friction", terms.as_str()];
    if m["effects"].as_array().is_some_and(|e| !e.is_empty()) {
        extra.extend(["--with-effects", out]);
    }
    let before = identify(&vc);
    let after = identify(&extra);
    assert!(
        (before - mean("heldout_rms_nominal")).abs() < 1e-3,
        "the nominal model's run-3 error {before} against the diagnosis' {}",
        mean("heldout_rms_nominal")
    );
    assert!(
        before - after >= 0.75 * claimed,
        "claimed {claimed:.3} N·m, identify with the effects ({extra:?}) gives {:.3}",
        before - after
    );
}
