//! Identification of a floating-base robot (Solo12, suspended from a
//! harness with a load cell) from its base rows and contact wrench alone,
//! and from its joint rows: held-out errors at the noise floor, every body
//! consistent, the whole robot's mass, CoM and centroidal inertia as the
//! truth's.

use momentlmi::data::Dataset;
use momentlmi::dynamics::urdf::free_flyer_from_urdf_file;
use momentlmi::dynamics::{Data, Model};
use momentlmi::identify::{Identification, Rows, reduce_floating};
use momentlmi::moments::InertialParams;
use momentlmi::sim::floating::{SuspendedConfig, simulate_suspended};
use std::path::Path;

#[path = "support/floating.rs"]
mod floating_support;
use floating_support::held_out_rms;

fn solo() -> Model {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    free_flyer_from_urdf_file(&root.join("robots/solo12/solo12.urdf"), None).unwrap()
}

fn logs(ff: &Model) -> (Dataset, Dataset) {
    // two minutes of training (the centroidal inertia of a 2.5 kg robot,
    // ≈ 0.03 kg·m², is what needs them: 1.6 % off after 20 s, 1.0 % after 60 s)
    let cfg = |seconds, seed| SuspendedConfig {
        seconds,
        seed,
        ..SuspendedConfig::default()
    };
    (
        simulate_suspended(ff, &cfg(120.0, 1)).unwrap(),
        simulate_suspended(ff, &cfg(20.0, 2)).unwrap(),
    )
}

fn truth(ff: &Model) -> Vec<f64> {
    let mut t = ff.params();
    t.resize(ff.regressor_columns(), 0.0); // no friction in the simulation
    t
}

#[test]
fn base_rows_alone_identify_the_whole_robot() {
    let ff = solo();
    let (train, test) = logs(&ff);
    let red = reduce_floating(&ff, &train, Rows::Base).unwrap();
    let solved = Identification::for_free_flyer(&ff, Rows::Base)
        .solve(&red)
        .unwrap();
    let theta = solved.theta.clone();
    let fit = held_out_rms(&ff, &test, &theta, Rows::Base);
    let floor = held_out_rms(&ff, &test, &truth(&ff), Rows::Base);
    println!("held-out base wrench RMS {fit:.5} (floor {floor:.5})");
    assert!(fit <= 1.10 * floor, "{fit} vs floor {floor}");
    for (b, name) in solved.bodies.iter().enumerate() {
        let p = InertialParams(std::array::from_fn(|k| theta[10 * b + k]));
        let min_eig = p.pseudo_inertia().symmetric_eigenvalues().min();
        assert!(
            min_eig >= -1e-9,
            "body {name}: J has eigenvalue {min_eig:e}"
        );
    }
    // the whole robot, at two configurations
    let mut fitted = ff.clone();
    fitted.set_params(&theta[..10 * ff.num_bodies()]).unwrap();
    let mut data = Data::new(&ff);
    for k in [0, 1234] {
        let q = &test.state(k).0;
        let (m0, c0, i0) = ff.centroidal(&mut data, q).unwrap();
        let (m1, c1, i1) = fitted.centroidal(&mut data, q).unwrap();
        let rel = (i1 - i0).norm() / i0.norm();
        println!(
            "sample {k}: mass {m1:.4} / {m0:.4}, CoM {:.4?} / {:.4?}, inertia off by {rel:.4}",
            c1.as_slice(),
            c0.as_slice()
        );
        assert!((m1 - m0).abs() <= 0.01 * m0, "mass {m1} vs {m0}");
        // a CoM within 1 % of the robot's size (its base is 0.39 m long)
        assert!((c1 - c0).norm() <= 0.01 * 0.39, "CoM {c1:?} vs {c0:?}");
        assert!(rel <= 0.01, "centroidal inertia off by {rel:.4}");
    }
}

#[test]
fn joint_rows_reach_their_floor_too() {
    let ff = solo();
    let (train, test) = logs(&ff);
    for rows in [Rows::Joints, Rows::All] {
        let red = reduce_floating(&ff, &train, rows).unwrap();
        let solved = Identification::for_free_flyer(&ff, rows)
            .solve(&red)
            .unwrap();
        let fit = held_out_rms(&ff, &test, &solved.theta, Rows::Joints);
        let floor = held_out_rms(&ff, &test, &truth(&ff), Rows::Joints);
        println!("{rows:?}: held-out joint torque RMS {fit:.5} (floor {floor:.5})");
        assert!(fit <= 1.10 * floor, "{rows:?}: {fit} vs floor {floor}");
    }
}

#[test]
fn a_log_that_does_not_fit_is_named() {
    let ff = solo();
    let (mut log, _) = logs(&ff);
    log.contacts[0].frame = "harness".into();
    let e = reduce_floating(&ff, &log, Rows::Base)
        .unwrap_err()
        .to_string();
    assert!(e.contains("contact frame 'harness'"), "{e}");
    let (mut log, _) = logs(&ff);
    log.base.as_mut().unwrap().pose[7][6] = 0.5; // sample 7's quaternion w
    let e = reduce_floating(&ff, &log, Rows::Base)
        .unwrap_err()
        .to_string();
    assert!(e.contains("sample 7") && e.contains("norm"), "{e}");
    let (mut log, _) = logs(&ff);
    log.contacts[0].wrench.truncate(60);
    let e = reduce_floating(&ff, &log, Rows::Base)
        .unwrap_err()
        .to_string();
    assert!(e.contains("wrench of 'base_link'"), "{e}");
    let (mut log, _) = logs(&ff);
    log.tau.clear(); // no torques measured
    assert!(reduce_floating(&ff, &log, Rows::Base).is_ok());
    let e = reduce_floating(&ff, &log, Rows::Joints)
        .unwrap_err()
        .to_string();
    assert!(e.contains("torques"), "{e}");
}

#[test]
fn rows_and_set_ups_that_do_not_match_are_named() {
    let ff = solo();
    let cfg = SuspendedConfig {
        seconds: 2.0,
        ..SuspendedConfig::default()
    };
    let log = simulate_suspended(&ff, &cfg).unwrap();
    let red = reduce_floating(&ff, &log, Rows::Base).unwrap();
    let e = Identification::for_free_flyer(&ff, Rows::All)
        .solve(&red)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rows 0..6") && e.contains("rows 0..18"), "{e}");
    // as many rows, other ones: the joint rows of a robot with six joints
    let mut red = reduce_floating(&ff, &log, Rows::Base).unwrap();
    red.row_range = Some(6..12);
    let e = Identification::for_free_flyer(&ff, Rows::Base)
        .solve(&red)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rows 6..12"), "{e}");
    // the fixed-base steps refuse a free-flyer's set-up (its columns are
    // not its tree's)
    let names = ff.joint_names();
    let d = momentlmi::data::Dataset::empty(&names);
    let e = Identification::for_free_flyer(&ff, Rows::Base)
        .fit(&d)
        .unwrap_err()
        .to_string();
    assert!(e.contains("needs a fixed-base model"), "{e}");
}

/// Every row, weighted: each group by 1/σ̂² of an unweighted fit first
/// (N and N·m rows of unlike noise), then every group at its floor.
#[test]
fn all_rows_weighted_reach_every_floor() {
    use momentlmi::identify::floating_fit::{fit_floating, floating_rms};
    let ff = solo();
    let (train, test) = logs(&ff);
    let id = Identification::for_free_flyer(&ff, Rows::All);
    let fit = fit_floating(&id, &ff, Rows::All, &[train], std::slice::from_ref(&test)).unwrap();
    let w = fit.row_weights.as_ref().unwrap();
    // σ̂ ≈ 0.24 N on the force rows, 0.02 N·m on the joints'
    assert!(
        w[0] > 10.0 && w[0] < 30.0 && w[6] > 1000.0 && w[6] < 4000.0,
        "{w:?}"
    );
    let (v, floor) = (
        fit.validation.unwrap(),
        floating_rms(&ff, &truth(&ff), &test).unwrap(),
    );
    println!("held-out {v:?}\nfloor {floor:?}");
    assert!(v.base_force <= 1.05 * floor.base_force && v.base_moment <= 1.05 * floor.base_moment);
    for (a, b) in v.joints.iter().zip(&floor.joints) {
        assert!(
            *a <= 1.05 * b,
            "joints {:?} vs floor {:?}",
            v.joints,
            floor.joints
        );
    }
}

/// The fixed base's set-up on a free flyer (one `Model`, one
/// `Identification`): Solo12 described with a free-flying root — every
/// body's bounding ellipsoid from its URDF geometry, the base's from the
/// root link's — fitted on the base rows alone at the ellipsoid level, and
/// under the entropic prior toward a model 20 % too heavy: held-out base
/// wrench at the floor, every body consistent (and realizable in its
/// ellipsoid at that level).
#[test]
fn the_ellipsoid_level_and_the_entropic_prior_reach_the_floor_from_base_rows() {
    use momentlmi::dynamics::robots::load_free_flyer;
    use momentlmi::identify::{Level, Regularizer};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let urdf = root.join("robots/solo12/solo12.urdf");
    let robot = load_free_flyer(urdf.to_str().unwrap(), None, &[]).unwrap();
    let ff = &robot.model;
    assert_eq!(robot.bounding().len(), ff.num_bodies());
    assert!(
        robot.bounding().iter().all(|b| !b.is_empty()),
        "every body bounded, the base included"
    );
    let (train, test) = logs(ff);
    let red = reduce_floating(ff, &train, Rows::Base).unwrap();
    let floor = held_out_rms(ff, &test, &truth(ff), Rows::Base);
    let heavy: Vec<f64> = ff.params().iter().map(|x| 1.2 * x).collect();
    let set_ups = [
        (
            "ellipsoid",
            Identification::for_robot(&robot, Level::Ellipsoid, 0.0).unwrap(),
        ),
        (
            "entropic",
            (Identification::for_robot(&robot, Level::Consistent, 1e-2).unwrap())
                .prior(1e-2, heavy)
                .unwrap()
                .regularizer(Regularizer::Entropic),
        ),
    ];
    for (name, id) in set_ups {
        let solved = id.rows(Rows::Base).solve(&red).unwrap();
        let fit = held_out_rms(ff, &test, &solved.theta, Rows::Base);
        println!("{name}: held-out base wrench RMS {fit:.5} (floor {floor:.5})");
        assert!(fit <= 1.10 * floor, "{name}: {fit} vs floor {floor}");
        for (b, body) in ff.body_names().iter().enumerate() {
            let p = InertialParams(std::array::from_fn(|k| solved.theta[10 * b + k]));
            let min_eig = p.pseudo_inertia().symmetric_eigenvalues().min();
            assert!(
                min_eig >= -1e-9,
                "{name}: body {body}: J eigenvalue {min_eig:e}"
            );
            if name == "ellipsoid" {
                let e = &robot.bounding()[b][0];
                let r = momentlmi::moments::check_realizable(&p, e, 1e-8);
                assert!(r.realizable, "{name}: body {body} outside its ellipsoid");
            }
        }
    }
}
