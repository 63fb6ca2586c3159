//! The example programs, run and checked (each `examples/*.rs` exposes a
//! `run` the test calls).

#[path = "../examples/confusion_real.rs"]
mod confusion_real;
#[path = "../examples/custom_constraints.rs"]
mod custom_constraints;
#[path = "../examples/custom_effect.rs"]
mod custom_effect;
#[path = "../examples/lambda_max.rs"]
mod lambda_max;
#[path = "../examples/lovasz_theta.rs"]
mod lovasz_theta;
#[path = "../examples/misuse.rs"]
mod misuse;
#[path = "../examples/nearest_psd.rs"]
mod nearest_psd;

use momentlmi::conic::ConicError;
use nalgebra::DMatrix;

#[test]
fn lambda_max_and_its_dual_are_the_top_eigenpair() {
    let a = DMatrix::from_row_slice(3, 3, &[2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0]);
    let (lmax, z, kkt) = lambda_max::run(&a).unwrap();
    let e = a.clone().symmetric_eigen();
    let (k, top) = e.eigenvalues.argmax();
    assert!((lmax - top).abs() < 1e-7, "{lmax} vs {top}");
    let v = e.eigenvectors.column(k);
    assert!((&z - v * v.transpose()).abs().max() < 1e-6, "{z}");
    assert!(kkt < 1e-6);
}

#[test]
fn lovasz_theta_of_the_five_cycle_is_root_five() {
    let c5: Vec<(usize, usize)> = (0..5).map(|i| (i, (i + 1) % 5)).collect();
    let (theta, price) = lovasz_theta::run(5, &c5).unwrap();
    assert!((theta - 5f64.sqrt()).abs() < 1e-7, "{theta}");
    assert!((price - theta).abs() < 1e-6, "{price}");
    // the complete graph K4 has θ = 1, the empty graph on 4 vertices θ = 4
    let k4: Vec<(usize, usize)> = (0..4)
        .flat_map(|i| (i + 1..4).map(move |j| (i, j)))
        .collect();
    assert!((lovasz_theta::run(4, &k4).unwrap().0 - 1.0).abs() < 1e-7);
    assert!((lovasz_theta::run(4, &[]).unwrap().0 - 4.0).abs() < 1e-6);
}

#[test]
fn the_nearest_psd_matrix_is_the_clipped_eigendecomposition() {
    let c = DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 0.0, 2.0, 1.0, 0.5, 0.0, 0.5, -0.5]);
    let x = nearest_psd::run(&c).unwrap();
    assert!((&x - nearest_psd::clipped(&c)).abs().max() < 1e-6, "{x}");
    // a PSD matrix is its own nearest
    let s = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 3.0]);
    assert!((nearest_psd::run(&s).unwrap() - &s).abs().max() < 1e-6);
}

#[test]
fn the_two_body_constraint_set_bounds_the_link() {
    let (small, pts) = custom_constraints::run(false).unwrap();
    // the least Izz: 1 kg on the axis through the CoM, m·x² = 1 · 0.14²
    assert!((small.mass() - 1.0).abs() < 1e-6);
    assert!(
        (small.0[9] - 0.14f64.powi(2)).abs() < 1e-6,
        "{}",
        small.0[9]
    );
    let (large, _) = custom_constraints::run(true).unwrap();
    assert!((large.mass() - 2.0).abs() < 1e-6 && large.0[9] > 10.0 * small.0[9]);
    // the four point masses reproduce the body
    let total: f64 = pts.iter().map(|p| p.mass).sum();
    assert!((total - small.mass()).abs() < 1e-6);
    let com = pts
        .iter()
        .map(|p| p.position * p.mass)
        .sum::<nalgebra::Vector3<f64>>()
        / total;
    assert!((com - small.com()).norm() < 1e-6);
}

#[test]
fn every_misuse_is_a_named_error() {
    let errors = misuse::run().unwrap();
    assert_eq!(errors.len(), 9, "{errors:?}");
    let kinds: Vec<&str> = errors
        .iter()
        .map(|(_, e)| match e {
            ConicError::ForeignHandle { .. } => "foreign",
            ConicError::DimensionMismatch { .. } => "dimension",
            ConicError::NotSolved { .. } => "not solved",
            ConicError::NegativeWeight { .. } => "weight",
            _ => "other",
        })
        .collect();
    assert_eq!(
        kinds,
        [
            "foreign",
            "foreign",
            "dimension",
            "dimension",
            "dimension",
            "not solved",
            "foreign",
            "not solved",
            "weight"
        ]
    );
}

#[path = "../examples/identify_constrained.rs"]
mod identify_constrained;

#[test]
fn the_constrained_identification_example_holds_its_constraints() {
    let r = identify_constrained::run(5.25).unwrap();
    let total: f64 = r.bodies.iter().map(|b| b.mass).sum();
    assert!((total - 5.25).abs() < 1e-6);
    let knee = r.body("knee").unwrap();
    assert!(knee.realizability.as_ref().unwrap().realizable);
    let (a, b) = (r.body("hip_rotor").unwrap(), r.body("knee_rotor").unwrap());
    assert!((0..10).all(|k| (a.params[k] - b.params[k]).abs() < 1e-7 * (1.0 + a.params[k].abs())));
    assert!(r.constraints_satisfied);
}

/// The user's own effect (`examples/custom_effect.rs`): simulated, the
/// diagnosis accepts it first and fits its amplitude; absent, it is not
/// accepted (nor anything else) — on the leg and on the Panda arm.
#[test]
fn a_users_own_effect_is_found_when_present_and_not_accepted_when_absent() {
    use momentlmi::dynamics::robots::load_robot;
    let leg = load_robot("cheetah3-leg", None).unwrap();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let urdf = dir.join("panda.urdf");
    let arm = load_robot(urdf.to_str().unwrap(), Some(&dir.join("panda.toml"))).unwrap();
    let cases = [
        (&leg, "hip", "rotor_inertia,coulomb,viscous"),
        (&arm, "panda_joint4", "coulomb,viscous"),
    ];
    for (robot, joint, base) in cases {
        let d = custom_effect::run(robot, joint, base, true).unwrap();
        assert_eq!(
            d.accepted,
            ["cable_spring"],
            "{}",
            custom_effect::verdict(&d)
        );
        let e = d.effect("cable_spring").unwrap();
        assert!(e.accepted && e.round == 1);
        // the fitted amplitude, from the report's detail: 0.6 N·m simulated
        let k: f64 = e.detail["k = ".len()..]
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!((k - 0.6).abs() < 0.03, "{}", e.detail);
        assert!(e.joints == [joint], "{:?}", e.joints);
        let none = custom_effect::run(robot, joint, base, false).unwrap();
        assert!(
            none.accepted.is_empty(),
            "{}",
            custom_effect::verdict(&none)
        );
        let e = none.effect("cable_spring").expect("it was evaluated");
        assert!(!e.accepted);
    }
}

/// A user's effect that names a joint the robot lacks is an error naming
/// the effect and the joint; a second effect of a built-in name is refused.
#[test]
fn a_users_effect_that_does_not_fit_is_a_named_error() {
    use momentlmi::effects::{EffectError, Library};
    use momentlmi::sim::{Effects, SimConfig};
    let leg = momentlmi::dynamics::cheetah3::description();
    let lib = Library::builtin()
        .with(custom_effect::CableSpring { joint: "elbow" })
        .unwrap();
    let cfg = SimConfig::for_robot(&leg, 1.0, Effects::new(["cable_spring"]), 1);
    let e = lib.simulate(&leg, &cfg, |_, _| {}).unwrap_err().to_string();
    assert!(e.contains("cable_spring") && e.contains("'elbow'"), "{e}");
    struct Impostor;
    impl momentlmi::effects::Effect for Impostor {
        fn name(&self) -> &'static str {
            "coulomb"
        }
        fn summary(&self) -> &'static str {
            "not the built-in one"
        }
        fn apply(
            &self,
            _: &momentlmi::effects::Values,
            _: &mut momentlmi::sim::Truth,
        ) -> Result<(), EffectError> {
            Ok(())
        }
        fn hypothesis(
            &self,
            _: &momentlmi::effects::Context,
        ) -> Result<momentlmi::effects::Hypothesis, EffectError> {
            Ok(momentlmi::effects::Hypothesis::none())
        }
    }
    let e = Library::builtin().with(Impostor).unwrap_err();
    assert!(
        matches!(e, EffectError::Duplicate(ref n) if n == "coulomb"),
        "{e}"
    );
}

/// The KUKA's untouched run 3 against a nominal that knows what runs 1–2
/// showed and were (their own effects in it, their data given to the
/// diagnosis: `--nominal-data`): no payload is named — the 0.05 kg one the
/// nominal as identified is named with is its own estimation error — while
/// an injected 1 kg payload still comes out within 0.1 kg (measured
/// 2026-12-07: accepted `time_delay` on two wrist joints only; 0.993 kg;
/// held as identified: `ripple`, `time_delay`, `payload`).
#[test]
fn the_untouched_real_run_names_no_payload_against_a_nominal_that_knows_its_data() {
    let inertial = |d: &momentlmi::diagnose::Diagnosis| {
        (d.accepted.iter()).any(|a| a == "payload" || a == "link_inertia")
    };
    let nominal = confusion_real::Nominal {
        own_effects: false,
        own_data: true,
    };
    let (null, rows) = confusion_real::run("payload", &[], nominal).unwrap();
    assert!(!inertial(&null), "{:?}", null.accepted);
    let payload = rows.iter().find(|r| r.effect == "payload").unwrap();
    let (mass, truth) = payload.fitted.unwrap();
    assert!(payload.found && (mass - truth).abs() <= 0.1, "{mass} kg");
    // held as identified, the same run names one
    let (held, _) = confusion_real::run("none", &[], confusion_real::Nominal::default()).unwrap();
    assert!(inertial(&held), "{:?}", held.accepted);
}

/// The real-data confusion table (`examples/confusion_real.rs`, the KUKA
/// of `robots/kuka-lwr4`): every case diagnosed; the ones on the shoulder
/// joint — a 5 % sensor gain, a 20 ms torque delay, a 2° encoder offset —
/// are accepted there; a 1 kg payload comes out within 0.1 kg; a change of
/// a term the nominal law has (an offset, Coulomb, load friction) comes out
/// of the law's refit within 20 %; 18 of the 21 cases are found (measured
/// 2026-12-06, docs/diagnosis.md; the misses: a viscous change under the
/// shoulder's repeatability, a delay and an encoder offset on the elbow).
#[test]
fn injected_effects_on_real_data_are_found_on_their_joint() {
    let (_, rows) = confusion_real::run("", &[], confusion_real::Nominal::default()).unwrap();
    assert_eq!(rows.len(), 21);
    for effect in ["torque_gain", "time_delay", "joint_offset"] {
        let r = rows
            .iter()
            .find(|r| r.effect == effect && r.joint == "lwr_1_joint")
            .unwrap();
        // injected well above the repeatability there
        assert!(r.size.0 > 2.0 * r.size.1, "{}: {:?}", r.case, r.size);
        assert!(
            r.found && r.how == "accepted",
            "{}: accepted {}",
            r.case,
            r.accepted
        );
    }
    let payload = rows.iter().find(|r| r.effect == "payload").unwrap();
    let (mass, truth) = payload.fitted.unwrap();
    assert!(payload.found && (mass - truth).abs() <= 0.1, "{mass} kg");
    for r in rows.iter().filter(|r| r.how == "law refit" && r.found) {
        let (fit, truth) = r.fitted.unwrap();
        assert!(
            (fit - truth).abs() <= 0.2 * truth,
            "{}: {fit} vs {truth}",
            r.case
        );
    }
    let found = rows.iter().filter(|r| r.found).count();
    assert!(found >= 18, "found {found} of {}", rows.len());
}
