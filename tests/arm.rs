//! The Panda arm in `robots/panda` (URDF, sidecar and collision meshes in the
//! repository): simulated with the defaults, identified with the same code
//! path as the leg, from a prior that is not the truth.

use momentlmi::diagnose::{DiagnoseOptions, diagnose};
use momentlmi::dynamics::RobotDescription;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::effects::simulate;
use momentlmi::identify::{
    Identification, IdentifyOptions, IdentifyResult, IdentifyWarning, Level, Regularizer,
};
use momentlmi::sim::{Effects, SimConfig};
use std::path::Path;

fn panda() -> RobotDescription {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let urdf = dir.join("panda.urdf");
    load_robot(urdf.to_str().unwrap(), Some(&dir.join("panda.toml"))).unwrap()
}

/// The URDF's inertias, each body's π scaled by 0.7 or 1.3 in turn (a scaled
/// π stays physically consistent).
fn perturbed_prior(r: &RobotDescription) -> Vec<f64> {
    r.prior
        .iter()
        .enumerate()
        .flat_map(|(b, p)| {
            let f = if b % 2 == 0 { 1.3 } else { 0.7 };
            p.0.map(|x| x * f)
        })
        .collect()
}

/// 15 s of the arm with Coulomb and viscous friction (the defaults otherwise).
fn friction_data(r: &RobotDescription, seed: u64) -> momentlmi::data::Dataset {
    let effects = Effects::new(["coulomb", "viscous"]);
    let cfg = SimConfig::for_robot(r, 15.0, effects, seed);
    simulate(r, &cfg, |_, _| {}).unwrap()
}

/// (identified error − prior's error) per link mass (kg).
fn excess_mass_error(r: &RobotDescription, prior: &[f64], res: &IdentifyResult) -> Vec<f64> {
    (0..res.bodies.len())
        .map(|b| {
            let truth = r.model.params()[10 * b];
            (res.bodies[b].mass - truth).abs() - (prior[10 * b] - truth).abs()
        })
        .collect()
}

/// Issue 17's criterion with `identify`'s defaults for this robot (the
/// Euclidean prior with weight 1e-6, and the masses' extra weight 1e-2 its
/// sidecar sets) from a prior that is not the truth: held-out RMS within
/// 1.1 σ, every body consistent, and (consistent level) no link mass further
/// from the truth than the prior's nor more than 50 % off. No torque of a
/// fixed-base arm sees a link mass alone: the masses stay at the prior
/// (measured within 2e-6 kg) and the first moments and inertias take the
/// data's corrections.
#[test]
fn the_arm_identifies_to_the_noise_floor_from_a_wrong_prior() {
    let r = panda();
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    assert_eq!(r.identification.prior_mass_weight, Some(1e-2));
    let (train, val) = (friction_data(&r, 1), friction_data(&r, 2));
    let prior = perturbed_prior(&r);
    for level in [Level::Consistent, Level::Ellipsoid] {
        let res = Identification::for_robot(&r, level, 1e-6)
            .unwrap()
            .prior(1e-6, prior.clone())
            .unwrap()
            .identify(&train, Some(&val))
            .unwrap();
        assert_eq!(res.prior_mass_weight, 1e-2);
        let rms = res.validation_rms.clone().unwrap();
        for (j, v) in rms.iter().enumerate() {
            assert!(
                *v <= 1.1 * 0.3,
                "{level:?}: joint {j}: held-out RMS {v} > 1.1 σ"
            );
        }
        assert!(res.bodies.iter().all(|b| b.consistent), "{level:?}");
        // the URDF prior outside the meshes' ellipsoids is said, by body
        let outside = res.warnings.iter().find_map(|w| match w {
            IdentifyWarning::PriorOutsideEllipsoid { bodies } => Some(bodies),
            _ => None,
        });
        match level {
            Level::Ellipsoid => {
                let w = outside.expect("a warning at the ellipsoid level");
                assert!(
                    w.iter().any(|b| b == "panda_link1") && !w.iter().any(|b| b == "panda_link6"),
                    "{w:?}"
                );
            }
            _ => assert!(outside.is_none(), "{outside:?}"),
        }
        if level == Level::Ellipsoid {
            // the URDF's own inertias (the truth here) are not density
            // realizable in the collision meshes' ellipsoids for six of the
            // seven links (`momentlmi check`): the masses cannot come back
            continue;
        }
        for (b, e) in excess_mass_error(&r, &prior, &res).iter().enumerate() {
            let (name, mass) = (&res.bodies[b].name, res.bodies[b].mass);
            let truth = r.model.params()[10 * b];
            assert!(*e <= 1e-5, "{name}: {e} kg further than the prior");
            assert!(
                (mass - truth).abs() <= 0.5 * truth,
                "{name} mass {mass} (truth {truth})"
            );
        }
    }
}

/// The masses' extra weight is what keeps them: without it (0) the
/// Euclidean prior's minimum-norm correction of the mass combinations moves
/// link3 and link5 further from the truth (link5 by 0.1 kg), the held-out
/// RMS the same; with it, the direct least squares (no constraints) keeps
/// them too. With the prior off (weight 0) the sidecar's weight is not taken.
#[test]
fn without_the_masses_weight_the_euclidean_prior_moves_masses_that_were_right() {
    let r = panda();
    let (train, val) = (friction_data(&r, 1), friction_data(&r, 2));
    let prior = perturbed_prior(&r);
    let run = |level: Level, mass_weight: Option<f64>| {
        let id = Identification::for_robot(&r, level, 1e-6)
            .unwrap()
            .prior(1e-6, prior.clone())
            .unwrap();
        let id = match mass_weight {
            Some(w) => id.prior_mass_weight(w).unwrap(),
            None => id,
        };
        id.identify(&train, Some(&val)).unwrap()
    };
    let res = run(Level::None, None);
    for (j, v) in res.validation_rms.clone().unwrap().iter().enumerate() {
        assert!(*v <= 1.1 * 0.3, "none: joint {j}: held-out RMS {v} > 1.1 σ");
    }
    for (b, e) in excess_mass_error(&r, &prior, &res).iter().enumerate() {
        let name = &res.bodies[b].name;
        assert!(*e <= 1e-5, "none: {name}: {e} kg further than the prior");
    }
    let without = run(Level::Consistent, Some(0.0));
    assert_eq!(without.prior_mass_weight, 0.0);
    for (j, v) in without.validation_rms.clone().unwrap().iter().enumerate() {
        assert!(
            *v <= 1.1 * 0.3,
            "weight 0: joint {j}: held-out RMS {v} > 1.1 σ"
        );
    }
    let worst = excess_mass_error(&r, &prior, &without)
        .into_iter()
        .fold(f64::MIN, f64::max);
    assert!(worst > 0.05, "without the mass weight: {worst}");
}

/// The sidecar's masses' weight is settled from the prior in effect when
/// solving: on with the Euclidean prior on, off with the prior off (weight
/// 0, however it was set) or the entropic prior, and the caller's own
/// weight wins; a weight not ≫ the prior's is a warning in the result.
#[test]
fn the_sidecar_mass_weight_follows_the_prior_in_effect() {
    let r = panda();
    let id = |w: f64| Identification::for_robot(&r, Level::Consistent, w).unwrap();
    let prior = r.prior_vector();
    assert_eq!(id(1e-6).mass_weight(), 1e-2);
    assert_eq!(id(0.0).mass_weight(), 0.0);
    assert_eq!(
        id(1e-6).prior(0.0, prior.clone()).unwrap().mass_weight(),
        0.0
    );
    assert_eq!(
        id(0.0).prior(1e-6, prior.clone()).unwrap().mass_weight(),
        1e-2
    );
    let entropic = id(1e-2).regularizer(Regularizer::Entropic);
    assert_eq!(entropic.mass_weight(), 0.0);
    let own = entropic.prior_mass_weight(1.0).unwrap();
    assert_eq!(own.mass_weight(), 1.0);
    assert_eq!(id(0.0).prior_mass_weight(2.0).unwrap().mass_weight(), 2.0);
    let opts = |w: f64| IdentifyOptions::for_robot(&r, Level::Consistent, w).unwrap();
    assert_eq!(opts(1e-6).prior_mass_weight(), 1e-2);
    assert_eq!(opts(0.0).prior_mass_weight(), 0.0);
    let ent = opts(1e-2).with_regularizer(Regularizer::Entropic);
    assert_eq!(ent.prior_mass_weight(), 0.0);
    // a prior weight of 1e-3 against the masses' 1e-2: not held, and said
    let data = friction_data(&r, 1);
    let weak = |w: f64| {
        Identification::for_robot(&r, Level::None, w)
            .unwrap()
            .identify(&data, None)
            .unwrap()
            .warnings
    };
    assert!(
        weak(1e-3)
            .iter()
            .any(|w| w.to_string().contains("not ≫ the prior's weight"))
    );
    assert!(
        weak(1e-6)
            .iter()
            .all(|w| !matches!(w, IdentifyWarning::MassWeightLow { .. }))
    );
}

/// The withheld-effect benchmark's rules on the arm: the nominal model
/// identified (ellipsoid level) on 20 s of other data with the base
/// effects; 15 s diagnosed, with the withheld effect added.
#[test]
fn the_arm_diagnosis_names_a_withheld_effect_and_invents_none() {
    let r = panda();
    let sim = |effects: &str, seconds, seed| {
        let fx = Effects::parse(effects, &[]).unwrap();
        simulate(&r, &SimConfig::for_robot(&r, seconds, fx, seed), |_, _| {}).unwrap()
    };
    let base = "coulomb,viscous";
    let opts = IdentifyOptions::for_robot(&r, Level::Ellipsoid, 1e-6).unwrap();
    let nominal =
        momentlmi::identify::identify(&r.model, &sim(base, 20.0, 101), None, &opts).unwrap();
    // the sidecar's masses' weight reaches the options' path too
    assert_eq!(nominal.prior_mass_weight, 1e-2);
    let (m, f) = nominal.applied_to(&r.model).unwrap();
    for (withheld, expect) in [
        ("", None),
        ("joint_offset", Some("joint_offset")),
        ("offset", Some("offset")),
        ("ripple", Some("ripple")),
    ] {
        let effects = if withheld.is_empty() {
            base.to_string()
        } else {
            format!("{base},{withheld}")
        };
        let dg = diagnose(&m, &f, &sim(&effects, 15.0, 7), &DiagnoseOptions::default()).unwrap();
        let accepted: Vec<&momentlmi::diagnose::EffectReport> =
            dg.ranked_effects.iter().filter(|e| e.accepted).collect();
        match expect {
            None => assert!(accepted.is_empty(), "null case: accepted {accepted:?}"),
            Some(e) => assert!(
                accepted.iter().any(|a| a.covers(e)),
                "{withheld}: accepted {accepted:?}"
            ),
        }
        assert!(!dg.unexplained, "{withheld}: {:?}", dg.unexplained_where);
        if withheld == "joint_offset" {
            // the offsets fitted are reported: 0.05 rad on joints 2–6 (to
            // 0.015; the seventh barely loaded), none on joint 1, whose axis
            // is along gravity (its offset changes no torque)
            let e = dg.effect(withheld).unwrap();
            let d = e.fitted("joint_offsets").unwrap();
            assert!(d[0].abs() < 0.01, "{}", e.detail);
            assert!(
                d[1..6].iter().all(|x| (x - 0.05).abs() < 0.015),
                "{}",
                e.detail
            );
        }
        // no motor side: the compliance and cogging hypotheses are not proposed, and say so
        assert!(
            dg.warnings
                .iter()
                .any(|w| w.to_string().starts_with("elasticity: not proposed"))
        );
    }
}

/// The entropic prior on the arm, from the same wrong prior: held-out RMS
/// within 1.1 σ, every body consistent, and no link mass further from the
/// truth than the prior's by more than 1 % of the truth. (Measured: the
/// unidentifiable masses stay at the prior to within 0.012 kg, e.g. link1
/// 6.467 kg against the prior's 6.462; the Euclidean prior without the
/// masses' extra weight moves link3 and link5 up to 8 % of the truth beyond
/// the prior's error, see above. The sidecar's extra mass weight is turned
/// off here to test the divergence alone: 1e-2 is not ≫ an entropic weight
/// of 1e-2, and with it link2 ended 0.018 kg further than the prior's, the
/// heavier links held harder by Σ (m − m̂)² than by the divergence.)
#[test]
fn the_arm_with_the_entropic_prior_keeps_masses_near_the_prior() {
    let r = panda();
    let (train, val) = (friction_data(&r, 1), friction_data(&r, 2));
    let prior = perturbed_prior(&r);
    let w = 1e-2;
    let res = Identification::for_robot(&r, Level::Consistent, w)
        .unwrap()
        .prior(w, prior.clone())
        .unwrap()
        .regularizer(Regularizer::Entropic)
        .prior_mass_weight(0.0)
        .unwrap()
        .identify(&train, Some(&val))
        .unwrap();
    for (j, v) in res.validation_rms.clone().unwrap().iter().enumerate() {
        assert!(*v <= 1.1 * 0.3, "joint {j}: held-out RMS {v} > 1.1 σ");
    }
    assert!(res.bodies.iter().all(|b| b.consistent));
    for (b, body) in res.bodies.iter().enumerate() {
        let truth = r.model.params()[10 * b];
        let (err, prior_err) = ((body.mass - truth).abs(), (prior[10 * b] - truth).abs());
        assert!(
            err <= prior_err + 0.01 * truth,
            "{} mass {} (prior {}, truth {truth})",
            body.name,
            body.mass,
            prior[10 * b]
        );
    }
}
