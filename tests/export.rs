//! The identified model written back into URDF (+ sidecar) and MJCF: the
//! URDF read back is the same model (parameters, rotors, friction, torques),
//! every byte of the original outside the replaced elements is kept, and a
//! model a format cannot hold is a named error.

use momentlmi::dynamics::robots::{built_in, load_robot_with};
use momentlmi::dynamics::{Data, Friction, Model, RobotDescription, rnea};
use momentlmi::export::{
    MujocoView, UrdfSource, sidecar_with_params, urdf_of_model, urdf_with_params,
};
use std::path::{Path, PathBuf};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// An "identified" model: each body's parameters scaled (still physically
/// consistent) and every joint with friction.
fn identified(robot: &RobotDescription) -> (Model, Friction) {
    let mut model = robot.model.clone();
    let p: Vec<f64> = (model.params().iter().enumerate())
        .map(|(k, x)| x * (1.05 + 0.01 * (k / 10) as f64))
        .collect();
    model.set_params(&p).unwrap();
    let n = model.dof();
    let mut f = Friction::zeros(n);
    f.viscous = (0..n).map(|j| 0.1 + 0.01 * j as f64).collect();
    f.coulomb = (0..n).map(|j| 1.0 + 0.1 * j as f64).collect();
    f.offset = (0..n).map(|j| -0.2 * j as f64).collect();
    (model, f)
}

/// Written URDF and sidecar read back: the same bodies, rotors and nominal
/// friction, and torques equal to 1e-9 at states across the joints' ranges.
fn assert_same_robot(a: &Model, fa: &Friction, b: &RobotDescription) {
    let m = &b.model;
    assert_eq!(a.joint_names(), m.joint_names());
    assert_eq!(a.body_names(), m.body_names());
    for (x, y) in a.params().iter().zip(m.params()) {
        assert!((x - y).abs() <= 1e-12 * (1.0 + x.abs()), "{x} {y}");
    }
    assert_eq!(&b.friction.viscous, &fa.viscous);
    assert_eq!(&b.friction.coulomb, &fa.coulomb);
    let (mut da, mut db) = (Data::new(a), Data::new(m));
    let n = a.dof();
    for k in 0..20 {
        let s =
            |c: f64| -> Vec<f64> { (0..n).map(|j| ((k * 7 + j * 3) as f64 * c).sin()).collect() };
        let (q, qd, qdd) = (s(0.37), s(1.1), s(2.3));
        let ta = rnea(a, &mut da, &q, &qd, &qdd).unwrap().clone();
        let tb = rnea(m, &mut db, &q, &qd, &qdd).unwrap();
        for j in 0..n {
            assert!(
                (ta[j] - tb[j]).abs() <= 1e-9,
                "joint {j}: {} {}",
                ta[j],
                tb[j]
            );
        }
    }
}

/// `text` without comments, `<inertial>` and `<dynamics>` elements and white
/// space: what an export must keep.
fn kept(text: &str) -> String {
    let mut s = text.to_string();
    for (open, close) in [
        ("<!--", "-->"),
        ("<inertial", "</inertial>"),
        ("<dynamics", "/>"),
    ] {
        while let Some(a) = s.find(open) {
            let b = a + s[a..].find(close).unwrap() + close.len();
            s.replace_range(a..b, "");
        }
    }
    s.split_whitespace().collect()
}

fn write_and_read(urdf: &str, sidecar: &str, dir: &Path) -> RobotDescription {
    let (u, s) = (dir.join("out.urdf"), dir.join("out.toml"));
    std::fs::write(&u, urdf).unwrap();
    std::fs::write(&s, sidecar).unwrap();
    load_robot_with(u.to_str().unwrap(), Some(&s), &[repo("robots/panda")]).unwrap()
}

/// The Panda (fixed joints, and locked finger joints merged into the
/// hand's body): the copy keeps every other byte, the merged links'
/// inertials become comments, and it reads back as the same model.
#[test]
fn panda_urdf_round_trip() {
    let path = repo("robots/panda/panda.urdf");
    let sidecar = repo("robots/panda/panda.toml");
    let robot = load_robot_with(path.to_str().unwrap(), Some(&sidecar), &[]).unwrap();
    let (model, friction) = identified(&robot);
    let text = std::fs::read_to_string(&path).unwrap();
    let (_, read) = momentlmi::urdf::read_file(&path).unwrap();
    let src = UrdfSource {
        text: &text,
        robot: &read,
        path: "panda.urdf",
    };
    let out = urdf_with_params(&src, &model, &friction).unwrap();
    assert_eq!(kept(&out), kept(&text));
    assert!(
        out.contains("merged into link 'panda_link7'"),
        "the hand's inertial"
    );
    assert!(
        out.contains("friction offset"),
        "the offsets in the comment"
    );
    let side_text = std::fs::read_to_string(&sidecar).unwrap();
    let side = sidecar_with_params(
        Some((&side_text, "panda.toml")),
        &model,
        &friction,
        &robot.prior,
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let back = write_and_read(&out, &side, dir.path());
    assert_same_robot(&model, &friction, &back);
    // the prior is still the CAD one, not the identified inertials
    for (x, y) in robot.prior_vector().iter().zip(back.prior_vector()) {
        assert!((x - y).abs() <= 1e-12 * (1.0 + x.abs()));
    }
}

/// The built-in leg (no URDF: one written from the model) with its three
/// rotors: the URDF and the sidecar read back give the same model and
/// the same bounding ellipsoids.
#[test]
fn leg_urdf_round_trip() {
    let robot = momentlmi::dynamics::robots::load_robot("cheetah3-leg", None).unwrap();
    let (model, friction) = identified(&robot);
    let urdf = urdf_of_model(&model, &friction).unwrap();
    let own = built_in("cheetah3-leg").unwrap().sidecar;
    let side = sidecar_with_params(
        Some((own, "cheetah3-leg.toml")),
        &model,
        &friction,
        &robot.prior,
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let back = write_and_read(&urdf, &side, dir.path());
    assert_eq!(back.model.rotors.len(), 3);
    assert_same_robot(&model, &friction, &back);
    assert_eq!(back.bounding(), robot.bounding());
}

/// A URDF with fixed joints, a link without an `<inertial>` (self-closing)
/// and one whose body is merged: elements are inserted where missing.
#[test]
fn fixed_joints_and_missing_inertials() {
    let text = r#"<robot name="r">
  <link name="base"/>
  <link name="a"/>
  <link name="a_tip"><inertial><mass value="0.5"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>
  <link name="b"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="tip" type="fixed"><parent link="a"/><child link="a_tip"/><origin xyz="0.3 0 0"/></joint>
  <joint name="j2" type="continuous"><parent link="a_tip"/><child link="b"/><axis xyz="0 1 0"/><dynamics damping="0.5"/></joint>
</robot>
"#;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("r.urdf");
    std::fs::write(&path, text).unwrap();
    let robot = load_robot_with(path.to_str().unwrap(), None, &[]).unwrap();
    let (mut model, friction) = identified(&robot);
    // b has no mass in the URDF: give it some, as an identification would
    let mut p = model.params();
    p[10..20].copy_from_slice(&[0.3, 0.0, 0.0, 0.03, 1e-3, 0.0, 0.0, 1e-3, 0.0, 1e-3]);
    model.set_params(&p).unwrap();
    let (_, read) = momentlmi::urdf::read_file(&path).unwrap();
    let src = UrdfSource {
        text,
        robot: &read,
        path: "r.urdf",
    };
    let out = urdf_with_params(&src, &model, &friction).unwrap();
    // the self-closing <link name="a"/> gains a body for its inertial
    assert_eq!(
        kept(&out),
        kept(&text.replace("<link name=\"a\"/>", "<link name=\"a\"></link>"))
    );
    let side = sidecar_with_params(None, &model, &friction, &robot.prior).unwrap();
    let back = write_and_read(&out, &side, dir.path());
    assert_same_robot(&model, &friction, &back);
    // a body of no mass cannot be written
    p[10] = 0.0;
    p[11..20].fill(0.0);
    model.set_params(&p).unwrap();
    let e = urdf_with_params(&src, &model, &friction)
        .unwrap_err()
        .to_string();
    assert!(e.contains("body 'b'") && e.contains("positive mass"), "{e}");
}

/// The MuJoCo view of the leg: rotors become armature N² aᵀĪa and their
/// rigid parts ride on the parent bodies. At q = 0 (every rotor at spin
/// angle 0) its mass matrix has the full model's diagonal, and differs off
/// it (the spin's coupling with the parent's rotation, dropped), by what
/// `dropped` measures over a motion.
#[test]
fn leg_mujoco_view() {
    let robot = momentlmi::dynamics::robots::load_robot("cheetah3-leg", None).unwrap();
    let (model, friction) = (robot.model.clone(), robot.friction.clone());
    let view = MujocoView::new(&model, &friction).unwrap();
    for r in &model.rotors {
        let j = r.inertia.inertia();
        let expect = r.gear_ratio.powi(2) * (r.axis.transpose() * j * r.axis)[0];
        assert!((view.armature[r.joint] - expect).abs() < 1e-15);
    }
    assert!(view.model.rotors.is_empty());
    assert_eq!(
        (view.damping.clone(), view.frictionloss.clone()),
        (friction.viscous, friction.coulomb)
    );
    let (mut d, mut dv) = (Data::new(&model), Data::new(&view.model));
    let rest = [0.0; 3];
    let g = rnea(&model, &mut d, &rest, &rest, &rest).unwrap().clone();
    let gv = view.torques(&mut dv, &rest, &rest, &rest).unwrap();
    let mut off = 0.0f64;
    for i in 0..3 {
        let mut qdd = [0.0; 3];
        qdd[i] = 1.0;
        let full = rnea(&model, &mut d, &rest, &rest, &qdd).unwrap() - &g;
        let v = view.torques(&mut dv, &rest, &rest, &qdd).unwrap();
        for j in 0..3 {
            let (a, b) = (full[j], v[j] - gv[j]);
            if i == j {
                assert!((a - b).abs() < 1e-12, "M[{i}][{i}]: {a} {b}");
            } else {
                off = off.max((a - b).abs());
            }
        }
    }
    assert!(off > 1e-3, "the coupling dropped: {off}");
    let motion =
        momentlmi::sim::trajectory::Trajectory::for_excitation(&robot.excitation, &model, 1);
    let dropped = view.dropped(&model, &motion, 2.0).unwrap();
    assert!(dropped.rms.iter().all(|x| x.is_finite()));
    assert!(dropped.rms.iter().any(|&x| x > 1e-3), "{dropped:?}");
}
