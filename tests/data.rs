//! Data files, the filter and differentiator, and RNEA against Euler–Lagrange.

use momentlmi::data::Dataset;
use momentlmi::data::ReadOptions;
use momentlmi::data::filter::{Biquad, differentiate, filtfilt};
use momentlmi::dynamics::{Data, cheetah3, crba, energy, rnea};

const J: [&str; 3] = ["abad", "hip", "knee"];

#[test]
fn csv_round_trip_any_column_order_and_extra_columns() {
    let text = "extra,tau_knee,t,q_abad,q_hip,q_knee,qd_abad,qd_hip,qd_knee,qdd_abad,qdd_hip,qdd_knee,tau_abad,tau_hip\n\
                9,3,0.0,0.1,0.2,0.3,1,2,3,4,5,6,1,2\n9,3.5,0.001,0.2,0.3,0.4,1,2,3,4,5,6,1.5,2.5\n";
    let d = Dataset::parse_csv(text, "x.csv", &J, ReadOptions::default()).unwrap();
    assert_eq!(d.len(), 2);
    assert_eq!(d.tau[1], vec![1.5, 2.5, 3.5]);
    assert_eq!(d.qdd[0], vec![4.0, 5.0, 6.0]);
    let back = Dataset::parse_csv(&d.to_csv(), "y.csv", &J, ReadOptions::default()).unwrap();
    assert_eq!(back, d);
}

#[test]
fn bad_rows_are_named() {
    let head = "t,q_abad,q_hip,q_knee,qd_abad,qd_hip,qd_knee,tau_abad,tau_hip,tau_knee\n";
    let ok = "0,0,0,0,0,0,0,0,0,0\n";
    let cases = [
        (
            format!("{head}{ok}0.001,0,nan,0,0,0,0,0,0,0\n"),
            "row 2, column 'q_hip': non-finite",
        ),
        (
            format!("{head}{ok}0.001,0,inf,0,0,0,0,0,0,0\n"),
            "row 2, column 'q_hip'",
        ),
        (
            format!("{head}{ok}0.001,0,abc,0,0,0,0,0,0,0\n"),
            "row 2, column 'q_hip': 'abc' is not a number",
        ),
        (
            format!("{head}{ok}0.002,1,0,0,0,0,0,0,0,0\n0.001,2,0,0,0,0,0,0,0,0\n"),
            "row 3, column 't': time 0.001 goes back from 0.002",
        ),
        (format!("{head}{ok}0.001,0,0,0\n"), "row 2: has 4 fields"),
        ("t,q_abad\n0,0\n".to_string(), "missing column 'q_hip'"),
        (head.to_string(), "no data rows"),
    ];
    for (text, want) in cases {
        let e = Dataset::parse_csv(&text, "bad.csv", &J, ReadOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(want) && e.contains("bad.csv"), "{e}");
    }
}

#[test]
fn filter_frequency_response_matches_the_design() {
    let fs = 1000.0;
    let fc = 20.0;
    for f in [2.0, 10.0, 20.0, 40.0, 80.0] {
        let t: Vec<f64> = (0..4000).map(|k| k as f64 / fs).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|&t| (2.0 * std::f64::consts::PI * f * t).sin())
            .collect();
        let y = filtfilt(&x, fc, fs);
        // amplitude and phase in the middle (away from the ends): least squares on sin/cos
        let (mut ss, mut sc) = (0.0, 0.0);
        for k in 1000..3000 {
            let w = 2.0 * std::f64::consts::PI * f * t[k];
            ss += y[k] * w.sin();
            sc += y[k] * w.cos();
        }
        let amp = 2.0 * (ss * ss + sc * sc).sqrt() / 2000.0;
        let want = Biquad::filtfilt_gain(fc, fs, f);
        assert!((amp - want).abs() < 0.01, "f = {f}: gain {amp} vs {want}");
        assert!((sc / ss).abs() < 0.01, "zero phase at f = {f}");
    }
    // −6 dB (gain ½) exactly at the cut-off
    assert!((Biquad::filtfilt_gain(fc, fs, fc) - 0.5).abs() < 1e-12);
}

#[test]
fn differentiation_of_known_signals() {
    let fs = 1000.0;
    let t: Vec<f64> = (0..3000).map(|k| k as f64 / fs).collect();
    // sin(ωt) → ω cos(ωt), within the central-difference error ω³h²/6
    let w = 2.0 * std::f64::consts::PI * 1.5;
    let x: Vec<f64> = t.iter().map(|&t| (w * t).sin()).collect();
    let d = differentiate(&x, &t);
    for k in 1..2999 {
        assert!((d[k] - w * (w * t[k]).cos()).abs() < w.powi(3) / fs / fs);
    }
    // a ramp and a parabola survive filtering + differentiation, ends included
    let p: Vec<f64> = t.iter().map(|&t| 3.0 * t * t - t).collect();
    let dp = differentiate(&filtfilt(&p, 30.0, fs), &t);
    for k in 50..2950 {
        assert!(
            (dp[k] - (6.0 * t[k] - 1.0)).abs() < 1e-3,
            "k = {k}: {}",
            dp[k]
        );
    }
}

#[test]
fn qdd_is_estimated_when_absent() {
    let fs = 1000.0;
    let mut s =
        String::from("t,q_abad,q_hip,q_knee,qd_abad,qd_hip,qd_knee,tau_abad,tau_hip,tau_knee\n");
    let w = 3.0;
    for k in 0..2000 {
        let t = k as f64 / fs;
        s += &format!(
            "{t},{},0,0,{},0,0,0,0,0\n",
            (w * t).sin(),
            w * (w * t).cos()
        );
    }
    let d = Dataset::parse_csv(&s, "x.csv", &J, ReadOptions::default()).unwrap();
    for k in 100..1900 {
        let t = d.t[k];
        assert!(
            (d.qdd[k][0] + w * w * (w * t).sin()).abs() < 0.02,
            "k = {k}"
        );
    }
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

#[test]
fn rnea_with_rotors_matches_euler_lagrange() {
    let m = cheetah3::model();
    let mut d = Data::new(&m);
    let states = [
        ([0.3, -0.9, 1.7], [1.0, -2.0, 3.0], [5.0, -3.0, 10.0]),
        ([-1.0, 2.0, -0.5], [-4.0, 0.5, 8.0], [0.0, 20.0, -7.0]),
    ];
    for (q, qd, qdd) in states {
        let a = rnea(&m, &mut d, &q, &qd, &qdd).unwrap().clone();
        let b = lagrange_torque(&q, &qd, &qdd);
        for i in 0..3 {
            assert!(
                (a[i] - b[i]).abs() < 1e-5 * (1.0 + b[i].abs()),
                "joint {i}: RNEA {} vs Lagrange {}",
                a[i],
                b[i]
            );
        }
    }
}

#[test]
fn io_errors_keep_their_source_and_outputs_are_whole() {
    use momentlmi::data::{DataError, write_with_record};
    use std::error::Error;
    let e = Dataset::read_csv(
        std::path::Path::new("/nonexistent/x.csv"),
        &J,
        ReadOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(e, DataError::Io { .. }), "{e:?}");
    let src = e.source().expect("the io::Error is kept as the source");
    assert!(src.downcast_ref::<std::io::Error>().is_some());
    assert!(e.to_string().contains("/nonexistent/x.csv"));
    // a cut-off at or above the file's Nyquist frequency is an error, not an
    // unfiltered q̈
    let mut s =
        String::from("t,q_abad,qd_abad,q_hip,qd_hip,q_knee,qd_knee,tau_abad,tau_hip,tau_knee\n");
    for k in 0..50 {
        let x = (k as f64 * 0.3).sin();
        s += &format!("{},{x},0,{x},0,{x},0,{x},0,0\n", k as f64 * 0.02);
    }
    let at = |c: f64| ReadOptions {
        cutoff_hz: Some(c),
        ..Default::default()
    };
    let e = Dataset::parse_csv(&s, "slow.csv", &J, at(30.0)).unwrap_err();
    assert!(matches!(e, DataError::Cutoff { .. }), "{e}");
    assert!(
        e.to_string().contains("slow.csv") && e.to_string().contains("25 Hz"),
        "{e}"
    );
    // the data file and its record would be one file: refused, nothing written
    let d = Dataset::parse_csv(&s, "slow.csv", &J, at(5.0)).unwrap();
    let dir = std::env::temp_dir().join(format!("momentlmi-data-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let clash = dir.join("x.json");
    assert!(matches!(
        write_with_record(&d, &clash, &"r"),
        Err(DataError::Output { .. })
    ));
    assert!(!clash.exists());
    let ok = dir.join("x.csv");
    let rec = write_with_record(&d, &ok, &"made by a test").unwrap();
    assert_eq!(rec, dir.join("x.json"));
    let back = Dataset::read_csv(&ok, &J, at(5.0)).unwrap();
    assert_eq!(back.len(), d.len());
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}
