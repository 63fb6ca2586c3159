//! Identification open to the caller's constraints: a known total mass, the
//! ellipsoid level on one body only, two bodies forced equal — each holds in
//! the result — and results read by body and joint name.

use momentlmi::data::Dataset;
use momentlmi::dynamics::cheetah3;
use momentlmi::effects::simulate;
use momentlmi::identify::{Identification, IdentifyError, Level, Reduced, reduce_samples};
use momentlmi::moments::check_realizable;
use momentlmi::sim::{Effects, SimConfig};

fn leg_data() -> Dataset {
    let leg = cheetah3::description();
    let fx = Effects::new(["rotor_inertia", "coulomb", "viscous"]);
    simulate(&leg, &SimConfig::for_robot(&leg, 8.0, fx, 5), |_, _| {}).unwrap()
}

#[test]
fn the_leg_with_a_known_mass_the_ellipsoid_on_the_knee_and_equal_rotors() {
    let leg = cheetah3::description();
    let d = leg_data();
    let (train, val) = (d.slice(0..5000), d.slice(5000..8000));
    let names = leg.model.body_names();
    let true_total: f64 = (0..names.len()).map(|b| leg.model.params()[10 * b]).sum();
    let total = true_total + 0.05; // what the scale said
    let id = Identification::for_robot(&leg, Level::Consistent, 1e-6)
        .unwrap()
        .level("knee", Level::Ellipsoid)
        .unwrap()
        .constrain(move |p, v| {
            p.add_eq(v.total_mass(), total)?;
            v.body("hip_rotor")?.add_equal(p, v.body("knee_rotor")?)?;
            Ok(())
        });
    let r = id.identify(&train, Some(&val)).unwrap();
    assert!(r.constraints_satisfied, "{:?}", r.status);
    // (a) the masses add up to the known total
    let sum: f64 = r.bodies.iter().map(|b| b.mass).sum();
    assert!((sum - total).abs() < 1e-6, "{sum} vs {total}");
    // (b) the knee is realizable in its ellipsoid; the others are only asked to be consistent
    let knee = r.body("knee").unwrap();
    assert_eq!(knee.level, Level::Ellipsoid);
    assert!(check_realizable(&knee.params(), &cheetah3::ellipsoids()[2], 1e-7).realizable);
    assert_eq!(r.body("hip").unwrap().level, Level::Consistent);
    assert!(r.bodies.iter().all(|b| b.consistent));
    // (c) the two rotors have the same parameters
    let (a, b) = (r.body("hip_rotor").unwrap(), r.body("knee_rotor").unwrap());
    for k in 0..10 {
        assert!(
            (a.params[k] - b.params[k]).abs() < 1e-7 * (1.0 + a.params[k].abs()),
            "{k}"
        );
    }
    // the fit is still at the noise floor (σ = 0.3 N·m)
    assert!(r.validation_rms.as_ref().unwrap().iter().all(|&v| v < 0.45));
    // read by joint name
    let (viscous, coulomb) = r.friction("knee").unwrap();
    assert!(viscous >= 0.0 && (coulomb - 0.95).abs() < 0.1, "{coulomb}");
    assert!(matches!(
        r.body("shin"),
        Err(IdentifyError::UnknownName { .. })
    ));
}

#[test]
fn hooks_see_every_body_and_joint_and_conflicts_are_named() {
    let leg = cheetah3::description();
    let d = leg_data();
    let red = reduce_samples(&leg.model, &d.q, &d.qd, &d.qdd, &d.tau, 1024).unwrap();
    // a CoM pinned in a hook, read back by name from `Solved`
    let pin = nalgebra::Vector3::new(0.0, 0.0, -0.15);
    let solved = Identification::for_robot(&leg, Level::Consistent, 1e-6)
        .unwrap()
        .constrain(move |p, v| {
            assert_eq!(v.bodies().count(), 6);
            v.body("knee")?.add_com(p, pin)?;
            p.add_ge(v.coulomb("abad")?, 3.0)?;
            Ok(())
        })
        .solve(&red)
        .unwrap();
    let knee = solved.body("knee").unwrap();
    assert!((knee.com() - pin).norm() < 1e-6, "{:?}", knee.com());
    assert!(solved.friction("abad").unwrap().1 >= 3.0 - 1e-7);
    // unknown names in a hook are errors naming the valid ones
    let e = Identification::new(&leg.model)
        .constrain(|p, v| {
            p.add_eq(v.body("shin")?.mass(), 1.0)?;
            Ok(())
        })
        .solve(&red)
        .unwrap_err()
        .to_string();
    assert!(e.contains("'shin'") && e.contains("knee_rotor"), "{e}");
    assert!(
        Identification::new(&leg.model)
            .level("shin", Level::None)
            .is_err()
    );
    // contradictory constraints: infeasible, reported with the solver status
    let e = Identification::new(&leg.model)
        .constrain(|p, v| {
            p.add_le(v.total_mass(), -1.0)?;
            Ok(())
        })
        .solve(&red)
        .unwrap_err();
    assert!(
        matches!(e, IdentifyError::Solver(s) if s.is_primal_infeasible()),
        "{e}"
    );
    // the ellipsoid level on a body without an ellipsoid names it
    let e = Identification::new(&leg.model)
        .level("hip", Level::Ellipsoid)
        .unwrap()
        .solve(&red)
        .unwrap_err()
        .to_string();
    assert!(e.contains("body 'hip' has no bounding ellipsoid"), "{e}");
}

#[test]
fn reduced_data_from_a_gram_matrix_are_validated() {
    let leg = cheetah3::description();
    let d = leg_data();
    let red = reduce_samples(&leg.model, &d.q, &d.qd, &d.qdd, &d.tau, 1024).unwrap();
    let again = Reduced::from_gram(red.gram.clone(), red.samples).unwrap();
    assert_eq!(again.p, red.p);
    let a = Identification::new(&leg.model).solve(&red).unwrap();
    let b = Identification::new(&leg.model).solve(&again).unwrap();
    assert_eq!(a.theta, b.theta);
    let mut bad = red.gram.clone();
    bad[(0, 1)] += 1.0; // not symmetric
    assert!(Reduced::from_gram(bad, red.samples).is_err());
    let mut nan = red.gram.clone();
    nan[(2, 2)] = f64::NAN;
    assert!(Reduced::from_gram(nan, red.samples).is_err());
    assert!(Reduced::from_gram(faer::Mat::zeros(3, 4), 10).is_err());
    assert!(Reduced::from_gram(red.gram.clone(), 0).is_err());
}
