//! Hostile and malformed input from the command line: every case ends with
//! exit 1 or 2 and a message naming what is wrong, never a panic (101) or a
//! signal; no output holds NaN or infinity; no command overwrites a file it
//! was not told to write, and a failed command leaves no partial output.
//! The files are written by the test itself.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_momentlmi"))
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("momentlmi-hostile-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

/// Exit 1 or 2, a message on stderr containing `needle`, no panic.
fn refused(o: &Output, needle: &str, case: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    let code = o.status.code();
    assert!(
        matches!(code, Some(1 | 2)),
        "{case}: exit {code:?} (a signal has none)\n{err}"
    );
    assert!(!err.contains("panicked"), "{case}: panicked\n{err}");
    assert!(
        err.contains(needle),
        "{case}: expected '{needle}' in\n{err}"
    );
}

/// A one-link pendulum URDF (1 kg, `ixx = iyy = side`, `izz`) at `path`.
fn pendulum(path: &Path, side: &str, izz: &str) {
    std::fs::write(
        path,
        format!(
            r#"<robot name="pend"><link name="base"/><link name="arm"><inertial><mass value="1"/>
<inertia ixx="{side}" ixy="0" ixz="0" iyy="{side}" iyz="0" izz="{izz}"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
<limit lower="-2" upper="2" effort="10" velocity="5"/></joint></robot>"#
        ),
    )
    .unwrap();
}

fn no_nan(path: &Path) {
    let t = std::fs::read_to_string(path).unwrap();
    let lower = t.to_lowercase();
    assert!(
        !lower.contains("nan") && !lower.contains("inf"),
        "{}: non-finite output",
        path.display()
    );
}

/// A small data set of the built-in leg and an identified parameter file.
fn leg_data(d: &Path) -> (PathBuf, serde_json::Value) {
    let csv = d.join("leg.csv");
    let o = run(&[
        "simulate",
        "--robot",
        "cheetah3-leg",
        "--seconds",
        "2",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = run(&[
        "identify",
        "--robot",
        "cheetah3-leg",
        "--data",
        csv.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (csv, serde_json::from_slice(&o.stdout).unwrap())
}

/// `leg.csv` with one cell replaced (data row `row`, column `col`) or the
/// header changed.
fn mutate_csv(src: &Path, dst: &Path, f: impl Fn(&mut Vec<Vec<String>>)) {
    let text = std::fs::read_to_string(src).unwrap();
    let mut rows: Vec<Vec<String>> = text
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    f(&mut rows);
    let out: Vec<String> = rows.iter().map(|r| r.join(",")).collect();
    std::fs::write(dst, out.join("\n") + "\n").unwrap();
}

#[test]
fn hostile_data_and_parameter_files_are_refused_with_their_place() {
    let d = dir("data");
    let (csv, params) = leg_data(&d);
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let big = d.join("big.csv");
    mutate_csv(&csv, &big, |r| r[50][3] = "1e300".into());
    let nan = d.join("nan.csv");
    mutate_csv(&csv, &nan, |r| r[9][5] = "NaN".into());
    let dup = d.join("dup.csv");
    mutate_csv(&csv, &dup, |r| {
        r[0].push("q_abad".into());
        for row in r.iter_mut().skip(1) {
            row.push("0".into());
        }
    });
    let ragged = d.join("ragged.csv");
    mutate_csv(&csv, &ragged, |r| {
        r[7].pop();
    });
    let backwards = d.join("backwards.csv");
    mutate_csv(&csv, &backwards, |r| r[20][0] = "0".into());
    let nonl = d.join("oneline.csv");
    std::fs::write(&nonl, "t,".repeat(9_000_000)).unwrap();
    let data_cases = [
        (&big, "row 50, column 'q_knee'"),
        (&nan, "row 9"),
        (&dup, "'q_abad' appears twice"),
        (&ragged, "row 7"),
        (&backwards, "row 20, column 't'"),
        (&nonl, "longer than"),
    ];
    for (file, needle) in data_cases {
        for cmd in ["identify", "diagnose"] {
            let o = run(&[cmd, "--robot", "cheetah3-leg", "--data", &s(file)]);
            refused(&o, needle, &format!("{cmd} {}", file.display()));
        }
        let out = d.join("pred.csv");
        let o = run(&[
            "predict",
            "--robot",
            "cheetah3-leg",
            "--data",
            &s(file),
            "--out",
            &s(&out),
        ]);
        refused(&o, needle, &format!("predict {}", file.display()));
        assert!(!out.exists(), "a failed predict wrote {}", out.display());
    }
    // parameter files: each mutation is refused by every reader of them
    type Mutation = fn(&mut serde_json::Value);
    let cases: [(&str, Mutation, &str); 6] = [
        (
            "negmass",
            |p| p["bodies"][0]["params"][0] = (-1.0).into(),
            "negative",
        ),
        (
            "huge",
            |p| p["bodies"][0]["params"][0] = 1e300.into(),
            "beyond",
        ),
        (
            "inertia",
            |p| p["bodies"][2]["params"][4] = 1e200.into(),
            "'knee': Ixx",
        ),
        ("robot", |p| p["robot"] = "other".into(), "robot 'other'"),
        (
            "dupbody",
            |p| p["bodies"][1]["name"] = p["bodies"][0]["name"].clone(),
            "'abad' appears twice",
        ),
        (
            "friction",
            |p| p["friction"]["viscous"][1] = (-3.0).into(),
            "joint 'hip'",
        ),
    ];
    for (name, mutate, needle) in cases {
        let mut p = params.clone();
        mutate(&mut p);
        let file = d.join(format!("{name}.json"));
        std::fs::write(&file, p.to_string()).unwrap();
        let out = d.join("pred.csv");
        for args in [
            vec!["predict", "--params", &s(&file), "--out", &s(&out)],
            vec!["identify", "--prior", &s(&file)],
            vec!["diagnose", "--nominal", &s(&file)],
        ] {
            let mut all = args.clone();
            all.extend(["--robot", "cheetah3-leg", "--data", csv.to_str().unwrap()]);
            refused(&run(&all), needle, &format!("{} {name}", args[0]));
        }
        assert!(!out.exists());
    }
}

#[test]
fn no_command_overwrites_its_input_or_leaves_a_partial_output() {
    let d = dir("outputs");
    let (csv, _) = leg_data(&d);
    let before = std::fs::read(&csv).unwrap();
    let s = |p: &Path| p.to_str().unwrap().to_string();
    // predict onto its own data, under another spelling
    let other_spelling = d.join(".").join("leg.csv");
    let o = run(&[
        "predict",
        "--robot",
        "cheetah3-leg",
        "--data",
        &s(&csv),
        "--out",
        &s(&other_spelling),
    ]);
    refused(&o, "is also an input", "predict --out = --data");
    // simulate onto its record, and onto the URDF it simulates
    let o = run(&[
        "simulate",
        "--robot",
        "cheetah3-leg",
        "--seconds",
        "1",
        "--out",
        &s(&d.join("x.json")),
    ]);
    refused(&o, "the same file", "simulate --out x.json");
    let urdf = d.join("pend.urdf");
    pendulum(&urdf, "0.01", "0.01");
    let urdf_before = std::fs::read(&urdf).unwrap();
    let o = run(&[
        "simulate",
        "--robot",
        &s(&urdf),
        "--seconds",
        "1",
        "--out",
        &s(&d.join("pend.json")).replace(".json", ".urdf"),
    ]);
    refused(&o, "is also an input", "simulate --out the URDF");
    assert_eq!(std::fs::read(&urdf).unwrap(), urdf_before);
    // a diagnosis whose folder cannot be made leaves nothing
    let o = run(&[
        "diagnose",
        "--robot",
        "cheetah3-leg",
        "--data",
        &s(&csv),
        "--out",
        &s(&csv),
    ]);
    refused(&o, "not a folder", "diagnose --out FILE");
    assert_eq!(
        std::fs::read(&csv).unwrap(),
        before,
        "the data file changed"
    );
    // no temporary file is left behind anywhere in the folder
    for e in std::fs::read_dir(&d).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().to_string();
        assert!(!name.ends_with(".tmp"), "left behind: {name}");
    }
}

#[test]
fn hostile_sidecars_and_settings_are_refused() {
    let d = dir("sidecar");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let urdf = d.join("pend.urdf");
    pendulum(&urdf, "0.01", "0.01");
    let rotor = |extra: &str| {
        format!(
            "[[rotor]]\njoint = \"j1\"\n{extra}\n[[joint]]\nname = \"j1\"\ncoulomb = 0.1\nviscous = 0.01\n"
        )
    };
    let cases = [
        ("gear0", rotor("gear_ratio = 0.0\nmass = 0.1\ninertia = [1e-4, 0, 0, 1e-4, 0, 1e-4]"), "gear ratio 0"),
        ("gearnan", rotor("gear_ratio = nan\nmass = 0.1\ninertia = [1e-4, 0, 0, 1e-4, 0, 1e-4]"), "gear ratio NaN"),
        ("rotormass", rotor("gear_ratio = 6.0\nmass = -0.1\ninertia = [1e-4, 0, 0, 1e-4, 0, 1e-4]"), "negative"),
        ("rotornan", rotor("gear_ratio = 6.0\nmass = 0.1\ninertia = [nan, 0, 0, 1e-4, 0, 1e-4]"), "not finite"),
        ("prior", "[[body]]\nname = \"arm\"\nprior = { params = [-1.0, 0, 0, 0, 0.01, 0, 0, 0.01, 0, 0.01] }\n".to_string(), "negative"),
        ("equal", "[identify]\nequal = [[\"arm\", \"arm\"]]\n".to_string(), "itself"),
        ("limits3", "[[joint]]\nname = \"j1\"\nlimits = [-1.0, 0.0, 1.0]\n".to_string(), "expected 2 values, found 3"),
        ("equal3", "[identify]\nequal = [[\"arm\", \"arm\", \"arm\"]]\n".to_string(), "expected 2 values, found 3"),
        ("coulomb", "[[joint]]\nname = \"j1\"\ncoulomb = -0.5\n".to_string(), "coulomb = -0.5"),
        ("lock2", "lock = [\"j1\", \"j1\"]\n".to_string(), "listed twice"),
        ("gravity", "gravity = [0.0, 0.0, -1e300]\n".to_string(), "gravity"),
    ];
    for (name, text, needle) in cases {
        let sc = d.join(format!("{name}.toml"));
        std::fs::write(&sc, text).unwrap();
        let out = d.join(format!("{name}.csv"));
        let o = run(&[
            "simulate",
            "--robot",
            &s(&urdf),
            "--sidecar",
            &s(&sc),
            "--seconds",
            "1",
            "--out",
            &s(&out),
        ]);
        refused(&o, needle, name);
        assert!(!out.exists(), "{name}: a failed simulate wrote its data");
    }
    // settings beyond their limits
    let out = d.join("s.csv");
    for (args, needle) in [
        (vec!["--seconds", "1e9"], "at most"),
        (vec!["--seconds", "nan"], "seconds"),
        (vec!["--noise", "inf"], "noise"),
    ] {
        let mut all = vec![
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--out",
            out.to_str().unwrap(),
        ];
        all.extend(args.iter());
        refused(&run(&all), needle, &args.join(" "));
    }
    assert!(!out.exists());
}

#[test]
fn a_robot_beyond_the_memory_limit_is_refused_before_it_starts() {
    let d = dir("memory");
    let (csv, _) = leg_data(&d);
    let s = csv.to_str().unwrap();
    let leg = |cmd: &str, limit: &str| {
        run(&[
            cmd,
            "--robot",
            "cheetah3-leg",
            "--data",
            s,
            "--max-memory-gib",
            limit,
        ])
    };
    refused(
        &leg("identify", "0.001"),
        "GiB limit",
        "identify --max-memory-gib",
    );
    refused(
        &leg("diagnose", "0.001"),
        "GiB limit",
        "diagnose --max-memory-gib",
    );
    // 2,000 samples of the leg: the essential candidates need ~13.6 MB
    // (142 columns, cogging's 72 the most), the inertial group ~5.8 MB and
    // the compliance group ~7.6 MB (`diagnose::memory_estimate`). A limit
    // above the essential part only: the diagnosis runs without the other
    // two and says so
    let o = leg("diagnose", "0.014");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("rotor_inertia, link_inertia: not considered"),
        "{err}"
    );
    assert!(
        err.contains("elasticity, backlash: not considered"),
        "{err}"
    );
    // room for the inertial candidates but not the compliance searches
    let o = leg("diagnose", "0.021");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        !err.contains("rotor_inertia, link_inertia: not considered"),
        "{err}"
    );
    assert!(
        err.contains("elasticity, backlash: not considered"),
        "{err}"
    );
    // and a fitting run writes finite numbers only
    let pred = d.join("pred.csv");
    let o = run(&[
        "predict",
        "--robot",
        "cheetah3-leg",
        "--params",
        "true",
        "--data",
        s,
        "--out",
        pred.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    no_nan(&pred);
}

/// Options out of range name the flag and its range: `--repair-margin`
/// NaN or too large (once "invalid option eps = NaN" and "solver ended with
/// status primal_infeasible"), and a memory limit beyond any machine is a
/// limit, not a broken read (`--max-memory-gib 1e20` once read nothing and
/// said "unexpected end of file").
#[test]
fn options_out_of_range_name_the_flag() {
    let d = dir("options");
    let urdf = d.join("r.urdf");
    pendulum(&urdf, "1", "5"); // izz > ixx + iyy: not consistent
    let out = d.join("fixed.urdf");
    for m in ["nan", "2", "-1e-3", "inf"] {
        let o = run(&[
            "check",
            urdf.to_str().unwrap(),
            "--repair",
            out.to_str().unwrap(),
            &format!("--repair-margin={m}"),
        ]);
        refused(&o, "--repair-margin", m);
        refused(&o, "[0, 0.1)", m);
        assert!(!out.exists(), "{m}: nothing is written");
    }
    // in range, the inconsistent inertia (izz > ixx + iyy) is repaired
    let o = run(&[
        "check",
        urdf.to_str().unwrap(),
        "--repair",
        out.to_str().unwrap(),
        "--repair-margin",
        "1e-3",
    ]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.exists());
    // a robot's total mass beyond any robot's: named, before the solver
    let (data, _) = leg_data(&d);
    for m in ["1e300", "0", "-5", "2e6", "4.9e-324", "1e-9"] {
        let o = run(&[
            "identify",
            "--robot",
            "cheetah3-leg",
            "--data",
            data.to_str().unwrap(),
            "--total-mass",
            m,
        ]);
        refused(&o, "--total-mass", m);
        refused(&o, "at most 1e6 kg", m);
        refused(&o, "a millionth of the robot's described mass", m);
        assert_eq!(o.status.code(), Some(2), "{m}");
    }
    // a cut-off that is no frequency, even on prepared data that need none
    for c in ["-5", "0", "nan"] {
        let args = [
            "identify",
            "--robot",
            "cheetah3-leg",
            "--data",
            data.to_str().unwrap(),
        ];
        let o = run(&[&args[..], &["--cutoff-hz", c]].concat());
        refused(&o, "--cutoff-hz", c);
        refused(&o, "must be a positive frequency", c);
    }
    // values with an exponent and a sign reach the flag's own check
    let leg = [
        "identify",
        "--robot",
        "cheetah3-leg",
        "--data",
        data.to_str().unwrap(),
    ];
    for (flag, v, words) in [
        ("--total-mass", "-1e-300", "-1e-300: must be above"),
        ("--cutoff-hz", "-1e-3", "must be a positive frequency"),
        ("--weight", "-1e-3", "'weight' = -0.001"),
        ("--weight", "-1e-300", "'weight' = -1e-300: must be"),
        ("--max-memory-gib", "2e9", "at most 1e9"),
        ("--max-memory-gib", "1e300", "--max-memory-gib 1e300"),
    ] {
        let o = run(&[&leg[..], &[flag, v]].concat());
        refused(&o, flag, v);
        refused(&o, words, v);
    }
    let o = run(&[
        "diagnose",
        "--robot",
        "cheetah3-leg",
        "--data",
        data.to_str().unwrap(),
        "--folds",
        "-3",
    ]);
    refused(&o, "'--folds <FOLDS>'", "--folds -3");
    let o = run(&[
        "simulate",
        "--robot",
        "cheetah3-leg",
        "--seconds",
        "1e300",
        "--out",
        d.join("s.csv").to_str().unwrap(),
    ]);
    refused(&o, "'seconds' = 1e300: 1e303 samples", "--seconds 1e300");
    let sdpa = d.join("small.dat-s");
    std::fs::write(
        &sdpa,
        "2\n2\n{2, -1}\n1.0 1.0\n0 1 1 2 -1.0\n1 1 1 1 1.0\n2 1 2 2 1.0\n1 2 1 1 1.0\n0 2 1 1 0.5\n",
    )
    .unwrap();
    let o = run(&["sdpa", sdpa.to_str().unwrap(), "--max-memory-gib", "1e20"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
