//! The robot description: a URDF robot with a sidecar gets its prior,
//! bounding ellipsoids, friction and tool point from the sidecar through the
//! same function as the built-in leg, and every later layer uses them.

use momentlmi::data::Samples;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::dynamics::{Data, ParamChoice, RobotDescription, cheetah3, rnea};
use momentlmi::effects::Library;
use momentlmi::effects::simulate;
use momentlmi::identify::{IdentifyOptions, Level, identify};
use momentlmi::moments::{Ellipsoid, InertialParams, check_realizable};
use momentlmi::sim::{Effects, SimConfig};
use nalgebra::{Matrix3, Vector3};
use std::path::PathBuf;

/// A 3-link arm: shoulder (z), elbow (y), wrist (y), and a hand fixed to the
/// last link; the wrist has URDF `<dynamics>` friction.
const ARM: &str = r#"<robot name="arm">
  <link name="base"/>
  <link name="upper">
    <inertial><origin xyz="0 0 0.15"/><mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.004"/></inertial>
  </link>
  <link name="fore">
    <inertial><origin xyz="0.12 0 0"/><mass value="1.2"/>
      <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.008" iyz="0" izz="0.008"/></inertial>
  </link>
  <link name="wrist">
    <inertial><origin xyz="0.03 0 0"/><mass value="0.4"/>
      <inertia ixx="0.0004" ixy="0" ixz="0" iyy="0.0005" iyz="0" izz="0.0005"/></inertial>
    <visual><geometry><mesh filename="package://arm/wrist.stl"/></geometry>
      <material name="grey"><texture/></material></visual>
  </link>
  <link name="hand">
    <inertial><mass value="0.3"/>
      <inertia ixx="0.0003" ixy="0" ixz="0" iyy="0.0003" iyz="0" izz="0.0003"/></inertial>
  </link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 0 1"/><limit lower="-2.5" upper="2.5" effort="50" velocity="3"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="30" velocity="3"/></joint>
  <joint name="wrist" type="revolute"><parent link="fore"/><child link="wrist"/>
    <origin xyz="0.25 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="3"/>
    <dynamics damping="0.03" friction="0.2"/></joint>
  <joint name="hand_fix" type="fixed"><parent link="wrist"/><child link="hand"/>
    <origin xyz="0.06 0 0" rpy="0 0 1.5707963267948966"/></joint>
</robot>
"#;

/// The arm's sidecar: the tool 0.04 m along the hand's x axis (the hand is
/// turned 90° about z, so that is the wrist frame's +y), friction for two
/// joints, a box prior and a bounding ellipsoid for every body.
const SIDECAR: &str = r#"
[tool]
frame = "hand"
xyz = [0.04, 0.0, 0.0]

[[joint]]
name = "shoulder"
coulomb = 0.8
viscous = 0.05

[[joint]]
name = "elbow"
coulomb = 0.6
viscous = 0.04
limits = [-1.5, 1.5]

[[body]]
name = "upper"
prior = { mass = 1.8, com = [0.0, 0.0, 0.14], box = [0.06, 0.06, 0.3] }
bounding = [{ center = [0.0, 0.0, 0.15], semi_axes = [0.08, 0.08, 0.25] }]

[[body]]
name = "fore"
prior = { mass = 1.1, com = [0.12, 0.0, 0.0], inertia = [0.0015, 0.0, 0.0, 0.007, 0.0, 0.007] }
bounding = [{ center = [0.12, 0.0, 0.0], semi_axes = [0.22, 0.07, 0.07] }]

[[body]]
name = "wrist"
bounding = [{ center = [0.05, 0.0, 0.0], semi_axes = [0.15, 0.09, 0.09] }]

[excitation]
kind = "multi_sine"
harmonics = 4
base_hz = 0.3

[effects]
payload_mass = 0.25
"#;

fn files(tag: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("momentlmi-desc-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (u, s) = (dir.join("arm.urdf"), dir.join("arm.toml"));
    std::fs::write(&u, ARM).unwrap();
    std::fs::write(&s, SIDECAR).unwrap();
    (u, s)
}

fn arm(tag: &str) -> RobotDescription {
    let (u, s) = files(tag);
    load_robot(u.to_str().unwrap(), Some(&s)).unwrap()
}

fn box_prior(m: f64, c: [f64; 3], s: [f64; 3]) -> InertialParams {
    let ic = Matrix3::from_diagonal(&Vector3::new(
        s[1] * s[1] + s[2] * s[2],
        s[0] * s[0] + s[2] * s[2],
        s[0] * s[0] + s[1] * s[1],
    )) * (m / 12.0);
    InertialParams::from_mass_com_inertia(m, Vector3::from(c), ic)
}

#[test]
fn a_urdf_robot_gets_its_prior_ellipsoids_friction_and_tool_from_the_sidecar() {
    let r = arm("facts");
    assert_eq!(r.model.joint_names(), ["shoulder", "elbow", "wrist"]);
    // prior: the sidecar's box and inertia forms, else the URDF's own
    let own = r.model.params();
    assert_eq!(
        r.prior[0],
        box_prior(1.8, [0.0, 0.0, 0.14], [0.06, 0.06, 0.3])
    );
    let fore = InertialParams::from_urdf(
        1.1,
        [0.12, 0.0, 0.0],
        [0.0; 3],
        [0.0015, 0.0, 0.0, 0.007, 0.0, 0.007],
    );
    assert_eq!(r.prior[1], fore);
    assert_eq!(
        r.prior[2].0.as_slice(),
        &own[20..30],
        "wrist: no prior given"
    );
    // bounding ellipsoids, one per body
    let e = r.single_ellipsoids().unwrap();
    assert_eq!(e[0].center, Vector3::new(0.0, 0.0, 0.15));
    assert_eq!(e[1].semi_axes, Vector3::new(0.22, 0.07, 0.07));
    // friction: sidecar, then URDF <dynamics>; no placeholder was needed
    assert_eq!(r.friction.coulomb, vec![0.8, 0.6, 0.2]);
    assert_eq!(r.friction.viscous, vec![0.05, 0.04, 0.03]);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    // limits replaced by the sidecar for the elbow only
    assert_eq!(r.model.joints[1].limits, (-1.5, 1.5));
    assert_eq!(r.model.joints[2].limits, (-2.0, 2.0));
    // the tool: hand origin (0.06, 0, 0) in the wrist, plus 0.04 along the
    // hand's x, which is the wrist's y
    let tool = r.model.tool.unwrap();
    assert_eq!(tool.body, 2);
    assert!((tool.point - Vector3::new(0.06, 0.04, 0.0)).norm() < 1e-12);
    assert_eq!(r.effects["payload_mass"], 0.25);
    // parameter choices: cad = the prior without friction, true = own + nominal friction
    let (cad, f) = r.parameters(&ParamChoice::Cad).unwrap();
    assert_eq!(cad.params()[..10], r.prior[0].0);
    assert!(f.coulomb.iter().all(|&c| c == 0.0));
    let (own_model, f) = r.parameters(&ParamChoice::True).unwrap();
    assert_eq!(own_model.params(), own);
    assert_eq!(f, r.friction);
}

#[test]
fn the_built_in_leg_goes_through_the_same_loader() {
    let leg = load_robot("cheetah3-leg", None).unwrap();
    assert_eq!(leg, cheetah3::description());
    // its sidecar states the values the leg always had (the box prior of the
    // public MATLAB example, the enlarged ellipsoids, the paper's friction)
    let want = [
        box_prior(1.5, [0.0, 0.045, 0.0], [0.09, 0.09, 0.09]),
        box_prior(0.5, [0.0, 0.0, -0.171], [0.06, 0.06, 0.342]),
        box_prior(0.5, [0.0, 0.0, -0.1725], [0.06, 0.06, 0.345]),
        box_prior(0.5, [0.0; 3], [0.0225, 0.09, 0.09]),
        box_prior(0.5, [0.0; 3], [0.09, 0.0225, 0.09]),
        box_prior(0.5, [0.0; 3], [0.09, 0.0225, 0.09]),
    ];
    assert_eq!(leg.prior, want);
    let e = |c: [f64; 3], a: [f64; 3]| Ellipsoid::new(Vector3::from(c), Vector3::from(a)).unwrap();
    assert_eq!(
        leg.single_ellipsoids().unwrap(),
        vec![
            e([0.0, 0.045, 0.0], [0.081, 0.081, 0.081]),
            e([0.0, 0.0, -0.171], [0.0594, 0.0594, 0.36936]),
            e([0.0, 0.0, -0.16], [0.12, 0.09, 0.32]),
            e([0.0; 3], [0.081; 3]),
            e([0.0; 3], [0.081; 3]),
            e([0.0; 3], [0.081; 3]),
        ]
    );
    assert_eq!(leg.friction.coulomb, vec![3.12, 1.25, 0.95]);
    assert_eq!(leg.friction.viscous, vec![0.1, 0.1, 0.1]);
    let tool = leg.model.tool.unwrap();
    assert_eq!((tool.body, tool.point), (2, Vector3::new(0.0, 0.0, -0.345)));
    // a sidecar for a built-in robot is refused
    let (_, s) = files("leg");
    assert!(load_robot("cheetah3-leg", Some(&s)).is_err());
}

#[test]
fn simulation_and_identification_use_the_description() {
    let r = arm("sim");
    // the Coulomb effect applies the sidecar's (and the URDF's) friction
    let states = |k: usize| {
        let t = k as f64 * 0.37;
        (
            vec![0.3 * t.sin(), -0.4 * t.cos(), 0.5 * (2.0 * t).sin()],
            vec![1.0 + t.cos(), -0.7 * t.sin(), 0.9 * t.cos()],
            vec![0.5, -1.0, 2.0],
        )
    };
    let (q, qd, qdd): (Vec<_>, Vec<_>, Vec<_>) =
        (0..20)
            .map(states)
            .fold((vec![], vec![], vec![]), |mut acc, (a, b, c)| {
                acc.0.push(a);
                acc.1.push(b);
                acc.2.push(c);
                acc
            });
    let torques = |e: &[&str]| {
        Library::builtin()
            .true_robot(&r, &Effects::new(e.iter().copied()))
            .unwrap()
            .torques(
                &Samples::from_rows(&q),
                &Samples::from_rows(&qd),
                &Samples::from_rows(&qdd),
            )
            .unwrap()
    };
    let none = torques(&[]);
    let coulomb = torques(&["coulomb"]);
    let payload = torques(&["payload"]);
    // the payload: the sidecar's 0.25 kg at the tool point, in the dynamics
    let mut heavy = r.model.clone();
    heavy.joints[2].inertia = heavy.joints[2]
        .inertia
        .plus(&InertialParams::from_mass_com_inertia(
            0.25,
            Vector3::new(0.06, 0.04, 0.0),
            Matrix3::zeros(),
        ));
    let mut data = Data::new(&heavy);
    for k in 0..q.len() {
        let t = rnea(&heavy, &mut data, &q[k], &qd[k], &qdd[k]).unwrap();
        for i in 0..3 {
            let c = r.friction.coulomb[i] * momentlmi::dynamics::sign(qd[k][i]);
            assert!(
                (coulomb[k][i] - none[k][i] - c).abs() < 1e-12,
                "{k} {i}: {} {} {c}",
                coulomb[k][i],
                none[k][i]
            );
            assert!((payload[k][i] - t[i]).abs() < 1e-12);
        }
    }
    // the sidecar's excitation (4 harmonics at 0.3 Hz) inside the sidecar's limits
    let fx = Effects::new(["coulomb", "viscous"]);
    let mut cfg = SimConfig::for_robot(&r, 12.0, fx, 4);
    cfg.noise_sigma = 0.02;
    let d = simulate(&r, &cfg, |_, _| {}).unwrap();
    assert!(d.q.iter().all(|q| q[1].abs() <= 1.5));
    match &cfg.trajectory {
        momentlmi::sim::trajectory::Trajectory::Fourier { omega, a, .. } => {
            assert!((omega - 2.0 * std::f64::consts::PI * 0.3).abs() < 1e-12);
            assert_eq!(a[0].len(), 4);
        }
        other => panic!("{other:?}"),
    }
    // identification at the ellipsoid level with the sidecar's prior and
    // ellipsoids: every body realizable in its own ellipsoid
    let opts = IdentifyOptions::for_robot(&r, Level::Ellipsoid, 1e-6).unwrap();
    let id = identify(
        &r.model,
        &d.slice(0..8000),
        Some(&d.slice(8000..12000)),
        &opts,
    )
    .unwrap();
    assert!(id.constraints_satisfied);
    for (b, e) in id.bodies.iter().zip(r.single_ellipsoids().unwrap()) {
        let pi = InertialParams(b.params);
        assert!(check_realizable(&pi, &e, 1e-7).realizable, "{}", b.name);
    }
    // the friction it finds is the sidecar's
    for i in 0..3 {
        assert!(
            (id.friction.coulomb[i] - r.friction.coulomb[i]).abs() < 0.05,
            "{:?}",
            id.friction
        );
    }
}

#[test]
fn description_errors_name_the_entry() {
    let (u, _) = files("errors");
    let dir = u.parent().unwrap().to_path_buf();
    let try_sidecar = |text: &str| {
        let s = dir.join("bad.toml");
        std::fs::write(&s, text).unwrap();
        load_robot(u.to_str().unwrap(), Some(&s))
            .unwrap_err()
            .to_string()
    };
    let e = try_sidecar("[[joint]]\nname = \"knee\"\ncoulomb = 1.0\n");
    assert!(
        e.contains("'knee'") && e.contains("shoulder, elbow, wrist"),
        "{e}"
    );
    let e = try_sidecar("[[body]]\nname = \"thigh\"\n");
    assert!(
        e.contains("'thigh'") && e.contains("upper, fore, wrist"),
        "{e}"
    );
    let e = try_sidecar(
        "[[body]]\nname = \"upper\"\nprior = { mass = 1.0, box = [0.1, 0.1, 0.1], inertia = [1, 0, 0, 1, 0, 1] }\n",
    );
    assert!(e.contains("'upper'") && e.contains("exactly one of"), "{e}");
    let e = try_sidecar("[tool]\nframe = \"gripper\"\n");
    assert!(e.contains("'gripper'") && e.contains("hand"), "{e}");
    // [effects] names are checked against an effect library (the built-in
    // one here, as the command line does), naming both files
    let effects = |text: &str| {
        let s = dir.join("bad.toml");
        std::fs::write(&s, text).unwrap();
        let robot = load_robot(u.to_str().unwrap(), Some(&s)).unwrap();
        Library::builtin()
            .check_defaults(&robot)
            .unwrap_err()
            .to_string()
    };
    let e = effects("[effects]\nstribek_force = 2.0\n");
    assert!(
        e.contains("stribek_force") && e.contains("stribeck_force") && e.contains("bad.toml"),
        "{e}"
    );
    let e = effects("[effects]\nstiffness = -5.0\n");
    assert!(e.contains("stiffness") && e.contains("> 0"), "{e}");
    let e = try_sidecar("[effects]\nstiffness = nan\n");
    assert!(e.contains("stiffness") && e.contains("not finite"), "{e}");
    let e = try_sidecar("[excitation]\nkind = \"leg_shell\"\n");
    assert!(e.contains("leg_shell"), "{e}");
    // without bounding ellipsoids, the ellipsoid level names the body that lacks one
    let bare = load_robot(u.to_str().unwrap(), None).unwrap();
    let e = IdentifyOptions::for_robot(&bare, Level::Ellipsoid, 1e-6)
        .unwrap_err()
        .to_string();
    assert!(e.contains("body 'upper' has no bounding ellipsoid"), "{e}");
    // and placeholder friction is reported, not silent
    assert!(
        bare.warnings
            .iter()
            .any(|w| w.to_string().contains("shoulder") && w.to_string().contains("placeholder")),
        "{:?}",
        bare.warnings
    );
    assert_eq!(
        bare.friction.coulomb[2], 0.2,
        "the URDF's <dynamics> still counts"
    );
}

/// The sidecar shown in docs/robots.md is a valid sidecar.
#[test]
fn the_documented_sidecar_parses() {
    let doc = include_str!("../docs/robots.md");
    let start = doc.find("```toml\n").expect("a toml block") + 8;
    let text = &doc[start..start + doc[start..].find("```").unwrap()];
    let sc = momentlmi::dynamics::sidecar::Sidecar::parse(text, "docs/robots.md").unwrap();
    assert_eq!(sc.rotors.len(), 1);
    assert_eq!(sc.joints[0].limits, Some([-2.8, 2.8]));
    assert_eq!(sc.bodies[0].bounding.len(), 1);
    // its [effects] table names parameters of the built-in effects, at
    // their nominal values
    let lib = Library::builtin();
    let effects = sc.effects.unwrap();
    assert!(!effects.is_empty());
    for (name, value) in effects {
        let (spec, _) = lib
            .params()
            .into_iter()
            .find(|(s, _)| s.name == name)
            .unwrap();
        assert_eq!(spec.nominal, value, "{name}");
    }
}

/// A URDF `<mimic>` joint the sidecar does not lock is named in a warning
/// (the model moves it on its own); locked, it is not.
#[test]
fn an_unlocked_mimic_joint_is_a_warning() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let urdf = dir.join("panda.urdf");
    let bare = load_robot(urdf.to_str().unwrap(), None).unwrap();
    let mimic: Vec<String> = bare
        .warnings
        .iter()
        .map(|w| w.to_string())
        .filter(|w| w.contains("<mimic>"))
        .collect();
    assert_eq!(mimic.len(), 1, "{:?}", bare.warnings);
    assert!(
        mimic[0].contains("'panda_finger_joint2' mimics 'panda_finger_joint1'"),
        "{}",
        mimic[0]
    );
    let locked = load_robot(urdf.to_str().unwrap(), Some(&dir.join("panda.toml"))).unwrap();
    assert!(
        !locked
            .warnings
            .iter()
            .any(|w| w.to_string().contains("<mimic>"))
    );
}

/// A sidecar's friction law beyond viscous and Coulomb (as `export`
/// writes it): the terms given on any joint are the model's terms, zero on
/// the joints that leave them out, at the sidecar's Stribeck velocity; a
/// value out of its range names the joint and the term.
#[test]
fn a_sidecar_carries_the_whole_friction_law() {
    use momentlmi::dynamics::FrictionTerm;
    let (u, _) = files("law");
    let s = u.parent().unwrap().join("law.toml");
    std::fs::write(
        &s,
        "stribeck_velocity = 0.1\n[[joint]]\nname = \"elbow\"\nviscous = 0.5\ncoulomb = 0.2\noffset = -0.3\nstribeck = 0.4\n",
    )
    .unwrap();
    let r = load_robot(u.to_str().unwrap(), Some(&s)).unwrap();
    use FrictionTerm::*;
    assert_eq!(
        r.model.friction_terms(),
        [Viscous, Coulomb, Offset, Stribeck]
    );
    assert_eq!(r.friction.offset, [0.0, -0.3, 0.0]);
    assert_eq!(r.friction.stribeck, [0.0, 0.4, 0.0]);
    assert_eq!(r.friction.stribeck_velocity(), 0.1);
    assert_eq!(r.model.stribeck_velocity(), 0.1);
    // the torque includes them: the elbow at q̇ = 0.1 rad/s, no load
    let want = 0.5 * 0.1 + 0.2 - 0.3 + 0.4 * (-1.0f64).exp();
    assert!((r.friction.torque(1, 0.1, 0.0) - want).abs() < 1e-12);
    std::fs::write(&s, "[[joint]]\nname = \"wrist\"\nload = -0.1\n").unwrap();
    let e = load_robot(u.to_str().unwrap(), Some(&s))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("'wrist'") && e.contains("load") && e.contains("≥ 0"),
        "{e}"
    );
}
