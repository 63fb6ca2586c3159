//! Training logs reduced while they are read (`identify::reduce_logs`)
//! against the same samples read whole and reduced (`reduce_samples`).

use momentlmi::data::{Dataset, ReadOptions};
use momentlmi::dynamics::cheetah3;
use momentlmi::effects::simulate;
use momentlmi::identify::{Identification, IdentifyError, Level, reduce_logs, reduce_samples};
use momentlmi::sim::{Effects, SimConfig};
use std::path::Path;

fn leg_data(seconds: f64, seed: u64) -> Dataset {
    let leg = cheetah3::description();
    let fx = Effects::new(["rotor_inertia", "coulomb", "viscous"]);
    simulate(
        &leg,
        &SimConfig::for_robot(&leg, seconds, fx, seed),
        |_, _| {},
    )
    .unwrap()
}

/// Largest |a − b| over the largest |b|.
fn rel(a: &faer::Mat<f64>, b: &faer::Mat<f64>) -> f64 {
    let (mut d, mut m) = (0.0f64, 0.0f64);
    for j in 0..b.ncols() {
        for i in 0..b.nrows() {
            d = d.max((a[(i, j)] - b[(i, j)]).abs());
            m = m.max(b[(i, j)].abs());
        }
    }
    d / m
}

/// Two CSV files (6 s and 4 s of the leg) streamed: the Gram matrix and
/// each joint's equal those of the samples read whole to 1e-12, and the
/// identification from them equals the one from the whole samples.
#[test]
fn a_streamed_reduction_equals_the_whole_one() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (leg_data(6.0, 3), leg_data(4.0, 4));
    let (pa, pb) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    a.write_csv(&pa).unwrap();
    b.write_csv(&pb).unwrap();
    let model = cheetah3::model();
    let paths: [&Path; 2] = [&pa, &pb];
    let opts = ReadOptions::default();
    let streamed = reduce_logs(&model, &paths, &opts).unwrap().unwrap();
    assert_eq!(streamed.files.len(), 2);
    assert!(streamed.files.iter().all(|f| f.taken_as_prepared));
    let whole = momentlmi::data::read_logs(&paths, &cheetah3::model().joint_names(), &opts)
        .unwrap()
        .data;
    assert_eq!(whole.len(), a.len() + b.len());
    let red = reduce_samples(&model, &whole.q, &whole.qd, &whole.qdd, &whole.tau, 256).unwrap();
    assert_eq!(streamed.reduced.samples, red.samples);
    let r = &streamed.reduced;
    assert!(
        rel(&r.gram, &red.gram) < 1e-12,
        "{}",
        rel(&r.gram, &red.gram)
    );
    assert_eq!(r.joint_grams.len(), 3);
    for (x, y) in r.joint_grams.iter().zip(&red.joint_grams) {
        assert!(rel(x, y) < 1e-12);
    }
    let leg = cheetah3::description();
    let id = Identification::for_robot(&leg, Level::Ellipsoid, 1e-4).unwrap();
    let one = id.fit_streamed(r).unwrap();
    let two = id.fit_reduced(&whole, &red).unwrap();
    assert_eq!(one.training_samples, two.training_samples);
    let (t, u) = (&one.timings, &two.timings);
    assert!(t.reduce_s > 0.0 && t.solve_s > 0.0 && t.total_s >= t.reduce_s + t.solve_s);
    assert!(u.solve_s > 0.0 && u.total_s >= u.solve_s && t.validate_s == 0.0);
    for (x, y) in one.theta.iter().zip(&two.theta) {
        assert!((x - y).abs() < 1e-6 * (1.0 + y.abs()), "{x} vs {y}");
    }
    for (x, y) in one.training_rms.iter().zip(&two.training_rms) {
        assert!((x - y).abs() < 1e-9, "{x} vs {y}");
    }
}

/// A raw log (no q̈) is not streamed; a bad value in the second file is
/// an error naming that file, its row and column.
#[test]
fn raw_logs_are_left_to_the_whole_reader_and_errors_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let model = cheetah3::model();
    let d = leg_data(2.0, 5);
    let (ok, bad, raw) = (
        dir.path().join("ok.csv"),
        dir.path().join("bad.csv"),
        dir.path().join("raw.csv"),
    );
    d.write_csv(&ok).unwrap();
    let mut lines: Vec<String> = d.to_csv().lines().map(str::to_string).collect();
    lines[1500] = lines[1500].replacen(',', ",nan", 1);
    std::fs::write(&bad, lines.join("\n")).unwrap();
    let e = reduce_logs(
        &model,
        &[ok.as_path(), bad.as_path()],
        &ReadOptions::default(),
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, IdentifyError::Data(_)), "{msg}");
    assert!(
        msg.contains("bad.csv") && msg.contains("row 1500") && msg.contains("q_abad"),
        "{msg}"
    );
    let no_qdd: String = d
        .to_csv()
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            [&f[..7], &f[10..]].concat().join(",") + "\n"
        })
        .collect();
    std::fs::write(&raw, no_qdd).unwrap();
    let none = reduce_logs(
        &model,
        &[ok.as_path(), raw.as_path()],
        &ReadOptions::default(),
    );
    assert!(none.unwrap().is_none());
    // not a regular file (a pipe, a device): left to the whole reader, which
    // reads it once
    #[cfg(unix)]
    {
        let dev = std::path::Path::new("/dev/null");
        let none = reduce_logs(&model, &[dev], &ReadOptions::default());
        assert!(none.unwrap().is_none());
    }
}
