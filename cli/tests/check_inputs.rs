//! `momentlmi check` on hostile and invalid URDFs (docs/inputs.md): limits
//! and structural errors exit 2 with a message, nothing to check exits 1,
//! geometry problems are warnings, and `--repair` never writes over its
//! input, never leaves a temporary file and writes nothing when it fails.

use std::path::Path;
use std::process::Output;

mod common;
use common::{TempDir, bin};

fn check(args: &[&Path]) -> Output {
    let mut c = bin();
    c.arg("check");
    for a in args {
        c.arg(a);
    }
    c.output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

const GOOD: &str = r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;
const BAD: &str = r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.05"/></inertial>"#;

fn robot(body: &str) -> String {
    format!("<?xml version=\"1.0\"?>\n<robot name=\"r\">\n{body}\n</robot>\n")
}

/// base (consistent) — arm (violates a triangle inequality).
fn two_links() -> String {
    robot(&format!(
        "<link name=\"base\">{GOOD}</link>\n<link name=\"arm\">{BAD}</link>\n\
         <joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"arm\"/><axis xyz=\"0 0 1\"/></joint>"
    ))
}

fn assert_invalid(o: &Output, file: &str, want: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{want}: {e}");
    assert!(e.contains(want) && e.contains(file), "{want}: {e}");
    assert!(!e.contains("panicked"), "{e}");
}

#[test]
fn a_20000_deep_file_exits_two_with_a_message() {
    let t = TempDir::new("check-inputs-deep");
    let n = 20_000;
    let f = t.write(
        "deep.urdf",
        &format!(
            "<robot name=\"x\"><link name=\"a\">{}{}</link></robot>",
            "<g>".repeat(n),
            "</g>".repeat(n)
        ),
    );
    let o = check(&[&f]);
    assert_invalid(&o, "deep.urdf", "elements nested more than 1000 deep");
}

#[test]
fn a_file_beyond_256_mib_is_refused_before_it_is_read() {
    let t = TempDir::new("check-inputs-large");
    let p = t.0.join("large.urdf");
    // sparse: no 257 MiB written
    std::fs::File::create(&p)
        .unwrap()
        .set_len((256 << 20) + 1)
        .unwrap();
    let o = check(&[&p]);
    assert_invalid(
        &o,
        "large.urdf",
        "the file is 268435457 bytes, more than the limit of 268435456 bytes (256 MiB)",
    );
}

#[test]
fn structural_errors_exit_two_naming_the_joint_and_link() {
    let t = TempDir::new("check-inputs-structure");
    let l = |n: &str| format!("<link name=\"{n}\">{GOOD}</link>");
    let j = |n: &str, p: &str, c: &str| {
        format!(
            "<joint name=\"{n}\" type=\"fixed\"><parent link=\"{p}\"/><child link=\"{c}\"/></joint>"
        )
    };
    let cases = [
        (
            "missing.urdf",
            robot(&(l("a") + &j("j", "a", "nope"))),
            "<joint name=\"j\">: child link 'nope' does not exist",
        ),
        (
            "two_parents.urdf",
            robot(&(l("a") + &l("b") + &l("c") + &j("j1", "a", "c") + &j("j2", "b", "c"))),
            "link 'c' is the child of two joints ('j1' and 'j2')",
        ),
        (
            "cycle.urdf",
            robot(&(l("base") + &l("a") + &l("b") + &j("ja", "b", "a") + &j("jb", "a", "b"))),
            "<joint name=\"ja\"> closes a cycle of 2 joint(s) through link 'a'",
        ),
        (
            "roots.urdf",
            robot(&(l("a") + &l("b"))),
            "expected one root link, found 2: a, b",
        ),
        (
            "dup_links.urdf",
            robot(&(l("arm") + &l("arm"))),
            "two links are named 'arm'",
        ),
        (
            "dup_joints.urdf",
            robot(&(l("a") + &l("b") + &l("c") + &j("j", "a", "b") + &j("j", "b", "c"))),
            "two joints are named 'j'",
        ),
    ];
    for (name, text, want) in cases {
        let f = t.write(name, &text);
        let o = check(&[&f]);
        assert_invalid(&o, name, want);
        assert!(!stdout(&o).contains("consistent"), "{name}: {}", stdout(&o));
    }
}

#[test]
fn links_without_inertials_are_nothing_to_check_and_exit_one() {
    let t = TempDir::new("check-inputs-nothing");
    let f = t.write(
        "frames.urdf",
        &robot("<link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>"),
    );
    let o = check(&[&f]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stdout(&o).contains("nothing to check: no link has an <inertial>"));
    // an empty <robot> (xacro leaves some) is nothing to check too
    let e = t.write("empty.urdf", "<robot name=\"r\"/>");
    let o = check(&[&e]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("no <link>"), "{}", stderr(&o));
    assert!(!stdout(&o).contains("all inertias are physically consistent"));
    let o = bin()
        .args(["check", f.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["consistent"], false);
    assert_eq!(v["links"].as_array().unwrap().len(), 0);
}

#[test]
fn bad_geometry_is_a_warning_naming_the_link_and_the_element() {
    let t = TempDir::new("check-inputs-geometry");
    let f = t.write(
        "geo.urdf",
        &robot(&format!(
            "<link name=\"arm\">{GOOD}\
             <collision><origin xyz=\"NaN 0 0\"/><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>\
             <collision><geometry><box size=\"0.1 -0.1 0.1\"/></geometry></collision>\
             <collision><geometry><cylinder radius=\"0\" length=\"0.1\"/></geometry></collision>\
             <visual><geometry><mesh filename=\"a.stl\" scale=\"NaN 1 1\"/></geometry></visual>\
             </link>"
        )),
    );
    let o = check(&[&f]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let e = stderr(&o);
    for w in [
        "warning: ",
        "link 'arm': <collision> 1: <origin xyz=\"NaN 0 0\">: expected three finite numbers",
        "link 'arm': <collision> 2: <box size=\"0.1 -0.1 0.1\">: every value must be positive",
        "link 'arm': <collision> 3: <cylinder radius=\"0\">: must be positive",
        "link 'arm': <visual> 1: <mesh scale=\"NaN 1 1\">: expected three finite numbers",
    ] {
        assert!(e.contains(w) && e.contains("geo.urdf"), "{w}: {e}");
    }
    let o = bin()
        .args(["check", f.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["warnings"].as_array().unwrap().len(), 4);
}

#[test]
fn repair_never_writes_over_its_input() {
    let t = TempDir::new("check-inputs-same");
    let text = two_links();
    let a = t.write("a.urdf", &text);
    std::fs::create_dir(t.0.join("sub")).unwrap();
    let link = t.0.join("link.urdf");
    std::os::unix::fs::symlink(&a, &link).unwrap();
    let spellings = [
        a.clone(),
        t.0.join("./a.urdf"),
        t.0.join("sub/../a.urdf"),
        link.clone(),
    ];
    for out in &spellings {
        let o = bin()
            .arg("check")
            .arg(&a)
            .arg("--repair")
            .arg(out)
            .output()
            .unwrap();
        assert_invalid(&o, "a.urdf", "that is the input file");
        assert!(stdout(&o).is_empty(), "refused before anything else");
        assert_eq!(std::fs::read_to_string(&a).unwrap(), text);
        assert_eq!(t.names(), ["a.urdf", "link.urdf", "sub"]);
    }
    // the input given through the link, the output as the file itself
    let o = bin()
        .arg("check")
        .arg(&link)
        .arg("--repair")
        .arg(&a)
        .output()
        .unwrap();
    assert_invalid(&o, "a.urdf", "that is the input file");
    assert_eq!(std::fs::read_to_string(&a).unwrap(), text);
}

#[test]
fn repair_writes_through_a_unique_temporary_file_and_leaves_none() {
    let t = TempDir::new("check-inputs-staged");
    let a = t.write("a.urdf", &two_links());
    // a file a fixed-suffix temporary would have clobbered
    t.write("b.urdf.tmp", "keep me");
    t.write("b.tmp", "keep me too");
    let b = t.0.join("b.urdf");
    let o = bin()
        .arg("check")
        .arg(&a)
        .arg("--repair")
        .arg(&b)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stdout(&o).contains("1 inertial(s) repaired: arm"));
    assert_eq!(
        t.names(),
        ["a.urdf", "b.tmp", "b.urdf", "b.urdf.tmp"],
        "nothing else left"
    );
    assert_eq!(
        std::fs::read_to_string(t.0.join("b.urdf.tmp")).unwrap(),
        "keep me"
    );
    assert_eq!(
        std::fs::read_to_string(t.0.join("b.tmp")).unwrap(),
        "keep me too"
    );
    assert_eq!(
        check(&[&b]).status.code(),
        Some(0),
        "the repair checks clean"
    );
}

#[test]
fn a_failing_repair_leaves_no_output_and_no_temporary_file() {
    let t = TempDir::new("check-inputs-fail");
    let a = t.write("a.urdf", &two_links());
    // the output is a folder: the staged file cannot be renamed onto it
    let dir = t.0.join("out.urdf");
    std::fs::create_dir(&dir).unwrap();
    let o = bin()
        .arg("check")
        .arg(&a)
        .arg("--repair")
        .arg(&dir)
        .output()
        .unwrap();
    assert_invalid(&o, "out.urdf", "out.urdf");
    assert!(dir.is_dir() && std::fs::read_dir(&dir).unwrap().next().is_none());
    assert_eq!(t.names(), ["a.urdf", "out.urdf"], "no temporary file left");
    // the output's folder does not exist
    let missing = t.0.join("nowhere/b.urdf");
    let o = bin()
        .arg("check")
        .arg(&a)
        .arg("--repair")
        .arg(&missing)
        .output()
        .unwrap();
    assert_invalid(&o, "b.urdf", "nowhere");
    assert_eq!(t.names(), ["a.urdf", "out.urdf"]);
    // an invalid input: nothing repaired, nothing written
    let dup = t.write(
        "dup.urdf",
        &robot(&format!(
            "<link name=\"arm\">{GOOD}</link><link name=\"arm\">{BAD}</link>"
        )),
    );
    let b = t.0.join("b.urdf");
    let o = bin()
        .arg("check")
        .arg(&dup)
        .arg("--repair")
        .arg(&b)
        .output()
        .unwrap();
    assert_invalid(&o, "dup.urdf", "two links are named 'arm'");
    assert_eq!(t.names(), ["a.urdf", "dup.urdf", "out.urdf"]);
}
