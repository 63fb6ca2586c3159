//! URDF input rules and limits (docs/inputs.md): what the reader refuses
//! before parsing, the rules the checker and the model loader share (each
//! bad file refused by both, with the same message), geometry warnings, and
//! large files read in linear time.

use momentlmi::dynamics::robots::load_robot;
use momentlmi::dynamics::urdf::model_from_urdf_str;
use momentlmi::moments::urdf_check::{RepairOptions, check_urdf_str, repair_urdf};
use momentlmi::urdf::{self, Geometry, Limits, UrdfError, read_str, read_str_with};
use std::time::Instant;

const INERTIAL: &str = r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;

fn link(name: &str) -> String {
    format!("<link name=\"{name}\">{INERTIAL}</link>")
}

fn joint(name: &str, kind: &str, parent: &str, child: &str) -> String {
    format!(
        "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/><child link=\"{child}\"/><axis xyz=\"0 0 1\"/></joint>"
    )
}

fn robot(parts: &[String]) -> String {
    format!("<robot name=\"r\">{}</robot>", parts.concat())
}

/// A chain of `n` links, each with a consistent inertial and a box, joined
/// by revolute joints; one element per line.
fn chain(n: usize) -> String {
    let mut s = String::from("<?xml version=\"1.0\"?>\n<robot name=\"chain\">\n");
    for i in 0..n {
        s.push_str(&format!(
            "  <link name=\"l{i}\">\n    <inertial>\n      <origin xyz=\"0 0 0.1\" rpy=\"0 0 0\"/>\n      <mass value=\"1.0\"/>\n      <inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/>\n    </inertial>\n    <collision><geometry><box size=\"0.3 0.3 0.3\"/></geometry></collision>\n  </link>\n"
        ));
        if i > 0 {
            s.push_str(&format!(
                "  <joint name=\"j{i}\" type=\"revolute\">\n    <parent link=\"l{}\"/>\n    <child link=\"l{i}\"/>\n    <origin xyz=\"0 0 0.2\"/>\n    <axis xyz=\"0 0 1\"/>\n    <limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>\n  </joint>\n",
                i - 1
            ));
        }
    }
    s.push_str("</robot>\n");
    s
}

#[test]
fn a_file_nested_20000_deep_is_refused_by_name_not_a_stack_overflow() {
    let n = 20_000;
    let text = format!(
        "<robot name=\"x\"><link name=\"a\">{}{}</link></robot>",
        "<g>".repeat(n),
        "</g>".repeat(n)
    );
    // in a test thread (2 MiB stack) like any library user's
    let e = read_str(&text, "deep.urdf").unwrap_err();
    assert!(matches!(e, UrdfError::TooDeep { limit: 1000, .. }), "{e}");
    assert_eq!(
        e.to_string(),
        "deep.urdf: line 1: elements nested more than 1000 deep"
    );
    assert!(check_urdf_str(&text, "deep.urdf").is_err());
    assert!(model_from_urdf_str(&text, "deep.urdf", None).is_err());
    // 1,000 deep is still read
    let ok = format!(
        "<robot name=\"x\"><link name=\"a\">{}{}</link></robot>",
        "<g>".repeat(998),
        "</g>".repeat(998)
    );
    assert!(read_str(&ok, "ok.urdf").is_ok());
}

#[test]
fn limits_are_named_errors() {
    let small = Limits {
        max_bytes: 400,
        max_nodes: 20,
        max_depth: 5,
        max_attributes: 6,
        max_namespaces: 1,
    };
    let ok = robot(&[link("a")]);
    assert!(read_str_with(&ok, "ok.urdf", &small).is_ok());
    let cases: Vec<(String, &str)> = vec![
        (
            format!("{ok}{}", " ".repeat(400)),
            "more than the limit of 400 bytes",
        ),
        (
            robot(&["<a/>".repeat(20)]),
            "line 1: more than 20 elements, comments and other nodes",
        ),
        (
            robot(&["<a b='1' c='2' d='3' e='4' f='5' g='6' h='7'/>".to_string()]),
            "an element with more than 6 attributes",
        ),
        (
            robot(&["<a xmlns:p='u'/><b xmlns:q='v'/>".to_string()]),
            "more than 1 namespace declarations",
        ),
        (
            robot(&["<a><b><c><d><e/></d></c></b></a>".to_string()]),
            "nested more than 5 deep",
        ),
    ];
    for (text, want) in cases {
        let e = read_str_with(&text, "big.urdf", &small)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("big.urdf: ") && e.contains(want), "{e}");
    }
    // the defaults, as documented
    let d = Limits::default();
    assert_eq!(d.max_bytes, 256 << 20);
    assert_eq!(d.max_depth, 1000);
    assert_eq!(d.max_nodes, 16 << 20);
    assert_eq!(d.max_attributes, 64);
    assert_eq!(d.max_namespaces, 1000);
    // a file is measured before it is read
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("big.urdf");
    std::fs::write(&p, format!("{ok}{}", " ".repeat(400))).unwrap();
    let e = urdf::read_file_with(&p, &small).unwrap_err();
    assert!(matches!(e, UrdfError::TooLarge { limit: 400, .. }), "{e}");
    // a DTD is refused (no entity expansion)
    let dtd = "<!DOCTYPE r [<!ENTITY a \"aaaa\">]><robot name=\"&a;\"><link name=\"a\"/></robot>";
    assert!(matches!(
        read_str(dtd, "dtd.urdf"),
        Err(UrdfError::Xml { .. })
    ));
}

#[test]
fn checker_and_model_loader_refuse_the_same_files_with_the_same_message() {
    let cases: Vec<(String, &str)> = vec![
        (
            robot(&[link("a"), joint("j", "revolute", "a", "nope")]),
            "<joint name=\"j\">: child link 'nope' does not exist",
        ),
        (
            robot(&[link("a"), joint("j", "revolute", "ghost", "a")]),
            "<joint name=\"j\">: parent link 'ghost' does not exist",
        ),
        (
            robot(&[
                link("a"),
                link("b"),
                link("c"),
                joint("j1", "fixed", "a", "c"),
                joint("j2", "fixed", "b", "c"),
            ]),
            "link 'c' is the child of two joints ('j1' and 'j2')",
        ),
        (
            robot(&[
                link("base"),
                link("a"),
                link("b"),
                joint("ja", "revolute", "b", "a"),
                joint("jb", "revolute", "a", "b"),
            ]),
            "closes a cycle of 2 joint(s) through link",
        ),
        (
            robot(&[link("a"), joint("j", "fixed", "a", "a")]),
            "<joint name=\"j\"> closes a cycle of 1 joint(s) through link 'a'",
        ),
        (
            robot(&[link("a"), link("b")]),
            "expected one root link, found 2: a, b",
        ),
        (
            robot(&[link("a"), link("a")]),
            "two links are named 'a'",
        ),
        (
            robot(&[
                link("a"),
                link("b"),
                link("c"),
                joint("j", "fixed", "a", "b"),
                joint("j", "fixed", "b", "c"),
            ]),
            "two joints are named 'j'",
        ),
        (
            robot(&[
                link("a"),
                link("b"),
                "<joint name=\"z\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 0\"/></joint>".into(),
            ]),
            "<joint name=\"z\">: axis must be a non-zero vector",
        ),
        (
            robot(&[
                link("a"),
                link("b"),
                "<joint name=\"t\" type=\"prismatic\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"1e-200 0 0\"/></joint>".into(),
            ]),
            "<joint name=\"t\">: axis must be a non-zero vector",
        ),
    ];
    for (text, want) in cases {
        let c = check_urdf_str(&text, "bad.urdf").unwrap_err().to_string();
        let m = model_from_urdf_str(&text, "bad.urdf", None)
            .unwrap_err()
            .to_string();
        assert!(
            c.starts_with("bad.urdf: ") && c.contains(want),
            "{want}: {c}"
        );
        assert_eq!(c, m, "the checker and the loader say the same");
    }
}

#[test]
fn a_large_cycle_and_many_roots_are_named_briefly() {
    let n = 5000;
    let mut parts: Vec<String> = (0..n).map(|i| link(&format!("l{i}"))).collect();
    parts.push(link("base"));
    for i in 0..n {
        parts.push(joint(
            &format!("j{i}"),
            "fixed",
            &format!("l{i}"),
            &format!("l{}", (i + 1) % n),
        ));
    }
    let e = check_urdf_str(&robot(&parts), "c.urdf")
        .unwrap_err()
        .to_string();
    assert!(e.contains(&format!("a cycle of {n} joint(s)")), "{e}");
    let roots: Vec<String> = (0..n).map(|i| link(&format!("r{i}"))).collect();
    let e = check_urdf_str(&robot(&roots), "r.urdf")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("found {n}: r0, r1,")) && e.ends_with(", …") && e.len() < 200,
        "{e}"
    );
}

#[test]
fn bad_geometry_is_kept_as_invalid_and_warned_about_by_the_checker_and_the_loader() {
    let text = robot(&[
        link("base"),
        format!(
            "<link name=\"arm\">{INERTIAL}\
             <collision><origin xyz=\"NaN 0 0\"/><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>\
             <collision><geometry><box size=\"-0.1 0.1 0.1\"/></geometry></collision>\
             <collision><geometry><box size=\"0 0.1 0.1\"/></geometry></collision>\
             <collision><geometry><cylinder radius=\"NaN\" length=\"1\"/></geometry></collision>\
             <collision><geometry><cylinder radius=\"0.1\" length=\"-1\"/></geometry></collision>\
             <collision><geometry><sphere radius=\"0\"/></geometry></collision>\
             <collision><geometry><capsule radius=\"0.1\" length=\"-0.1\"/></geometry></collision>\
             <visual><geometry><mesh filename=\"m.stl\" scale=\"1 -1 1\"/></geometry></visual>\
             <visual><geometry><mesh filename=\"m.stl\" scale=\"1 0 1\"/></geometry></visual>\
             <visual><geometry><sphere radius=\"0.1\"/></geometry></visual>\
             </link>"
        ),
        joint("j", "revolute", "base", "arm"),
    ]);
    let r = read_str(&text, "g.urdf").unwrap();
    let arm = r.link("arm").unwrap();
    assert!(
        arm.collisions
            .iter()
            .all(|s| matches!(s.geometry, Geometry::Invalid { .. }))
    );
    assert!(matches!(arm.visuals[2].geometry, Geometry::Sphere { .. }));
    // a negative mesh scale mirrors the mesh (left/right parts): valid
    assert!(matches!(
        arm.visuals[0].geometry,
        Geometry::Mesh {
            scale: [1.0, -1.0, 1.0],
            ..
        }
    ));
    let rep = check_urdf_str(&text, "g.urdf").unwrap();
    let want = [
        "link 'arm': <collision> 1: <origin xyz=\"NaN 0 0\">: expected three finite numbers",
        "link 'arm': <collision> 2: <box size=\"-0.1 0.1 0.1\">: every value must be positive",
        "link 'arm': <collision> 3: <box size=\"0 0.1 0.1\">: every value must be positive",
        "link 'arm': <collision> 4: <cylinder radius=\"NaN\">: not finite",
        "link 'arm': <collision> 5: <cylinder length=\"-1\">: must be positive",
        "link 'arm': <collision> 6: <sphere radius=\"0\">: must be positive",
        "link 'arm': <collision> 7: <capsule length=\"-0.1\">: must not be negative",
        "link 'arm': <visual> 2: <mesh scale=\"1 0 1\">: every value must be non-zero",
    ];
    let got: Vec<String> = rep.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(got, want);
    // the invalid shapes give no bounding volume and no note of their own
    let l = rep.links.iter().find(|l| l.name == "arm").unwrap();
    assert_eq!(l.geometry_primitives, 0);
    assert!(l.geometry_notes.is_empty(), "{:?}", l.geometry_notes);
    assert!(rep.consistent);
    // the model loader builds the model and its description warns the same
    assert!(model_from_urdf_str(&text, "g.urdf", None).is_ok());
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("g.urdf");
    std::fs::write(&p, &text).unwrap();
    let d = load_robot(p.to_str().unwrap(), None).unwrap();
    for w in want {
        assert!(
            d.warnings.iter().any(|x| x.to_string() == *w),
            "{w}: {:?}",
            d.warnings
        );
    }
}

#[test]
fn nothing_to_check_is_not_consistent() {
    let text = robot(&[
        "<link name=\"a\"/>".into(),
        "<link name=\"b\"/>".into(),
        joint("j", "fixed", "a", "b"),
    ]);
    let rep = check_urdf_str(&text, "frames.urdf").unwrap();
    assert!(rep.nothing_to_check());
    assert!(!rep.consistent);
    assert_eq!(rep.links_without_inertial, ["a", "b"]);
}

#[test]
fn nested_transmissions_are_read_once() {
    let text = robot(&[
        link("a"),
        link("b"),
        joint("j", "revolute", "a", "b"),
        "<transmission name=\"outer\"><joint name=\"j\"/><transmission name=\"inner\"><mechanicalReduction>3</mechanicalReduction></transmission></transmission>".into(),
        "<gazebo><transmission name=\"deep\"><joint name=\"j\"/></transmission></gazebo>".into(),
    ]);
    let r = read_str(&text, "t.urdf").unwrap();
    let names: Vec<&str> = r.transmissions.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(names, ["outer", "deep"]);
    assert_eq!(
        r.transmissions[0].reduction,
        Some(momentlmi::urdf::Reduction::Ratio(3.0))
    );
}

#[test]
fn a_20000_link_chain_is_checked_and_loaded() {
    let text = chain(20_000);
    let rep = check_urdf_str(&text, "chain.urdf").unwrap();
    assert_eq!(rep.links.len(), 20_000);
    assert!(rep.consistent);
    let m = model_from_urdf_str(&text, "chain.urdf", None).unwrap();
    assert_eq!(m.dof(), 19_999);
    assert_eq!(m.joints[0].name, "j1");
    assert_eq!(m.joints[19_998].parent, Some(19_997));
}

#[test]
fn many_repairs_on_one_line_are_spliced_in_one_pass() {
    let bad = "<link name=\"NAME\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.05\"/></inertial></link>";
    let n = 200;
    let mut parts: Vec<String> = (0..n)
        .map(|i| bad.replace("NAME", &format!("l{i}")))
        .collect();
    for i in 1..n {
        parts.push(joint(
            &format!("j{i}"),
            "fixed",
            &format!("l{}", i - 1),
            &format!("l{i}"),
        ));
    }
    let text = robot(&parts); // one line
    let rep = check_urdf_str(&text, "a.urdf").unwrap();
    assert!(!rep.consistent);
    let (fixed, names) = repair_urdf(&text, &rep, "a.urdf", &RepairOptions::default()).unwrap();
    assert_eq!(names.len(), n);
    let again = check_urdf_str(&fixed, "b.urdf").unwrap();
    assert!(again.consistent);
    assert_eq!(again.links[123].name, "l123");
}

/// Prints the times of a 100k-link chain (about 50 MB); run with
/// `cargo test --release --test urdf_inputs -- --ignored --nocapture`.
#[test]
#[ignore = "a 50 MB file; a few seconds in release"]
fn a_100k_link_chain_in_a_few_seconds() {
    let text = chain(100_000);
    let t = Instant::now();
    let robot = read_str(&text, "chain.urdf").unwrap();
    let read = t.elapsed();
    let t = Instant::now();
    let rep = momentlmi::moments::urdf_check::check_robot(&robot, "chain.urdf").unwrap();
    let check = t.elapsed();
    let t = Instant::now();
    let m = momentlmi::dynamics::urdf::model_from_robot(&robot, "chain.urdf", None).unwrap();
    let load = t.elapsed();
    assert!(rep.consistent);
    assert_eq!(m.dof(), 99_999);
    println!(
        "{} MB: read {read:?}, check {check:?}, model {load:?}",
        text.len() >> 20
    );
}

/// A negative mass is a finding of the checker (`nonpositive_mass`, the rest
/// of the table still reported) and a reason the model loader refuses.
#[test]
fn a_negative_mass_is_a_finding_for_check_and_an_error_for_the_loader() {
    let neg = "<link name=\"arm\"><inertial><mass value=\"-2\"/>\
<inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>";
    let text = format!(
        "<robot name=\"r\"><link name=\"base\"/>{neg}<joint name=\"j\" type=\"revolute\">\
<parent link=\"base\"/><child link=\"arm\"/><axis xyz=\"0 0 1\"/></joint></robot>"
    );
    let rep = check_urdf_str(&text, "neg.urdf").unwrap();
    assert_eq!(rep.links[0].status, "nonpositive_mass");
    assert!(!rep.consistent);
    assert!(rep.links[0].principal_moments.iter().all(|x| x.is_finite()));
    let e = model_from_urdf_str(&text, "neg.urdf", None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("link 'arm': negative mass -2 kg"), "{e}");
}

/// An empty `<robot>` (as xacro leaves some files) is "nothing to check"
/// for the checker, and no model for the loader.
#[test]
fn an_empty_robot_is_nothing_to_check_and_no_model() {
    let text = "<robot name=\"r\"/>";
    let rep = check_urdf_str(text, "e.urdf").unwrap();
    assert!(rep.nothing_to_check() && !rep.consistent);
    assert!(
        rep.warnings[0].to_string().contains("no <link>"),
        "{:?}",
        rep.warnings
    );
    let e = model_from_urdf_str(text, "e.urdf", None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("the <robot> has no <link>"), "{e}");
}
