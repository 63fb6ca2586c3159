//! `--friction auto` (issue 56): the friction law chosen by cross-validation
//! on the training data picks viscous + Coulomb when that is the truth, and
//! a simulated Stribeck or load-dependent friction when it is present.

use momentlmi::dynamics::robots::load_robot;
use momentlmi::dynamics::{FrictionTerm, RobotDescription};
use momentlmi::effects::simulate;
use momentlmi::identify::{Identification, Level};
use momentlmi::sim::{Effects, SimConfig};

fn panda() -> RobotDescription {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    load_robot(
        dir.join("panda.urdf").to_str().unwrap(),
        Some(&dir.join("panda.toml")),
    )
    .unwrap()
}

/// The law chosen on 10 s of the Panda simulated with `effects`.
fn chosen(robot: &RobotDescription, effects: &str) -> (Vec<FrictionTerm>, Option<f64>) {
    let cfg = SimConfig::for_robot(robot, 10.0, Effects::parse(effects, &[]).unwrap(), 3);
    let d = simulate(robot, &cfg, |_, _| {}).unwrap();
    let c = Identification::for_robot(robot, Level::Consistent, 1e-6)
        .unwrap()
        .choose_friction(&d)
        .unwrap();
    assert_eq!(c.laws.len(), 20, "every law is scored");
    assert!(c.laws[c.chosen].mean_rms <= 1.02 * c.laws[c.best].mean_rms);
    (c.terms(), c.stribeck_velocity())
}

#[test]
fn viscous_and_coulomb_are_chosen_when_they_are_the_truth() {
    let (terms, vs) = chosen(&panda(), "coulomb,viscous");
    assert_eq!(terms, FrictionTerm::DEFAULT.to_vec());
    assert_eq!(vs, None);
}

#[test]
fn a_simulated_stribeck_friction_is_chosen_with_its_velocity() {
    // the simulator's Stribeck velocity is 0.2 rad/s
    let (terms, vs) = chosen(&panda(), "coulomb,viscous,stribeck");
    assert!(terms.contains(&FrictionTerm::Stribeck), "{terms:?}");
    assert_eq!(vs, Some(0.2));
    assert!(!terms.contains(&FrictionTerm::Load), "{terms:?}");
}

#[test]
fn a_simulated_load_friction_is_chosen() {
    let (terms, _) = chosen(&panda(), "coulomb,viscous,load_friction");
    assert!(terms.contains(&FrictionTerm::Load), "{terms:?}");
    assert!(!terms.contains(&FrictionTerm::Stribeck), "{terms:?}");
}

/// The prior's weight chosen with the law (`--friction auto --weight
/// auto`): with the prior the simulation's own parameters, the strongest
/// weight within the noise is large; with a prior 1.5× every body's, the
/// data pull away from it and the weight chosen is smaller.
#[test]
fn the_weight_is_chosen_with_the_law_strong_for_a_true_prior_weak_for_a_wrong_one() {
    use momentlmi::identify::friction_choice::WEIGHTS;
    let robot = panda();
    let effects = Effects::parse("coulomb,viscous", &[]).unwrap();
    let cfg = SimConfig::for_robot(&robot, 10.0, effects, 3);
    let d = simulate(&robot, &cfg, |_, _| {}).unwrap();
    let id = Identification::for_robot(&robot, Level::Consistent, 1e-6).unwrap();
    let c = id.choose_model(&d, &WEIGHTS).unwrap();
    assert_eq!(
        c.laws.len(),
        20 * WEIGHTS.len(),
        "every law at every weight"
    );
    assert!(c.weight_chosen());
    assert_eq!(c.terms(), FrictionTerm::DEFAULT.to_vec());
    let strong = c.weight();
    assert!(strong >= 1e-2, "true prior: weight {strong:e}");
    let nb = robot.model.num_bodies();
    let wrong: Vec<f64> = (0..nb)
        .flat_map(|b| id.prior_body(b).unwrap().0.map(|x| 1.5 * x))
        .collect();
    let id = Identification::for_robot(&robot, Level::Consistent, 1e-6)
        .unwrap()
        .prior(1e-6, wrong)
        .unwrap();
    let c = id.choose_model(&d, &WEIGHTS).unwrap();
    assert_eq!(c.terms(), FrictionTerm::DEFAULT.to_vec());
    // (measured: the curve is flat to 1e-2 and 14 % up at 1)
    assert!(
        c.weight() < strong && c.weight() <= 0.1,
        "wrong prior: weight {:e}",
        c.weight()
    );
    // and a weight given is the only one tried
    let c = id.choose_friction(&d).unwrap();
    assert!(!c.weight_chosen() && c.weight() == 1e-6);
}

/// Training data without torques is a named error, not a panic.
#[test]
fn data_without_torques_is_an_error_naming_it() {
    let robot = panda();
    let cfg = SimConfig::for_robot(&robot, 1.0, Effects::parse("", &[]).unwrap(), 3);
    let mut d = simulate(&robot, &cfg, |_, _| {}).unwrap();
    d.tau = momentlmi::dynamics::Samples::new(d.joints.len());
    let e = Identification::for_robot(&robot, Level::Consistent, 1e-6)
        .unwrap()
        .choose_friction(&d)
        .unwrap_err();
    assert!(
        matches!(
            e,
            momentlmi::identify::IdentifyError::NoTrainingData { torques: 0, .. }
        ),
        "{e}"
    );
}
