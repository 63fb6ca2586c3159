//! The CSV form of a floating-base log: written and read back equal, and
//! bad files named by row, column or frame.

use momentlmi::data::floating_csv::floating_from_csv;
use momentlmi::dynamics::urdf::free_flyer_from_urdf_file;
use momentlmi::dynamics::{Model, WrenchFrame};
use momentlmi::sim::floating::{SuspendedConfig, simulate_suspended};
use std::path::Path;

fn solo() -> Model {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    free_flyer_from_urdf_file(&root.join("robots/solo12/solo12.urdf"), None).unwrap()
}

fn short_log(ff: &Model) -> momentlmi::data::Dataset {
    let cfg = SuspendedConfig {
        seconds: 0.1,
        ..SuspendedConfig::default()
    };
    simulate_suspended(ff, &cfg).unwrap()
}

#[test]
fn a_log_round_trips_through_csv() {
    let ff = solo();
    let mut log = short_log(&ff);
    // a second contact, world-aligned, to carry both kinds of column
    let mut plate = log.contacts[0].clone();
    plate.frame = "HR_FOOT".into();
    plate.expressed = WrenchFrame::WorldAligned;
    log.contacts.push(plate);
    let text = log.to_csv();
    let header = text.lines().next().unwrap();
    assert!(header.starts_with("t,base_x,base_y,base_z,base_qx,base_qy,base_qz,base_qw,base_vx"));
    assert!(header.contains(",force_base_link_x,") && header.contains(",world_moment_HR_FOOT_z"));
    let back = floating_from_csv(&ff, &text, "log.csv").unwrap();
    assert_eq!(back, log);
    back.check(&ff).unwrap();
}

#[test]
fn columns_in_any_order_and_a_point_contact() {
    let ff = solo();
    let log = short_log(&ff);
    let text = log.to_csv();
    // reverse the columns, drop the moments: a point contact
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    let keep: Vec<usize> = (0..rows[0].len())
        .rev()
        .filter(|&c| !rows[0][c].starts_with("moment_"))
        .collect();
    let text: String = rows
        .iter()
        .map(|r| keep.iter().map(|&c| r[c]).collect::<Vec<_>>().join(",") + "\n")
        .collect();
    let back = floating_from_csv(&ff, &text, "log.csv").unwrap();
    assert_eq!(back.q, log.q);
    assert_eq!(back.contacts[0].wrench[2], log.contacts[0].wrench[2]);
    assert_eq!(back.contacts[0].wrench[5], 0.0);
}

#[test]
fn bad_files_are_named() {
    let ff = solo();
    let text = short_log(&ff).to_csv();
    let err = |t: &str| {
        floating_from_csv(&ff, t, "log.csv")
            .unwrap_err()
            .to_string()
    };
    // a missing base column
    let e = err(&text.replacen("base_qw", "base_qq", 1));
    assert!(e.contains("'base_qq'"), "{e}");
    // a contact frame that does not exist
    let e = err(&text.replace("force_base_link", "force_harness"));
    assert!(
        e.contains("'force_harness_x'") && e.contains("contact frame 'harness'"),
        "{e}"
    );
    // a wrench column missing
    let e = err(&text.replace(",force_base_link_y", ",moment_x_y"));
    assert!(e.contains("moment_x_y"), "{e}");
    // a moment with one axis only: the others are missing, not zero
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    let keep: Vec<usize> = (0..rows[0].len())
        .filter(|&c| !matches!(rows[0][c], "moment_base_link_y" | "moment_base_link_z"))
        .collect();
    let partial: String = rows
        .iter()
        .map(|r| keep.iter().map(|&c| r[c]).collect::<Vec<_>>().join(",") + "\n")
        .collect();
    let e = err(&partial);
    assert!(e.contains("missing column 'moment_base_link_y'"), "{e}");
    // a value that is not a number, named by row and column
    let e = err(&with_cell(&text, 3, "base_qx", "abc"));
    assert!(
        e.contains("row 3") && e.contains("'base_qx'") && e.contains("'abc'"),
        "{e}"
    );
    // a quaternion that is not of unit norm: read, then refused by check
    let log = floating_from_csv(&ff, &with_cell(&text, 2, "base_qw", "0.5"), "log.csv").unwrap();
    let e = log.check(&ff).unwrap_err().to_string();
    assert!(e.contains("sample 1") && e.contains("norm"), "{e}");
}

/// The log's text with data row `row`'s `column` set to `value`.
fn with_cell(text: &str, row: usize, column: &str, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let c = lines[0].split(',').position(|h| h == column).unwrap();
    let mut fields: Vec<String> = lines[row].split(',').map(str::to_string).collect();
    fields[c] = value.into();
    lines[row] = fields.join(",");
    lines.join("\n") + "\n"
}

#[test]
fn values_beyond_the_readers_limits_and_time_going_back_are_named() {
    let ff = solo();
    let text = short_log(&ff).to_csv();
    let err = |t: &str| {
        floating_from_csv(&ff, t, "log.csv")
            .unwrap_err()
            .to_string()
    };
    // the limits every fixed-base reader applies (±1e8; time ±1e12)
    for (column, value) in [
        ("base_wx", "1e200"),
        ("force_base_link_z", "1e300"),
        ("base_vy", "-2e8"),
        ("t", "1e13"),
        ("base_wz", "inf"),
    ] {
        let e = err(&with_cell(&text, 5, column, value));
        assert!(
            e.contains("log.csv") && e.contains("row 5") && e.contains(&format!("'{column}'")),
            "{column}: {e}"
        );
        assert!(e.len() < 200, "a number written in full: {e}");
    }
    // a time that does not increase, named by row
    let t2 = text
        .lines()
        .nth(2)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .to_string();
    let e = err(&with_cell(&text, 3, "t", &t2));
    assert!(
        e.contains("row 3") && e.contains("'t'") && e.contains("not after"),
        "{e}"
    );
}

#[test]
fn check_applies_the_same_limits_to_a_log_built_in_memory() {
    let ff = solo();
    let log = short_log(&ff);
    let mut wild = log.clone();
    wild.base.as_mut().unwrap().twist[4][3] = 1e200; // v's entry 3

    let e = wild.check(&ff).unwrap_err().to_string();
    assert!(
        e.contains("v: sample 4, entry 3") && e.contains("1e200"),
        "{e}"
    );
    let mut back = log.clone();
    back.t[3] = back.t[1];
    let e = back.check(&ff).unwrap_err().to_string();
    assert!(e.contains("t: sample 3") && e.contains("not after"), "{e}");
    log.check(&ff).unwrap();
}

#[test]
fn logs_are_laid_end_to_end_as_fixed_base_files_are() {
    let ff = solo();
    let one = short_log(&ff);
    let mut logs = vec![one.clone(), one.clone(), one];
    momentlmi::data::base::lay_end_to_end(&mut logs);
    let t: Vec<f64> = logs.iter().flat_map(|l| l.t.iter().copied()).collect();
    assert!(
        t.windows(2).all(|w| w[1] > w[0]),
        "times increase across files"
    );
    let step = logs[0].t[1] - logs[0].t[0];
    let last = *logs[0].t.last().unwrap();
    assert!((logs[1].t[0] - (last + step)).abs() < 1e-12);
    // a log that already follows is left as it is
    let mut later = logs[0].clone();
    later.t.iter_mut().for_each(|x| *x += 100.0);
    let mut pair = vec![logs[0].clone(), later.clone()];
    momentlmi::data::base::lay_end_to_end(&mut pair);
    assert_eq!(pair[1].t, later.t);
}

#[test]
fn a_line_without_end_and_a_huge_column_name_make_short_errors() {
    let ff = solo();
    // no line break in 17 MiB: refused at the fixed-base reader's line limit
    let one_line = "a".repeat((1 << 24) + 10);
    let e = floating_from_csv(&ff, &one_line, "zero.csv")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("zero.csv") && e.contains("a line longer than"),
        "{e}"
    );
    assert!(e.len() < 300, "{} bytes", e.len());
    // a 1 MB column name is quoted by its start and length
    let text = short_log(&ff).to_csv();
    let name = "x".repeat(1 << 20);
    let e = err_of(&ff, &text.replacen("base_qw", &name, 1));
    assert!(
        e.contains("bytes)") && e.len() < 600,
        "{} bytes: {}",
        e.len(),
        &e[..300]
    );
}

fn err_of(ff: &Model, text: &str) -> String {
    floating_from_csv(ff, text, "log.csv")
        .unwrap_err()
        .to_string()
}

/// A NumPy `.npz` archive of a log's CSV columns (one float64 1-D array
/// per column, in the CSV's order but `t` last: the reader puts it first).
fn npz_of(text: &str, path: &Path) {
    use npyz::WriterBuilder;
    use std::io::Write;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<f64>> =
        (lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())).collect();
    let mut z = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    let opts = zip::write::SimpleFileOptions::default();
    let order = (1..header.len()).chain([0]);
    for c in order {
        let values: Vec<f64> = rows.iter().map(|r| r[c]).collect();
        let mut bytes = vec![];
        let mut w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&[values.len() as u64])
            .writer(&mut bytes)
            .begin_nd()
            .unwrap();
        w.extend(values.iter().copied()).unwrap();
        w.finish().unwrap();
        z.start_file(format!("{}.npy", header[c]), opts).unwrap();
        z.write_all(&bytes).unwrap();
    }
    z.finish().unwrap();
}

#[test]
fn a_numpy_archive_of_the_columns_reads_as_its_csv_and_identifies_the_same() {
    use momentlmi::data::floating_csv::read_floating_npz;
    use momentlmi::identify::{Identification, Rows, reduce_floating};
    let ff = solo();
    let cfg = SuspendedConfig {
        seconds: 5.0,
        ..SuspendedConfig::default()
    };
    let log = simulate_suspended(&ff, &cfg).unwrap();
    let text = log.to_csv();
    let dir = std::env::temp_dir().join(format!("momentlmi-floating-npz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("log.npz");
    npz_of(&text, &path);
    let from_csv = floating_from_csv(&ff, &text, "log.csv").unwrap();
    let from_npz = read_floating_npz(&ff, &path, 1 << 30).unwrap();
    assert_eq!(from_npz, from_csv);
    let fit = |l| {
        let red = reduce_floating(&ff, l, Rows::Base).unwrap();
        Identification::for_free_flyer(&ff, Rows::Base)
            .solve(&red)
            .unwrap()
            .theta
    };
    assert_eq!(fit(&from_npz), fit(&from_csv));
    // the memory bound is checked before the arrays past the first are read
    let e = read_floating_npz(&ff, &path, 1000).unwrap_err().to_string();
    assert!(
        e.contains("log.npz") && e.contains("values allowed in memory"),
        "{e}"
    );
    // a column the log does not have is named, as in a CSV
    let renamed = text.replacen("base_qw", "base_qq", 1);
    npz_of(&renamed, &path);
    let e = read_floating_npz(&ff, &path, 1 << 30)
        .unwrap_err()
        .to_string();
    assert!(e.contains("base_qq"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
