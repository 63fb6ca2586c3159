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
/// its JSON, and the URDF + sidecar predict what the JSON predicts.
#[test]
fn identify_exports_what_it_identified() {
    let dir = TempDir::new("export-identify");
    let data = dir.0.join("d.csv");
    let o = bin()
        .args([
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--seconds",
            "3",
            "--out",
            s(&data),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (u, x) = (dir.0.join("id.urdf"), dir.0.join("id.xml"));
    let o = bin()
        .args([
            "identify",
            "--robot",
            "cheetah3-leg",
            "--data",
            s(&data),
            "--json",
        ])
        .args(["--urdf-out", s(&u), "--mjcf-out", s(&x)])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let json = dir.write("id.json", &String::from_utf8_lossy(&o.stdout));
    let predict = |robot: &[&str], params: &Path, out: &str| {
        let out = dir.0.join(out);
        let o = bin()
            .arg("predict")
            .args(robot)
            .args(["--params", s(params), "--data", s(&data), "--out", s(&out)])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(out).unwrap()
    };
    let from_json = predict(&["--robot", "cheetah3-leg"], &json, "a.csv");
    let side = dir.0.join("id.toml");
    let urdf_robot = ["--robot", s(&u), "--sidecar", s(&side)];
    let from_urdf = predict(&urdf_robot, Path::new("true"), "b.csv");
    let rows = |t: &str| -> Vec<Vec<f64>> {
        (t.lines().skip(1))
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    for (a, b) in rows(&from_json).iter().zip(rows(&from_urdf)) {
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1e-9, "{x} {y}");
        }
    }
}
