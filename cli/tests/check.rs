//! `momentlmi check` on URDFs written here with deliberate violations, on
//! bad input, and on the Panda URDF from ../shared when present.

use std::path::Path;

mod common;
use common::{TempDir, bin};

fn link(name: &str, inertial: &str, geometry: &str) -> String {
    format!("  <link name=\"{name}\">\n{inertial}\n{geometry}\n  </link>\n")
}

fn inertial(m: &str, xyz: &str, i: [&str; 6]) -> String {
    format!(
        "    <inertial>\n      <origin xyz=\"{xyz}\" rpy=\"0 0 0\"/>\n      <mass value=\"{m}\"/>\n      <inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" iyz=\"{}\" izz=\"{}\"/>\n    </inertial>",
        i[0], i[1], i[2], i[3], i[4], i[5]
    )
}

/// A robot of these links, each fixed to the one before (one tree, as a
/// URDF must be).
fn robot(links: &[String]) -> String {
    let name = |l: &str| l.split('"').nth(1).unwrap_or("").to_string();
    let joints: String = links
        .windows(2)
        .map(|w| {
            let (p, c) = (name(&w[0]), name(&w[1]));
            format!(
                "  <joint name=\"{p}_{c}\" type=\"fixed\"><parent link=\"{p}\"/><child link=\"{c}\"/></joint>\n"
            )
        })
        .collect();
    format!(
        "<?xml version=\"1.0\"?>\n<robot name=\"test\">\n{}{joints}</robot>\n",
        links.concat()
    )
}

/// A 2 kg solid box 0.1 × 0.2 × 0.3 m: I = m/12 (b² + c², a² + c², a² + b²).
fn box_link(name: &str) -> String {
    let m = 2.0;
    let (a, b, c) = (0.1f64, 0.2f64, 0.3f64);
    let i = [
        m / 12.0 * (b * b + c * c),
        m / 12.0 * (a * a + c * c),
        m / 12.0 * (a * a + b * b),
    ]
    .map(|x| x.to_string());
    let geo = "    <collision>\n      <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n      <geometry><box size=\"0.1 0.2 0.3\"/></geometry>\n    </collision>";
    link(
        name,
        &inertial("2.0", "0 0 0", [&i[0], "0", "0", &i[1], "0", &i[2]]),
        geo,
    )
}

fn json_of(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("bad JSON ({e}): {}", String::from_utf8_lossy(&out.stdout)))
}

fn status_of<'a>(v: &'a serde_json::Value, name: &str) -> &'a str {
    v["links"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["name"] == name)
        .unwrap()["status"]
        .as_str()
        .unwrap()
}

#[test]
fn consistent_robot_exits_zero_and_is_realizable_in_its_box() {
    let t = TempDir::new("check-good");
    let f = t.write(
        "good.urdf",
        &robot(&[box_link("body"), link("frame", "", "")]),
    );
    let out = bin()
        .args(["check", f.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json_of(&out);
    assert_eq!(status_of(&v, "body"), "ok");
    let l = &v["links"][0];
    assert_eq!(l["realizable_in_geometry"], true);
    assert!(l["triangle_margin_rel"].as_f64().unwrap() > 0.0);
    assert_eq!(l["principal_moments"].as_array().unwrap().len(), 3);
    assert_eq!(v["links_without_inertial"][0], "frame");
    // text output too
    let out = bin().args(["check", f.to_str().unwrap()]).output().unwrap();
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("all inertias are physically consistent")
    );
}

#[test]
fn deliberate_violations_get_their_verdicts_and_exit_one() {
    let t = TempDir::new("check-bad");
    let links = [
        box_link("good"),
        // principal moments 0.01, 0.01, 0.05: 0.01 + 0.01 < 0.05, short by 60 %
        link(
            "triangle",
            &inertial("1.0", "0 0 0.1", ["0.01", "0", "0", "0.01", "0", "0.05"]),
            "",
        ),
        link(
            "not_pd",
            &inertial("1.0", "0 0 0", ["0.01", "0", "0", "0.01", "0", "-0.002"]),
            "",
        ),
        link(
            "zero_mass",
            &inertial("0", "0 0 0", ["0.01", "0", "0", "0.01", "0", "0.01"]),
            "",
        ),
        link(
            "placeholder",
            &inertial("0", "0 0 0", ["0", "0", "0", "0", "0", "0"]),
            "",
        ),
        // consistent but its CoM sits outside its sphere: not realizable there
        link(
            "outside",
            &inertial("1.0", "0.5 0 0", ["0.001", "0", "0", "0.001", "0", "0.001"]),
            "    <collision><geometry><sphere radius=\"0.1\"/></geometry></collision>",
        ),
    ];
    let f = t.write("bad.urdf", &robot(&links));
    let out = bin()
        .args(["check", f.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v = json_of(&out);
    assert_eq!(status_of(&v, "good"), "ok");
    assert_eq!(status_of(&v, "triangle"), "triangle_violation");
    assert_eq!(status_of(&v, "not_pd"), "not_positive_definite");
    assert_eq!(status_of(&v, "zero_mass"), "nonpositive_mass");
    assert_eq!(status_of(&v, "placeholder"), "placeholder");
    assert_eq!(status_of(&v, "outside"), "ok");
    let tri = v["links"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["name"] == "triangle")
        .unwrap();
    assert!((tri["triangle_margin_rel"].as_f64().unwrap() + 0.6).abs() < 1e-9);
    let outside = v["links"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["name"] == "outside")
        .unwrap();
    assert_eq!(outside["realizable_in_geometry"], false);
    let text = bin().args(["check", f.to_str().unwrap()]).output().unwrap();
    assert!(
        String::from_utf8_lossy(&text.stdout)
            .contains("violates the triangle inequality by 60.000 %")
    );

    // --repair writes a file whose repaired links check clean
    let fixed = t.0.join("fixed.urdf");
    let out = bin()
        .args([
            "check",
            f.to_str().unwrap(),
            "--repair",
            fixed.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(1),
        "the input is still reported as inconsistent"
    );
    let out = bin()
        .args(["check", fixed.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    let v = json_of(&out);
    assert_eq!(status_of(&v, "triangle"), "ok");
    assert_eq!(status_of(&v, "not_pd"), "ok");
    assert_eq!(status_of(&v, "good"), "ok");
    // zero mass with inertia cannot be repaired without a mass: left as is
    assert_eq!(status_of(&v, "zero_mass"), "nonpositive_mass");
    let mass = v["links"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["name"] == "triangle")
        .unwrap()["mass"]
        .as_f64()
        .unwrap();
    assert!((mass - 1.0).abs() < 1e-9, "mass kept");
}

#[test]
fn bad_input_exits_two_with_a_message_naming_the_problem() {
    let t = TempDir::new("check-err");
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "missing_inertia.urdf",
            robot(&[link(
                "arm",
                "    <inertial><mass value=\"1\"/></inertial>",
                "",
            )]),
            "link 'arm': <inertial> has no <inertia>",
        ),
        (
            "nan.urdf",
            robot(&[link(
                "arm",
                &inertial("1", "0 0 0", ["NaN", "0", "0", "1", "0", "1"]),
                "",
            )]),
            "link 'arm'",
        ),
        (
            "malformed.urdf",
            "<robot name=\"x\"><link name=\"a\"></robot>".to_string(),
            "malformed XML",
        ),
        (
            "badxyz.urdf",
            robot(&[link(
                "arm",
                &inertial("1", "0 zero 0", ["1", "0", "0", "1", "0", "1"]),
                "",
            )]),
            "link 'arm': <origin xyz",
        ),
        ("notrobot.urdf", "<model/>".to_string(), "not <robot>"),
    ];
    for (name, text, want) in cases {
        let f = t.write(name, &text);
        let out = bin().args(["check", f.to_str().unwrap()]).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{name}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(want), "{name}: {err}");
        assert!(
            err.contains(name),
            "{name}: the message names the file: {err}"
        );
        assert!(!err.contains("panicked"), "{name}");
    }
    let out = bin()
        .args(["check", "/nonexistent/robot.urdf"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn panda_urdf_verdicts() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/reference/panda.urdf");
    if !p.exists() {
        println!("skipping: {} not found", p.display());
        return;
    }
    let out = bin()
        .args(["check", p.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let v = json_of(&out);
    let links = v["links"].as_array().unwrap();
    assert_eq!(links.len(), 13);
    for l in links {
        let name = l["name"].as_str().unwrap();
        let want = if name == "panda_link8" || name == "panda_hand_tcp" {
            "placeholder"
        } else {
            "ok"
        };
        assert_eq!(l["status"], want, "{name}");
        if want == "ok" {
            // the triangle inequalities hold on the reported principal moments
            let j: Vec<f64> = l["principal_moments"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert!(j[0] > 0.0 && j[0] + j[1] >= j[2], "{name}: {j:?}");
        }
    }
}

#[test]
fn a_negative_mass_is_reported_with_the_rest_of_the_table() {
    let t = TempDir::new("check-negmass");
    let f = t.write(
        "negative.urdf",
        &robot(&[link(
            "arm",
            &inertial("-1", "0 0 0", ["1", "0", "0", "1", "0", "1"]),
            "",
        )]),
    );
    let o = bin().args(["check", "--json"]).arg(&f).output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(status_of(&v, "arm"), "nonpositive_mass");
}

/// A point mass, a rod and a thin plate are consistent (status `ok`) but
/// degenerate: reported by name, exit 0, and exit 1 with `--strict`. The
/// JSON carries the bounding ellipsoids used.
#[test]
fn degenerate_links_are_named_and_strict_makes_them_findings() {
    let t = TempDir::new("degenerate");
    let box_geom = "    <collision><geometry><box size=\"0.4 0.2 0.2\"/></geometry></collision>";
    let f = t.write(
        "d.urdf",
        &robot(&[
            link(
                "base",
                &inertial("1", "0 0 0", ["0.01", "0", "0", "0.01", "0", "0.01"]),
                box_geom,
            ),
            link(
                "sensor",
                &inertial("0.0001", "0.01 0 0", ["0", "0", "0", "0", "0", "0"]),
                "",
            ),
            // a thin rod along x: no spread across it
            link(
                "rod",
                &inertial("1", "0 0 0", ["0", "0", "0", "0.0133", "0", "0.0133"]),
                "",
            ),
            // a plate in the xy plane: Izz = Ixx + Iyy
            link(
                "plate",
                &inertial("1", "0 0 0", ["0.01", "0", "0", "0.02", "0", "0.03"]),
                "",
            ),
        ]),
    );
    let o = bin().args(["check", "--json"]).arg(&f).output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let kind = |name: &str| {
        v["links"]
            .as_array()
            .unwrap()
            .iter()
            .find(|l| l["name"] == name)
            .unwrap()["degenerate"]
            .clone()
    };
    assert_eq!(kind("base"), serde_json::Value::Null);
    assert_eq!(kind("sensor"), "point mass");
    assert_eq!(kind("rod"), "rod");
    assert_eq!(kind("plate"), "thin plate");
    // the box's bounding ellipsoid: semi-axes √3 · half sides
    let e = &v["links"][0]["bounding_ellipsoids"][0];
    let want = [0.2, 0.1, 0.1].map(|h: f64| h * 3f64.sqrt());
    for (k, w) in want.iter().enumerate() {
        assert!(
            (e["semi_axes"][k].as_f64().unwrap() - w).abs() < 1e-9,
            "{e}"
        );
    }
    let o = bin().args(["check"]).arg(&f).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("3 degenerate link(s)"), "{out}");
    let o = bin().args(["check", "--strict"]).arg(&f).output().unwrap();
    assert_eq!(o.status.code(), Some(1));
}

/// A 2 kg rod 1 m long along z, in a 0.1 × 0.2 × 0.3 m box: consistent, but
/// not density realizable in the box's bounding ellipsoid; and a 2 kg link
/// over two 0.1 m cubes at x = ±0.15 m whose mass spreads too far along x
/// (rms √0.1 ≈ 0.32 m) for their union.
fn geometry_robot() -> String {
    let rod = link(
        "rod",
        &inertial("2.0", "0 0 0", ["0.1667", "0", "0", "0.1667", "0", "0.001"]),
        "    <collision><geometry><box size=\"0.1 0.2 0.3\"/></geometry></collision>",
    );
    let cube = |x: &str| {
        format!(
            "    <collision><origin xyz=\"{x} 0 0\"/><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>"
        )
    };
    let pair = link(
        "pair",
        &inertial("2.0", "0 0 0", ["0.002", "0", "0", "0.2", "0", "0.2"]),
        &format!("{}\n{}", cube("0.15"), cube("-0.15")),
    );
    robot(&[rod, pair])
}

fn in_geometry(v: &serde_json::Value) -> Vec<(String, serde_json::Value)> {
    v["links"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| {
            (
                l["name"].as_str().unwrap().to_string(),
                l["realizable_in_geometry"].clone(),
            )
        })
        .collect()
}

#[test]
fn repair_to_geometry_projects_into_the_links_bounding_volume() {
    let dir = TempDir::new("check-repair-geometry");
    let f = dir.write("g.urdf", &geometry_robot());
    let out = bin().arg("check").arg(&f).arg("--json").output().unwrap();
    assert_eq!(out.status.code(), Some(0)); // consistent, only not realizable
    let before = in_geometry(&json_of(&out));
    assert_eq!(before[0], ("rod".into(), false.into()));
    assert_eq!(before[1], ("pair".into(), false.into()));
    // the default repair leaves consistent inertias alone
    let same = dir.0.join("same.urdf");
    let o = bin()
        .arg("check")
        .arg(&f)
        .arg("--repair")
        .arg(&same)
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&o.stdout).contains("0 inertial(s) repaired"));
    // --repair-to geometry moves both into their volumes, mass kept
    let fixed = dir.0.join("fixed.urdf");
    let o = bin()
        .arg("check")
        .arg(&f)
        .args([
            "--repair-to",
            "geometry",
            "--repair-margin",
            "1e-4",
            "--repair",
        ])
        .arg(&fixed)
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(said.contains("2 inertial(s) repaired: rod, pair"), "{said}");
    let again = bin()
        .arg("check")
        .arg(&fixed)
        .arg("--json")
        .output()
        .unwrap();
    let v = json_of(&again);
    assert_eq!(
        in_geometry(&v),
        vec![("rod".into(), true.into()), ("pair".into(), true.into())]
    );
    for l in v["links"].as_array().unwrap() {
        assert!((l["mass"].as_f64().unwrap() - 2.0).abs() < 1e-9, "{l}");
    }
    // the pair was projected onto the union: its mass still spreads along x
    // beyond either cube alone (rms > 0.1 m)
    let pm = v["links"][1]["principal_moments"].as_array().unwrap();
    assert!(pm[2].as_f64().unwrap() / 2.0 > 0.1f64.powi(2), "{pm:?}");
}

#[test]
fn repair_to_needs_repair() {
    let dir = TempDir::new("check-repair-to-alone");
    let f = dir.write("g.urdf", &geometry_robot());
    let o = bin()
        .arg("check")
        .arg(&f)
        .args(["--repair-to", "geometry"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--repair"));
}

#[test]
fn a_sidecar_ellipsoid_replaces_the_links_geometry() {
    let dir = TempDir::new("check-sidecar-ellipsoid");
    let f = dir.write("g.urdf", &geometry_robot());
    let s = dir.write(
        "s.toml",
        "[[body]]\nname = \"rod\"\nbounding = [{ semi_axes = [0.2, 0.2, 0.6] }]\n",
    );
    let o = bin()
        .arg("check")
        .arg(&f)
        .arg("--json")
        .arg("--sidecar")
        .arg(&s)
        .output()
        .unwrap();
    let v = json_of(&o);
    assert_eq!(in_geometry(&v)[0], ("rod".into(), true.into()));
    let e = &v["links"][0]["bounding_ellipsoids"][0]["semi_axes"];
    assert_eq!(e, &serde_json::json!([0.2, 0.2, 0.6]));
    // a link the URDF does not have is an error naming it
    let bad = dir.write(
        "b.toml",
        "[[body]]\nname = \"arm\"\nbounding = [{ semi_axes = [1, 1, 1] }]\n",
    );
    let o = bin()
        .arg("check")
        .arg(&f)
        .arg("--sidecar")
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("'arm'"));
}

#[test]
fn out_draws_one_figure_per_link_in_three_views() {
    let dir = TempDir::new("check-out-figures");
    let f = dir.write("g.urdf", &geometry_robot());
    let figs = dir.0.join("figs");
    let o = bin()
        .arg("check")
        .arg(&f)
        .arg("--out")
        .arg(&figs)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let mut names: Vec<String> = std::fs::read_dir(&figs)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["link_pair.svg", "link_rod.svg"]);
    let svg = std::fs::read_to_string(figs.join("link_pair.svg")).unwrap();
    for view in ["top (x, y)", "front (x, z)", "side (y, z)"] {
        assert!(svg.contains(view), "{view}");
    }
    // two bounding outlines and a covariance outline in each of three views
    assert!(
        svg.matches("<polyline").count() >= 9,
        "{}",
        svg.matches("<polyline").count()
    );
    assert!(svg.contains("NOT realizable in its geometry"));
    // an --out that is a file is refused, and nothing is written
    let o = bin()
        .arg("check")
        .arg(&f)
        .arg("--out")
        .arg(&f)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}

/// A reader that closes the pipe early (`check … | head -1`) ends the
/// command quietly: no panic, nothing on stderr about stdout. The table of
/// 2,000 links is larger than a pipe's buffer, so the command is still
/// printing when the pipe closes.
#[test]
fn a_closed_pipe_is_not_a_panic() {
    use std::fmt::Write as _;
    use std::io::Read;
    use std::process::Stdio;
    let dir = TempDir::new("closed-pipe");
    let mut urdf = String::from("<robot name=\"star\"><link name=\"base\"/>\n");
    for k in 0..2000 {
        let _ = write!(
            urdf,
            "<link name=\"l{k}\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n<joint name=\"j{k}\" type=\"fixed\"><parent link=\"base\"/><child link=\"l{k}\"/></joint>\n"
        );
    }
    urdf.push_str("</robot>\n");
    let path = dir.write("star.urdf", &urdf);
    let mut child = bin()
        .args(["check", path.to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 1];
    child
        .stdout
        .as_mut()
        .unwrap()
        .read_exact(&mut first)
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(!err.contains("Broken pipe"), "{err}");
}

/// The bounding-volume cache folder: `MOMENTLMI_CACHE_DIR` names it (an
/// entry per mesh appears there, and a second run gives the same report),
/// `off` turns it off, and one that cannot be written is a warning that
/// leaves the report as it was.
#[test]
fn the_cache_folder_is_used_turned_off_or_warned_about() {
    let dir = TempDir::new("cache-dir");
    let mut obj = String::new();
    for k in 0..8 {
        let c = |i: usize| if k >> i & 1 == 1 { 0.1 } else { -0.1 };
        obj.push_str(&format!("v {} {} {}\n", c(0), 2.0 * c(1), 3.0 * c(2)));
    }
    obj.push_str("f 1 2 4\nf 1 4 3\nf 5 7 8\nf 5 8 6\nf 1 5 6\nf 1 6 2\nf 3 4 8\nf 3 8 7\nf 1 3 7\nf 1 7 5\nf 2 6 8\nf 2 8 4\n");
    dir.write("box.obj", &obj);
    let urdf = dir.write(
        "r.urdf",
        r#"<robot name="r"><link name="body"><inertial><mass value="2"/>
<inertia ixx="0.03" iyy="0.02" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
<collision><geometry><mesh filename="box.obj"/></geometry></collision></link></robot>"#,
    );
    let run = |cache: &str| {
        let o = bin()
            .env("MOMENTLMI_CACHE_DIR", cache)
            .args(["check", "--json", urdf.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        (o.stdout, String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let cache = dir.0.join("cache");
    let (first, err) = run(cache.to_str().unwrap());
    assert!(!err.contains("warning"), "{err}");
    let entries = std::fs::read_dir(&cache).unwrap().count();
    assert_eq!(entries, 1);
    let (again, _) = run(cache.to_str().unwrap());
    assert_eq!(again, first);
    std::fs::remove_dir_all(&cache).unwrap();
    let (off, _) = run("off");
    assert_eq!(off, first);
    assert!(!cache.exists() && !std::path::Path::new("off").exists());
    let not_a_folder = dir.write("file", "x");
    let (blocked, err) = run(not_a_folder.to_str().unwrap());
    assert_eq!(blocked, first);
    assert!(
        err.contains("bounding ellipsoids not cached") && err.contains("file"),
        "{err}"
    );
}
