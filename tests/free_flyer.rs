//! The free-flyer dynamics of Solo12 (robots/solo12) against Pinocchio 4.1's
//! free-flyer model: generalized force, mass matrix, regressor and contact
//! forces at three random states (tests/data/solo12_free_flyer.json, written
//! by tools/reference/solo12_free_flyer.py), and the algorithms against
//! each other.

use momentlmi::dynamics::urdf::free_flyer_from_urdf_file;
use momentlmi::dynamics::{ContactWrench, Data, DynamicsError, Model, WrenchFrame};
use serde_json::Value;
use std::path::Path;

fn solo() -> Model {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    free_flyer_from_urdf_file(&root.join("robots/solo12/solo12.urdf"), None).unwrap()
}

fn reference() -> Value {
    let text = include_str!("data/solo12_free_flyer.json");
    serde_json::from_str(text).unwrap()
}

fn floats(x: &Value) -> Vec<f64> {
    x.as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

fn max_diff(a: impl IntoIterator<Item = f64>, b: impl IntoIterator<Item = f64>) -> f64 {
    a.into_iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn contacts(ff: &Model, c: &Value) -> Vec<ContactWrench> {
    c["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| ContactWrench {
            frame: ff.frame_index(w["frame"].as_str().unwrap()).unwrap(),
            wrench: floats(&w["wrench"]).try_into().unwrap(),
            expressed: match w["expressed"].as_str().unwrap() {
                "local" => WrenchFrame::Local,
                _ => WrenchFrame::WorldAligned,
            },
        })
        .collect()
}

#[test]
fn solo12_matches_pinocchio_free_flyer() {
    let ff = solo();
    let r = reference();
    let names: Vec<&str> = r["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    assert_eq!(ff.joint_names(), names);
    assert_eq!(
        (ff.nq(), ff.nv(), ff.regressor_columns()),
        (19, 18, 130 + 24)
    ); // + viscous and Coulomb per joint
    let mut data = Data::new(&ff);
    for (k, c) in r["cases"].as_array().unwrap().iter().enumerate() {
        let (q, v, a) = (floats(&c["q"]), floats(&c["v"]), floats(&c["a"]));
        let tau = momentlmi::dynamics::rnea(&ff, &mut data, &q, &v, &a)
            .unwrap()
            .clone();
        let err = max_diff(tau.iter().copied(), floats(&c["tau"]));
        assert!(err < 1e-9, "case {k}: rnea differs by {err:e}");
        let m = momentlmi::dynamics::crba(&ff, &mut data, &q)
            .unwrap()
            .clone();
        for (i, row) in c["mass_matrix"].as_array().unwrap().iter().enumerate() {
            let err = max_diff(m.row(i).iter().copied(), floats(row));
            assert!(err < 1e-9, "case {k}: mass row {i} differs by {err:e}");
        }
        let y = momentlmi::dynamics::regressor(&ff, &mut data, &q, &v, &a)
            .unwrap()
            .clone();
        for (i, row) in c["regressor"].as_array().unwrap().iter().enumerate() {
            let err = max_diff(y.row(i).iter().copied(), floats(row));
            assert!(err < 1e-9, "case {k}: regressor row {i} differs by {err:e}");
        }
        let g = ff.contact_force(&mut data, &q, &contacts(&ff, c)).unwrap();
        let err = max_diff(g.iter().copied(), floats(&c["contact_force"]));
        assert!(err < 1e-9, "case {k}: contact force differs by {err:e}");
    }
}

#[test]
fn regressor_times_parameters_is_the_inverse_dynamics() {
    // with the tree's friction columns (viscous, Coulomb): Y π + Y_f φ = rnea + friction
    let ff = solo();
    let mut data = Data::new(&ff);
    let r = reference();
    let c = &r["cases"][1];
    let (q, v, a) = (floats(&c["q"]), floats(&c["v"]), floats(&c["a"]));
    let tau = momentlmi::dynamics::rnea(&ff, &mut data, &q, &v, &a)
        .unwrap()
        .clone();
    let y = momentlmi::dynamics::regressor(&ff, &mut data, &q, &v, &a)
        .unwrap()
        .clone();
    let mut p = ff.params();
    p.resize(ff.regressor_columns(), 0.0);
    let yp = &y * nalgebra::DVector::from_vec(p);
    assert!(max_diff(yp.iter().copied(), tau.iter().copied()) < 1e-10);
    // the base rows have no friction columns
    let nb = 10 * ff.num_bodies();
    assert!((nb..ff.regressor_columns()).all(|j| (0..6).all(|i| y[(i, j)] == 0.0)));
    // the base parameters enter the base rows only
    assert!((6..18).all(|i| (0..10).all(|j| y[(i, j)] == 0.0)));
}

#[test]
fn a_free_robot_at_rest_weighs_its_mass() {
    // at rest, the base rows of the inverse dynamics are the weight of the
    // whole robot: force R^T (0, 0, m g), moment about the base of the CoM
    let ff = solo();
    let mut data = Data::new(&ff);
    let mut q = vec![0.0; 19];
    q[6] = 1.0;
    let tau = momentlmi::dynamics::rnea(&ff, &mut data, &q, &[0.0; 18], &[0.0; 18])
        .unwrap()
        .clone();
    let mass: f64 = ff.params().chunks(10).map(|p| p[0]).sum();
    assert!(
        (tau[2] - 9.81 * mass).abs() < 1e-12,
        "{} vs {}",
        tau[2],
        9.81 * mass
    );
    assert!(tau[0].abs() < 1e-12 && tau[1].abs() < 1e-12);
    // the URDF's masses: base 1.16115091, per leg 2 × 0.14853845 + 0.03070001 + 0.00693606
    assert!((mass - 2.50000279).abs() < 1e-12, "solo12 weighs {mass} kg");
}

#[test]
fn bad_floating_base_input_is_named() {
    let ff = solo();
    let mut data = Data::new(&ff);
    let mut q = vec![0.0; 19];
    q[6] = 0.9;
    let e = momentlmi::dynamics::rnea(&ff, &mut data, &q, &[0.0; 18], &[0.0; 18]).unwrap_err();
    assert!(matches!(e, DynamicsError::Quaternion { .. }), "{e}");
    assert!(e.to_string().contains("norm 0.9"), "{e}");
    let e =
        momentlmi::dynamics::rnea(&ff, &mut data, &q[..18], &[0.0; 18], &[0.0; 18]).unwrap_err();
    assert!(e.to_string().contains("q: expected length 19"), "{e}");
    let e = ff.frame_index("FL_TOE").unwrap_err();
    assert!(
        e.to_string().contains("'FL_TOE'") && e.to_string().contains("FL_FOOT"),
        "{e}"
    );
    q[6] = 1.0;
    let bad = ContactWrench {
        frame: 999,
        wrench: [0.0; 6],
        expressed: WrenchFrame::Local,
    };
    assert!(ff.contact_force(&mut data, &q, &[bad]).is_err());
}

#[test]
fn the_centroidal_quantities_are_the_weight_and_its_moment() {
    // at rest, the base rows of the RNEA hold the support of the weight:
    // force (0, 0, m g) and moment c × f about the base origin — another
    // route (RNEA) to what `centroidal` reads off the mass matrix (CRBA)
    let ff = solo();
    let mut data = Data::new(&ff);
    let r = reference();
    let mut q = floats(&r["cases"][0]["q"]);
    q[3..7].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
    let (m, c, i) = ff.centroidal(&mut data, &q).unwrap();
    let tau = momentlmi::dynamics::rnea(&ff, &mut data, &q, &[0.0; 18], &[0.0; 18])
        .unwrap()
        .clone();
    let f = nalgebra::Vector3::new(tau[0], tau[1], tau[2]);
    let n = nalgebra::Vector3::new(tau[3], tau[4], tau[5]);
    assert!((f.z - 9.81 * m).abs() < 1e-12, "{f:?} vs m = {m}");
    assert!(
        (n - c.cross(&f)).norm() < 1e-12,
        "{n:?} vs {:?}",
        c.cross(&f)
    );
    assert!(c.norm() > 1e-3, "a CoM off the base origin: {c:?}");
    // the centroidal inertia is symmetric positive definite
    assert!((i - i.transpose()).norm() < 1e-15);
    assert!(i.symmetric_eigenvalues().min() > 0.0);
}
