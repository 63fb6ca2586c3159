//! Fuzz-style properties: whatever the bytes, the URDF reader, the checker
//! (and its repair) and the model loader return a value or an error, never
//! panic. Random bytes, soups of URDF tokens, and mutations of a valid small
//! URDF (256 cases in all).

use momentlmi::dynamics::urdf::model_from_urdf_str;
use momentlmi::moments::urdf_check::{RepairOptions, check_urdf_str, repair_urdf};
use momentlmi::urdf;
use proptest::prelude::*;

/// A valid URDF with most of what the reader reads: inertials (one
/// inconsistent, so that a repair runs), every geometry, joints of several
/// kinds, limits, mimic, dynamics, a transmission, ignored blocks, comments.
const FIXTURE: &str = r#"<?xml version="1.0"?>
<!-- a small robot -->
<robot name="fuzz" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="base">
    <inertial>
      <origin xyz="0 0 0.05" rpy="0 0 0"/>
      <mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/>
    </inertial>
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.2 0.2"/></geometry></collision>
    <visual><geometry><mesh filename="package://fuzz/base.stl" scale="1 1 1"/></geometry></visual>
  </link>
  <link name="arm">
    <inertial>
      <origin xyz="0 0 0.1" rpy="0.1 0 0"/>
      <mass value="1.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.05"/>
    </inertial>
    <collision><geometry><cylinder radius="0.05" length="0.3"/></geometry></collision>
    <collision><origin xyz="0 0 0.2"/><geometry><sphere radius="0.06"/></geometry></collision>
    <visual><geometry><capsule radius="0.05" length="0.2"/></geometry></visual>
  </link>
  <link name="tool"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/>
    <child link="arm"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 1 0"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="2"/>
    <dynamics damping="0.1" friction="0.2"/>
  </joint>
  <joint name="flange" type="fixed">
    <parent link="arm"/>
    <child link="tool"/>
    <origin xyz="0 0 0.3"/>
    <mimic joint="shoulder" multiplier="1" offset="0"/>
  </joint>
  <transmission name="t">
    <type>transmission_interface/SimpleTransmission</type>
    <joint name="shoulder"/>
    <actuator name="m"><mechanicalReduction>50</mechanicalReduction></actuator>
  </transmission>
  <gazebo reference="arm"><material>Gazebo/Grey</material></gazebo>
</robot>
"#;

/// Pieces that make interesting URDF when inserted or concatenated.
const TOKENS: &[&str] = &[
    "<",
    ">",
    "/>",
    "</",
    "\"",
    "'",
    "=",
    " ",
    "\n",
    "<robot name=\"r\">",
    "</robot>",
    "<link name=\"base\">",
    "<link name=\"x\"/>",
    "</link>",
    "<joint name=\"j\" type=\"fixed\">",
    "<joint name=\"k\" type=\"revolute\">",
    "</joint>",
    "<parent link=\"base\"/>",
    "<child link=\"base\"/>",
    "<child link=\"arm\"/>",
    "<child link=\"x\"/>",
    "<axis xyz=\"0 0 0\"/>",
    "<inertial>",
    "</inertial>",
    "<mass value=\"1\"/>",
    "<mass value=\"-1\"/>",
    "<inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"3\"/>",
    "<origin xyz=\"NaN 0 0\"/>",
    "<collision><geometry><box size=\"-1 0 1\"/></geometry></collision>",
    "<geometry>",
    "<sphere radius=\"0\"/>",
    "<transmission name=\"t\">",
    "<mechanicalReduction>x</mechanicalReduction>",
    "NaN",
    "inf",
    "-0",
    "1e309",
    "1e-320",
    "-1",
    "&amp;",
    "&#0;",
    "&#x10FFFF;",
    "&bogus;",
    "<!--",
    "-->",
    "<![CDATA[",
    "]]>",
    "<?pi?>",
    "<!DOCTYPE robot>",
    "xmlns:a=\"u\"",
    "\u{feff}",
    "é",
];

/// Values a number of the fixture is replaced with (the XML stays
/// well-formed).
const VALUES: &[&str] = &[
    "NaN", "-NaN", "inf", "-inf", "1e309", "-1e309", "1e-320", "1e300", "-1e300", "0", "-0", "-1",
    "-0.05", "1 2", "", " ", "x", "0x10", "1e", "+", "3.0 4",
];

/// Whole elements inserted after a `>` (the XML stays well-formed where
/// that `>` ends a tag).
const ELEMENTS: &[&str] = &[
    r#"<link name="x"/>"#,
    r#"<link name="arm"/>"#,
    "<link/>",
    r#"<joint name="j" type="fixed"><parent link="tool"/><child link="x"/></joint>"#,
    r#"<joint name="loop" type="fixed"><parent link="tool"/><child link="base"/></joint>"#,
    r#"<joint name="shoulder" type="fixed"><parent link="base"/><child link="tool"/></joint>"#,
    r#"<joint name="z" type="prismatic"><parent link="tool"/><child link="x"/><axis xyz="0 0 0"/></joint>"#,
    r#"<joint name="f" type="floating"><parent link="tool"/><child link="x"/></joint>"#,
    r#"<inertial><mass value="1"/><inertia ixx="1" ixy="2" ixz="3" iyy="1" iyz="0" izz="-1"/></inertial>"#,
    r#"<inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>"#,
    r#"<inertial><mass value="1"/></inertial>"#,
    r#"<collision><geometry><box size="0 0 0"/></geometry></collision>"#,
    "<collision><geometry/></collision>",
    "<collision><geometry><torus/></geometry></collision>",
    r#"<visual><origin rpy="1 2"/><geometry><sphere radius="1"/></geometry></visual>"#,
    r#"<origin xyz="1e308 1e308 1e308" rpy="1e308 0 0"/>"#,
    r#"<transmission name="t2"><joint name="shoulder"/><mechanicalReduction>0</mechanicalReduction></transmission>"#,
    r#"<mimic joint="nowhere"/>"#,
    r#"<limit lower="1" upper="-1"/>"#,
    r#"<!-- <link name="c"/> -->"#,
    r#"<![CDATA[<link name="d"/>]]>"#,
];

/// A mutation of a text, positions taken modulo its length.
#[derive(Clone, Debug)]
enum Edit {
    Delete(usize, usize),
    Insert(usize, usize),
    Duplicate(usize, usize, usize),
    Bytes(usize, Vec<u8>),
    Number(usize, usize),
    Element(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        1 => (any::<usize>(), 0usize..64).prop_map(|(a, n)| Edit::Delete(a, n)),
        1 => (any::<usize>(), 0..TOKENS.len()).prop_map(|(a, t)| Edit::Insert(a, t)),
        1 => (any::<usize>(), 0usize..200, any::<usize>())
            .prop_map(|(a, n, b)| Edit::Duplicate(a, n, b)),
        1 => (any::<usize>(), proptest::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(a, b)| Edit::Bytes(a, b)),
        4 => (any::<usize>(), 0..VALUES.len()).prop_map(|(a, t)| Edit::Number(a, t)),
        4 => (any::<usize>(), 0..ELEMENTS.len()).prop_map(|(a, t)| Edit::Element(a, t)),
    ]
}

fn numeric(c: u8) -> bool {
    c.is_ascii_digit() || matches!(c, b'.' | b'-' | b'+' | b'e' | b'E')
}

/// Replaces the `k`-th (mod count) number (a run of digits, signs, points
/// and exponents that starts with a digit or a minus) with `with`.
fn replace_number(b: &mut Vec<u8>, k: usize, with: &[u8]) {
    let starts: Vec<usize> = (0..b.len())
        .filter(|&i| (b[i].is_ascii_digit() || b[i] == b'-') && (i == 0 || !numeric(b[i - 1])))
        .collect();
    if starts.is_empty() {
        return;
    }
    let s = starts[k % starts.len()];
    let e = (s..b.len()).find(|&i| !numeric(b[i])).unwrap_or(b.len());
    b.splice(s..e, with.iter().copied());
}

/// Inserts `with` after the `k`-th (mod count) `>`.
fn insert_element(b: &mut Vec<u8>, k: usize, with: &[u8]) {
    let ends: Vec<usize> = (0..b.len()).filter(|&i| b[i] == b'>').collect();
    if ends.is_empty() {
        return;
    }
    let at = ends[k % ends.len()] + 1;
    b.splice(at..at, with.iter().copied());
}

fn apply(b: &mut Vec<u8>, e: &Edit) {
    let at = |a: usize, b: &Vec<u8>| a % (b.len() + 1);
    match e {
        Edit::Delete(a, n) => {
            let s = at(*a, b);
            let end = (s + n).min(b.len());
            b.drain(s..end);
        }
        Edit::Insert(a, t) => {
            let s = at(*a, b);
            b.splice(s..s, TOKENS[*t].bytes());
        }
        Edit::Duplicate(a, n, to) => {
            let s = at(*a, b);
            let piece: Vec<u8> = b[s..(s + n).min(b.len())].to_vec();
            let d = at(*to, b);
            b.splice(d..d, piece);
        }
        Edit::Bytes(a, bytes) => {
            let s = at(*a, b);
            b.splice(s..s, bytes.iter().copied());
        }
        Edit::Number(k, t) => replace_number(b, *k, VALUES[*t].as_bytes()),
        Edit::Element(k, t) => insert_element(b, *k, ELEMENTS[*t].as_bytes()),
    }
}

/// Everything a command does with a URDF text; any panic fails the case.
fn exercise(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let _ = urdf::read_str(&text, "f.urdf").map(|r| {
        let _ = urdf::validate(&r, "f.urdf");
        urdf::geometry_warnings(&r)
    });
    if let Ok(report) = check_urdf_str(&text, "f.urdf") {
        let _ = serde_json::to_string(&report);
        if let Ok((fixed, _)) = repair_urdf(&text, &report, "f.urdf", &RepairOptions::default()) {
            let _ = check_urdf_str(&fixed, "g.urdf");
        }
    }
    let _ = model_from_urdf_str(&text, "f.urdf", None);
}

#[test]
fn the_fixture_is_valid_and_exercises_a_repair() {
    let r = check_urdf_str(FIXTURE, "f.urdf").unwrap();
    assert_eq!(r.links.len(), 2);
    assert!(
        !r.consistent,
        "the arm's inertia violates a triangle inequality"
    );
    assert!(r.warnings.is_empty());
    let m = model_from_urdf_str(FIXTURE, "f.urdf", None).unwrap();
    assert_eq!(m.dof(), 1);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        exercise(&bytes);
    }

    #[test]
    fn token_soups_never_panic(picks in proptest::collection::vec(0..TOKENS.len(), 0..60)) {
        let text: String = picks.iter().map(|&t| TOKENS[t]).collect();
        exercise(text.as_bytes());
        exercise(format!("<robot name=\"r\">{text}</robot>").as_bytes());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn mutations_of_a_valid_urdf_never_panic(edits in proptest::collection::vec(edit(), 1..6)) {
        let mut b = FIXTURE.as_bytes().to_vec();
        for e in &edits {
            apply(&mut b, e);
        }
        exercise(&b);
    }
}
