//! `momentlmi diagnose --model-out`: the model file it writes makes
//! `predict` give the held-out error the diagnosis reported (and `export`
//! and `identify --prior` take it); written onto
//! one of its inputs, it is refused (exit 2) and nothing is written.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_momentlmi"))
}

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("momentlmi-dm-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 4 s leg log with a 10 % torque gain (seed `seed`) at `p`.
fn leg_log(p: &Path, seed: &str) {
    let o = bin()
        .args(["simulate", "--robot", "cheetah3-leg", "--seconds", "4"])
        .args(["--effects", "torque_gain", "--seed", seed, "--out"])
        .arg(p)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `diagnose` of the leg against its true model on the files `a` and `b`,
/// the model written to `model_out`.
fn diagnose(a: &Path, b: &Path, model_out: &Path) -> Command {
    let mut c = bin();
    c.args(["diagnose", "--robot", "cheetah3-leg", "--nominal", "true"])
        .arg("--data")
        .arg(a)
        .arg("--data")
        .arg(b)
        .arg("--model-out")
        .arg(model_out);
    c
}

/// The columns of a CSV whose header names start with `prefix`, by name.
fn columns(p: &Path, prefix: &str) -> Vec<(String, Vec<f64>)> {
    let text = std::fs::read_to_string(p).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header.iter().enumerate())
        .filter(|(_, h)| h.starts_with(prefix))
        .map(|(c, h)| (h.to_string(), rows.iter().map(|r| r[c]).collect()))
        .collect()
}

/// `predict` with the model file `m` on the held-out file `b` gives the
/// held-out RMS the report gave per joint (`heldout_rms_final`, to 1e-6).
fn predict_gives_the_reported(report: &serde_json::Value, m: &Path, b: &Path, p: &Path) {
    let reported: Vec<f64> = (report["heldout_rms_final"].as_array().unwrap().iter())
        .map(|x| x.as_f64().unwrap())
        .collect();
    let o = bin()
        .args(["predict", "--robot", "cheetah3-leg", "--params"])
        .arg(m)
        .arg("--data")
        .arg(b)
        .arg("--out")
        .arg(p)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (measured, predicted) = (columns(b, "tau_"), columns(p, "tau_"));
    assert_eq!(measured.len(), reported.len());
    for (i, ((name, tau), (pname, hat))) in measured.iter().zip(&predicted).enumerate() {
        assert_eq!(name, pname);
        let ms = (tau.iter().zip(hat))
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            / tau.len() as f64;
        assert!(
            (ms.sqrt() - reported[i]).abs() <= 1e-6,
            "{name}: predict {} against the reported {}",
            ms.sqrt(),
            reported[i]
        );
    }
}

#[test]
fn predict_with_the_model_out_gives_the_reported_heldout_error() {
    let d = dir("claim");
    let (a, b, m) = (d.join("a.csv"), d.join("b.csv"), d.join("m.json"));
    let c = d.join("c.csv");
    leg_log(&a, "1");
    leg_log(&c, "7");
    leg_log(&b, "2");
    // three files: one fold each, the last (b) held out
    let o = diagnose(&a, &c, &m)
        .arg("--data")
        .arg(&b)
        .arg("--json")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(report["folds"], "3 files");
    // the held-out part is the last file: predicted with the model file
    predict_gives_the_reported(&report, &m, &b, &d.join("p.csv"));
    let reported: Vec<f64> = (report["heldout_rms_final"].as_array().unwrap().iter())
        .map(|x| x.as_f64().unwrap())
        .collect();
    // the model differs from the nominal one: the claim is not the nominal's
    let nominal: Vec<f64> = (report["heldout_rms_nominal"].as_array().unwrap().iter())
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(
        nominal
            .iter()
            .zip(&reported)
            .any(|(x, y)| (x - y).abs() > 1e-3)
    );
}

#[test]
fn a_model_out_onto_an_input_is_refused_and_nothing_is_written() {
    let d = dir("onto");
    let (a, b) = (d.join("a.csv"), d.join("b.csv"));
    leg_log(&a, "3");
    leg_log(&b, "4");
    let before = std::fs::read(&b).unwrap();
    let out = d.join("report");
    let o = diagnose(&a, &b, &b)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("b.csv"), "{err}");
    assert_eq!(std::fs::read(&b).unwrap(), before);
    assert!(!out.exists(), "--out was written");
    // a record simulate wrote beside a data file, a folder, a missing
    // folder, inside --out: each refused before the run, nothing written
    let record = d.join("b.json");
    let record_before = std::fs::read(&record).unwrap();
    let missing = d.join("nowhere").join("m.json");
    let inside = out.join("m.json");
    for (target, needle) in [
        (&record, "also an input"),
        (&d, "is a folder"),
        (&missing, "folder does not exist"),
        (&inside, "inside --out"),
    ] {
        let o = diagnose(&a, &b, target)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{}", target.display());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{}: {err}", target.display());
        assert!(!out.exists() && !missing.exists());
    }
    assert_eq!(std::fs::read(&record).unwrap(), record_before);
}

/// With `--nominal-data` (the nominal's bodies refit with the law on
/// those data and the fitting part) the claim holds as well: `predict`
/// with the model file gives the reported held-out error; a `--model-out`
/// onto the nominal's data file is refused (exit 2) and nothing written.
#[test]
fn the_claim_holds_with_the_nominals_data_and_they_are_protected() {
    let d = dir("nomdata");
    let (a, b, c, e) = (
        d.join("a.csv"),
        d.join("b.csv"),
        d.join("c.csv"),
        d.join("e.csv"),
    );
    let m = d.join("m.json");
    for (p, seed) in [(&a, "1"), (&c, "7"), (&b, "2"), (&e, "9")] {
        leg_log(p, seed);
    }
    let before = std::fs::read(&e).unwrap();
    let o = diagnose(&a, &c, &e)
        .arg("--data")
        .arg(&b)
        .arg("--nominal-data")
        .arg(&e)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("e.csv") && err.contains("--model-out"),
        "{err}"
    );
    assert_eq!(std::fs::read(&e).unwrap(), before);
    let o = diagnose(&a, &c, &m)
        .arg("--data")
        .arg(&b)
        .arg("--nominal-data")
        .arg(&e)
        .arg("--json")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    predict_gives_the_reported(&report, &m, &b, &d.join("p.csv"));
}

/// `identify --with-effects FILE` holds a model file's fitted effects: with
/// zero coefficients it fits what a plain identify fits (the plumbing
/// changes nothing else), with a gain it fits other torques; the
/// identified model file carries the effects; a file without effects is
/// refused (exit 2, named).
#[test]
fn identify_with_effects_holds_them_and_carries_them() {
    let d = dir("with");
    let (a, b) = (d.join("a.csv"), d.join("b.csv"));
    leg_log(&a, "5");
    leg_log(&b, "6");
    let identify = |extra: &[&Path]| -> serde_json::Value {
        let mut c = bin();
        c.args(["identify", "--robot", "cheetah3-leg", "--json", "--data"])
            .arg(&a)
            .arg("--validate")
            .arg(&b);
        if let Some(f) = extra.first() {
            c.arg("--with-effects").arg(f);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let plain = identify(&[]);
    let base = d.join("base.json");
    std::fs::write(&base, plain.to_string()).unwrap();
    let with_gain = |g: f64, name: &str| {
        let mut m = plain.clone();
        m["effects"] = serde_json::json!([{
            "effect": "torque_gain", "key": {},
            "columns": ["abad#0", "hip#0", "knee#0"],
            "coefficients": [g, 0.0, -g]
        }]);
        let p = d.join(name);
        std::fs::write(&p, m.to_string()).unwrap();
        p
    };
    let rms = |v: &serde_json::Value| -> Vec<f64> {
        (v["validation_rms"].as_array().unwrap().iter())
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let zero = identify(&[&with_gain(0.0, "zero.json")]);
    for (x, y) in rms(&zero).iter().zip(rms(&plain)) {
        assert!((x - y).abs() < 1e-9, "{x} vs {y}");
    }
    assert_eq!(zero["effects"][0]["effect"], "torque_gain");
    // gains of +10 % and −10 % on two joints (one on every joint would be
    // a scaling of every parameter, which the fit absorbs)
    let gain = identify(&[&with_gain(0.1, "gain.json")]);
    assert_eq!(gain["effects"][0]["coefficients"][0], 0.1);
    let params = |v: &serde_json::Value| -> Vec<f64> {
        (v["bodies"].as_array().unwrap().iter())
            .flat_map(|b| b["params"].as_array().unwrap().clone())
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let (p0, p1) = (params(&plain), params(&gain));
    let top = p0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let moved = (p0.iter().zip(&p1)).any(|(x, y)| (x - y).abs() > 1e-3 * top);
    assert!(moved, "a held gain changed no parameter");
    // the identified file is a model file predict applies the effects of
    let fx = d.join("fx.json");
    std::fs::write(&fx, gain.to_string()).unwrap();
    let o = bin()
        .args(["predict", "--robot", "cheetah3-leg", "--params"])
        .arg(&fx)
        .arg("--data")
        .arg(&b)
        .arg("--out")
        .arg(d.join("p.csv"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = bin()
        .args(["identify", "--robot", "cheetah3-leg", "--data"])
        .arg(&a)
        .arg("--with-effects")
        .arg(&base)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("holds no fitted effects"));
}
