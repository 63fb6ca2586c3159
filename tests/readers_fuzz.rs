//! Fuzz-style properties of the readers of data CSV, parameter files and
//! sidecars: on random and mutated input they return `Ok` or a named
//! error, never panic; and whatever they accept is finite and within the
//! stated limits.

use momentlmi::data::csv::{MAX_ABS_TIME, MAX_ABS_VALUE};
use momentlmi::data::{Dataset, ReadOptions};
use momentlmi::dynamics::params_file::ParamsFile;
use momentlmi::dynamics::sidecar::Sidecar;
use momentlmi::dynamics::urdf::model_from_robot;
use momentlmi::dynamics::{RobotDescription, cheetah3};
use proptest::prelude::*;

const CSV: &str = "t,q_a,qd_a,qdd_a,tau_a,q_b,qd_b,qdd_b,tau_b\n\
0,0.1,0.2,0.3,1.0,0.5,0.1,0.0,2.0\n\
0.001,0.11,0.21,0.31,1.1,0.51,0.11,0.01,2.1\n\
0.002,0.12,0.22,0.32,1.2,0.52,0.12,0.02,2.2\n";

const URDF: &str = r#"<robot name="two"><link name="base"/>
<link name="a"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
<link name="b"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/>
<inertia ixx="0.005" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<joint name="ja" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
<limit lower="-2" upper="2" effort="10" velocity="5"/></joint>
<joint name="jb" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0.3 0 0"/>
<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="5"/></joint></robot>"#;

const SIDECAR: &str = r#"gravity = [0.0, 0.0, -9.81]
[[rotor]]
joint = "ja"
gear_ratio = 6.0
mass = 0.1
inertia = [1e-4, 0.0, 0.0, 1e-4, 0.0, 2e-4]
[[joint]]
name = "ja"
coulomb = 0.3
viscous = 0.05
limits = [-1.5, 1.5]
[[body]]
name = "a"
prior = { mass = 1.1, com = [0.1, 0.0, 0.0], box = [0.2, 0.05, 0.05] }
bounding = [{ center = [0.1, 0.0, 0.0], semi_axes = [0.2, 0.06, 0.06] }]
level = "ellipsoid"
[identify]
total_mass = 1.6
"#;

/// Tokens a careless or hostile file holds.
fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("1e300".to_string()),
        Just("-1e308".to_string()),
        Just("1e-320".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("".to_string()),
        Just(",".to_string()),
        Just("\n".to_string()),
        Just("\"".to_string()),
        Just("]".to_string()),
        Just("[[".to_string()),
        Just("=".to_string()),
        Just("\u{0}".to_string()),
        Just("é".to_string()),
        "[ -~]{0,6}",
        any::<f64>().prop_map(|x| x.to_string()),
    ]
}

/// `base` with up to 4 spans replaced by tokens.
fn mutated(base: &'static str) -> impl Strategy<Value = String> {
    prop::collection::vec((0..base.len(), 0usize..8, token()), 0..4).prop_map(move |edits| {
        let mut s = base.to_string();
        for (at, len, tok) in edits {
            let mut a = at.min(s.len());
            while !s.is_char_boundary(a) {
                a -= 1;
            }
            let mut b = (a + len).min(s.len());
            while !s.is_char_boundary(b) {
                b += 1;
            }
            s.replace_range(a..b, &tok);
        }
        s
    })
}

fn csv_holds_its_rules(text: &str) {
    let opts = ReadOptions {
        cutoff_hz: Some(100.0),
        ..Default::default()
    };
    if let Ok(d) = Dataset::parse_csv(text, "fuzz.csv", &["a", "b"], opts) {
        assert!(d.t.windows(2).all(|w| w[1] > w[0]));
        assert!(d.t.iter().all(|t| t.abs() <= MAX_ABS_TIME));
        for v in [&d.q, &d.qd, &d.tau] {
            assert!(
                v.iter()
                    .flatten()
                    .all(|x| x.is_finite() && x.abs() <= MAX_ABS_VALUE)
            );
        }
        assert!(d.qdd.iter().flatten().all(|x| x.is_finite()));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn csv_reader_never_panics_on_mutations(text in mutated(CSV)) {
        csv_holds_its_rules(&text);
    }

    #[test]
    fn csv_reader_never_panics_on_random_text(text in "[t,q_abdu0-9.e\\-\n ]{0,300}") {
        csv_holds_its_rules(&text);
    }

    #[test]
    fn parameter_file_reader_never_panics(text in mutated(PARAMS)) {
        let mut model = cheetah3::model();
        if let Ok(f) = serde_json::from_str::<ParamsFile>(&text)
            && f.apply(&mut model, "fuzz.json").is_ok()
        {
            for b in &f.bodies {
                prop_assert!(momentlmi::moments::InertialParams(b.params).validate().is_ok());
            }
        }
    }

    #[test]
    fn sidecar_reader_never_panics(text in mutated(SIDECAR)) {
        let robot = momentlmi::urdf::read_str(URDF, "two.urdf").unwrap();
        if let Ok(sc) = Sidecar::parse(&text, "fuzz.toml")
            && let Ok(model) = model_from_robot(&robot, "two.urdf", Some(&sc))
            && let Ok(desc) = RobotDescription::new("two.urdf", model, &sc, Some(&robot))
        {
            for r in &desc.model.rotors {
                prop_assert!(r.gear_ratio > 0.0 && r.gear_ratio.is_finite());
                prop_assert!(r.inertia.validate().is_ok());
            }
            for p in &desc.prior {
                prop_assert!(p.validate().is_ok());
            }
        }
    }
}

/// The leg's parameter file as `identify --json` writes it (its own
/// parameters, friction on every joint).
const PARAMS: &str = r#"{"robot":"cheetah3-leg","joints":["abad","hip","knee"],
"parameter_order":"m, hx, hy, hz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz",
"bodies":[
{"name":"abad","params":[2.7,0.0,0.07,0.05,0.003,0.0,0.0,0.016,-0.001,0.017]},
{"name":"hip","params":[0.9,0.0,0.01,-0.05,0.01,0.0,0.0,0.01,0.0,0.001]},
{"name":"knee","params":[0.2,0.0,0.0,-0.02,0.003,0.0,0.0,0.003,0.0,0.0001]},
{"name":"abad_rotor","params":[0.5,0.0,0.0,0.0,0.0003,0.0,0.0,0.0003,0.0,0.0005]},
{"name":"hip_rotor","params":[0.5,0.0,0.0,0.0,0.0003,0.0,0.0,0.0003,0.0,0.0005]},
{"name":"knee_rotor","params":[0.5,0.0,0.0,0.0,0.0003,0.0,0.0,0.0003,0.0,0.0005]}],
"friction":{"viscous":[0.1,0.1,0.1],"coulomb":[1.0,1.0,1.0]}}"#;

#[test]
fn the_unmutated_inputs_are_accepted() {
    // the properties above would hold vacuously if the bases were refused
    let opts = ReadOptions {
        cutoff_hz: Some(100.0),
        ..Default::default()
    };
    Dataset::parse_csv(CSV, "base.csv", &["a", "b"], opts).unwrap();
    let f: ParamsFile = serde_json::from_str(PARAMS).unwrap();
    let mut model = cheetah3::model();
    let body_names = model.body_names();
    assert_eq!(
        f.bodies.iter().map(|b| b.name.clone()).collect::<Vec<_>>(),
        body_names
    );
    f.apply(&mut model, "base.json").unwrap();
    let robot = momentlmi::urdf::read_str(URDF, "two.urdf").unwrap();
    let sc = Sidecar::parse(SIDECAR, "base.toml").unwrap();
    let model = model_from_robot(&robot, "two.urdf", Some(&sc)).unwrap();
    RobotDescription::new("two.urdf", model, &sc, Some(&robot)).unwrap();
}
