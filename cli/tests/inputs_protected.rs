//! No output is one of the command's inputs — logs, mappings (given or the
//! sidecar's), sidecars, the URDF's meshes, trajectories, repeats — by
//! identity (a hard link or another spelling is the same file), and a
//! command's several outputs are written all or none.

#![cfg(unix)]

mod common;
use common::{TempDir, bin};
use std::path::{Path, PathBuf};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `args`; asserts exit 2, that stderr has `words`, and that each of
/// `kept` still holds what it held.
fn refused_keeping(args: &[&str], words: &[&str], kept: &[&Path]) {
    let before: Vec<Vec<u8>> = kept.iter().map(|p| std::fs::read(p).unwrap()).collect();
    let o = bin().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{}: {err}", args.join(" "));
    for w in words {
        assert!(err.contains(w), "{}: {err} lacks {w}", args.join(" "));
    }
    for (p, b) in kept.iter().zip(before) {
        assert_eq!(std::fs::read(p).unwrap(), b, "{} was changed", p.display());
    }
}

fn leg_log(dir: &TempDir, name: &str) -> PathBuf {
    let p = dir.0.join(name);
    let o = bin()
        .args([
            "simulate",
            "--robot",
            "cheetah3-leg",
            "--seconds",
            "0.5",
            "--out",
            s(&p),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    p
}

/// A one-joint arm whose link has a box mesh (an ASCII STL), and a sidecar
/// naming a `[data] mapping`, in `dir`.
fn arm_with_mesh(dir: &TempDir) -> (PathBuf, PathBuf, PathBuf, PathBuf) {
    let stl = "solid b\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\nvertex 0 0.1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0.1\nvertex 0.1 0 0.1\nvertex 0 0.1 0.1\nendloop\nendfacet\nendsolid b\n";
    let mesh = dir.write("box.stl", stl);
    let urdf = dir.write(
        "arm.urdf",
        r#"<robot name="arm">
  <link name="base"/>
  <link name="l1">
    <inertial><origin xyz="0.05 0.05 0.05"/><mass value="1"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><mesh filename="box.stl"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
</robot>
"#,
    );
    let mapping = dir.write("map.toml", "time = \"t\"\n");
    let sidecar = dir.write("arm.toml", "[data]\nmapping = \"map.toml\"\n");
    (urdf, mesh, sidecar, mapping)
}

#[test]
fn mappings_meshes_and_hard_links_are_inputs() {
    let dir = TempDir::new("inputs-protected");
    let log = leg_log(&dir, "log.csv");
    let mapping = dir.write("m.toml", "time = \"t\"\n");
    let leg = ["--robot", "cheetah3-leg"];
    // a mapping given as --mapping
    let predict = [
        &["predict"][..],
        &leg,
        &["--data", s(&log), "--mapping", s(&mapping)],
    ]
    .concat();
    let onto = [&predict[..], &["--out", s(&mapping)]].concat();
    refused_keeping(&onto, &["m.toml", "input"], &[&mapping, &log]);
    let identify = [
        &["identify"][..],
        &leg,
        &["--data", s(&log), "--mapping", s(&mapping)],
    ]
    .concat();
    let urdf_out = dir.0.join("out.urdf");
    let onto = [
        &identify[..],
        &["--urdf-out", s(&urdf_out), "--sidecar-out", s(&mapping)],
    ]
    .concat();
    refused_keeping(&onto, &["m.toml", "input"], &[&mapping]);
    assert!(!urdf_out.exists());
    // a hard link to the log is the log
    let link = dir.0.join("link.csv");
    std::fs::hard_link(&log, &link).unwrap();
    let onto = [&predict[..], &["--out", s(&link)]].concat();
    refused_keeping(&onto, &["link.csv", "input"], &[&log]);
    // the URDF's mesh, the sidecar's [data] mapping
    let (urdf, mesh, sidecar, map) = arm_with_mesh(&dir);
    let arm = ["export", "--robot", s(&urdf)];
    let onto = [&arm[..], &["--mjcf-out", s(&mesh)]].concat();
    refused_keeping(&onto, &["box.stl", "input"], &[&mesh]);
    let onto = [&arm[..], &["--urdf-out", s(&map)]].concat();
    refused_keeping(&onto, &["map.toml", "input"], &[&map, &sidecar]);
    let nothing: Vec<String> = dir
        .names()
        .into_iter()
        .filter(|n| n.contains("momentlmi"))
        .collect();
    assert!(nothing.is_empty(), "{nothing:?}");
}

#[test]
fn trajectories_and_repeats_are_inputs() {
    let dir = TempDir::new("inputs-protected-2");
    let log = leg_log(&dir, "run.csv");
    let excite = dir.0.join("traj.csv");
    let o = bin()
        .args([
            "excite",
            "--robot",
            "cheetah3-leg",
            "--seconds",
            "2",
            "--seeds",
            "1",
            "--out",
            s(&excite),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let link = dir.0.join("traj-link.csv");
    std::fs::hard_link(&excite, &link).unwrap();
    let sim = [
        "simulate",
        "--robot",
        "cheetah3-leg",
        "--trajectory",
        s(&excite),
        "--out",
        s(&link),
    ];
    refused_keeping(&sim, &["traj-link.csv", "input"], &[&excite]);
    let other = leg_log(&dir, "run2.csv");
    let diagnose = [
        "diagnose",
        "--robot",
        "cheetah3-leg",
        "--data",
        s(&log),
        "--repeats",
        s(&log),
        s(&other),
        "--model-out",
        s(&other),
    ];
    refused_keeping(&diagnose, &["run2.csv"], &[&other]);
}

#[test]
fn several_outputs_are_written_all_or_none() {
    let dir = TempDir::new("outputs-all-or-none");
    let (urdf, ..) = arm_with_mesh(&dir);
    let a = dir.0.join("a.urdf");
    let args = [
        "export",
        "--robot",
        s(&urdf),
        "--urdf-out",
        s(&a),
        "--mjcf-out",
        "/dev/full",
    ];
    let o = bin().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("/dev/full"), "{err}");
    let left: Vec<String> = dir
        .names()
        .into_iter()
        .filter(|n| n.starts_with("a.") || n.starts_with(".momentlmi"))
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}
