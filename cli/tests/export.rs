//! `momentlmi export`: the files written, and bad requests refused with a
//! named error and nothing written.

mod common;
use common::{TempDir, bin};
use std::path::Path;

fn export(args: &[&str]) -> (i32, String) {
    let o = bin().arg("export").args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The leg's three files, written together; the MJCF says what it leaves out.
#[test]
fn leg_exports_are_written_together() {
    let dir = TempDir::new("export-leg");
    let (u, x) = (dir.0.join("leg.urdf"), dir.0.join("leg.xml"));
    let args = ["--robot", "cheetah3-leg", "--params", "true"];
    let (code, err) = export(&[&args[..], &["--urdf-out", s(&u), "--mjcf-out", s(&x)]].concat());
    assert_eq!(code, 0, "{err}");
    assert_eq!(dir.names(), ["leg.toml", "leg.urdf", "leg.xml"]);
    let xml = std::fs::read_to_string(&x).unwrap();
    assert_eq!(xml.matches("armature=").count(), 3);
    assert!(err.contains("torque left out"), "{err}");
}

/// An output that is an input, an output in a missing folder, a body
/// MuJoCo cannot hold (a point mass): named errors, exit 2, nothing written.
#[test]
fn bad_requests_write_nothing() {
    let dir = TempDir::new("export-bad");
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/panda/panda.urdf");
    let before = std::fs::read(&urdf).unwrap();
    let x = dir.0.join("p.xml");
    let (code, err) = export(&[
        "--robot",
        s(&urdf),
        "--urdf-out",
        s(&urdf),
        "--mjcf-out",
        s(&x),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("panda.urdf") && err.contains("input"), "{err}");
    assert_eq!(std::fs::read(&urdf).unwrap(), before);
    let missing = dir.0.join("no/such/folder/leg.urdf");
    let (code, err) = export(&[
        "--robot",
        "cheetah3-leg",
        "--urdf-out",
        s(&missing),
        "--mjcf-out",
        s(&x),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no/such/folder"), "{err}");
    assert!(dir.names().is_empty(), "{:?}", dir.names());
    // the leg with its knee a point mass 0.3 m down the shank
    let (m, z) = (0.6, -0.3);
    let point = [m, 0.0, 0.0, m * z, m * z * z, 0.0, 0.0, m * z * z, 0.0, 0.0];
    let leg = momentlmi::dynamics::cheetah3::model();
    let mut file = momentlmi::dynamics::params_file::ParamsFile::from_model(
        &leg,
        momentlmi::dynamics::Friction::zeros(3),
    );
    file.bodies[2].params = point;
    let params = dir.write("point.json", &serde_json::to_string(&file).unwrap());
    let (u, x) = (dir.0.join("leg.urdf"), dir.0.join("leg.xml"));
    let (code, err) = export(&[
        "--robot",
        "cheetah3-leg",
        "--params",
        s(&params),
        "--urdf-out",
        s(&u),
        "--mjcf-out",
        s(&x),
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("body 'knee'") && err.contains("principal moments"),
        "{err}"
    );
    assert_eq!(dir.names(), ["point.json"]);
}

/// `identify --urdf-out --mjcf-out`: the identified model written beside
/// its JSON, and the URDF + sidecar (`--params true`: their inertias,
/// rotors and friction) predict what the JSON predicts, to 1e-9 relative
/// per joint: on the simulated leg, on the Panda at the ellipsoid level and
/// on the real KUKA (runs 1–2, the default options; predicted on run 3).
#[test]
fn identify_exports_what_it_identified() {
    let dir = TempDir::new("export-identify");
    let data = dir.0.join("d.csv");
    let panda = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/panda/panda.urdf");
    let kuka = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/kuka-lwr4");
    for (robot, seconds) in [("cheetah3-leg", "3"), (s(&panda), "4")] {
        let args = [
            "simulate",
            "--robot",
            robot,
            "--seconds",
            seconds,
            "--out",
            s(&data),
        ];
        let o = bin().args(args).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let level = if robot == "cheetah3-leg" {
            "consistent"
        } else {
            "ellipsoid"
        };
        let fit = ["--data", s(&data), "--constraints", level];
        round_trip(&dir, &["--robot", robot], &fit, &["--data", s(&data)]);
    }
    let run = |k: u32| kuka.join(format!("data/measurements_{k}.npz"));
    let (r1, r2, r3) = (run(1), run(2), run(3));
    let urdf = kuka.join("kuka_lwr4.urdf");
    let fit = ["--data", s(&r1), "--data", s(&r2)];
    // the same cut-off for both predictions (the model file carries its own)
    let on = ["--data", s(&r3), "--cutoff-hz", "7"];
    round_trip(&dir, &["--robot", s(&urdf)], &fit, &on);
}

/// Identifies `robot` with `fit` (writing its URDF and sidecar), predicts
/// `on` with the JSON and with the written files, and compares.
fn round_trip(dir: &TempDir, robot: &[&str], fit: &[&str], on: &[&str]) {
    let (u, x) = (dir.0.join("id.urdf"), dir.0.join("id.xml"));
    let o = bin()
        .arg("identify")
        .args(robot)
        .args(fit)
        .args(["--json", "--urdf-out", s(&u), "--mjcf-out", s(&x)])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{robot:?}: {err}");
    let json = dir.write("id.json", &String::from_utf8_lossy(&o.stdout));
    let predict = |robot: &[&str], params: &Path, out: &str| {
        let out = dir.0.join(out);
        let o = bin()
            .arg("predict")
            .args(robot)
            .args(["--params", s(params), "--out", s(&out)])
            .args(on)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(out).unwrap()
    };
    let from_json = predict(robot, &json, "a.csv");
    let side = dir.0.join("id.toml");
    let urdf_robot = ["--robot", s(&u), "--sidecar", s(&side)];
    let from_urdf = predict(&urdf_robot, Path::new("true"), "b.csv");
    let rows = |t: &str| -> Vec<Vec<f64>> {
        (t.lines().skip(1))
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (a, b) = (rows(&from_json), rows(&from_urdf));
    assert_eq!(a.len(), b.len());
    let n = a[0].len();
    for j in 1..n {
        let scale = a.iter().map(|r| r[j].abs()).fold(0.0, f64::max);
        let diff = (a.iter().zip(&b))
            .map(|(x, y)| (x[j] - y[j]).abs())
            .fold(0.0, f64::max);
        assert!(
            diff <= 1e-9 * scale,
            "{robot:?} column {j}: {diff:e} of {scale:e}"
        );
    }
}
