//! The floating-base diagnosis finds each withheld effect in a suspended
//! Solo12's log (the diagnoser is given the URDF's model and not told), and
//! invents none in a log without one.

use momentlmi::diagnose::floating::{FloatingEffect, diagnose_floating};
use momentlmi::dynamics::Model;
use momentlmi::dynamics::urdf::free_flyer_from_urdf_file;
use momentlmi::sim::floating::{FloatingEffects, SuspendedConfig, simulate_suspended};
use std::path::Path;

fn solo() -> Model {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    free_flyer_from_urdf_file(&root.join("robots/solo12/solo12.urdf"), None).unwrap()
}

fn diagnosed(effects: FloatingEffects) -> Vec<FloatingEffect> {
    diagnosis(effects).accepted
}

fn diagnosis(effects: FloatingEffects) -> momentlmi::diagnose::floating::FloatingDiagnosis {
    let ff = solo();
    let cfg = SuspendedConfig {
        seconds: 60.0,
        seed: 7,
        effects,
        ..SuspendedConfig::default()
    };
    let log = simulate_suspended(&ff, &cfg).unwrap();
    let mut theta = ff.params();
    theta.resize(ff.regressor_columns(), 0.0);
    let d = diagnose_floating(&ff, &theta, &[log]).unwrap();
    for (i, r) in d.rounds.iter().enumerate() {
        for c in &r.candidates {
            println!(
                "round {}: {:?}: gap closed {:.3}",
                i + 1,
                c.effect,
                c.gap_closed
            );
        }
    }
    d
}

/// The payload comes out as the mass and point it is.
#[test]
fn the_payload_is_measured() {
    let d = diagnosis(FloatingEffects {
        payload: Some((0.3, [0.05, 0.0, 0.03])),
        ..Default::default()
    });
    let c = d.final_fit().unwrap();
    assert_eq!(c.effect, FloatingEffect::Payload);
    let v: Vec<f64> = c.values.iter().map(|(_, x)| *x).collect();
    let (m, com) = (v[0], [v[1] / v[0], v[2] / v[0], v[3] / v[0]]);
    assert!((m - 0.3).abs() < 0.01, "mass {m}");
    for (got, want) in com.iter().zip([0.05, 0.0, 0.03]) {
        assert!((got - want).abs() < 0.003, "payload at {com:?}");
    }
}

#[test]
fn each_withheld_effect_is_found() {
    let cases = [
        (
            FloatingEffects {
                joint_friction: Some([0.01, 0.05]),
                ..Default::default()
            },
            FloatingEffect::JointFriction,
        ),
        (
            FloatingEffects {
                wrench_offset: Some([1.0, -0.5, 2.0, 0.05, 0.02, -0.03]),
                ..Default::default()
            },
            FloatingEffect::WrenchOffset,
        ),
        (
            FloatingEffects {
                payload: Some((0.3, [0.05, 0.0, 0.03])),
                ..Default::default()
            },
            FloatingEffect::Payload,
        ),
    ];
    for (effects, want) in cases {
        assert_eq!(diagnosed(effects), [want], "{effects:?}");
    }
}

#[test]
fn no_effect_is_invented() {
    assert_eq!(diagnosed(FloatingEffects::default()), []);
}

fn standing(effects: FloatingEffects) -> momentlmi::diagnose::floating::FloatingDiagnosis {
    use momentlmi::sim::standing::{StandingConfig, simulate_standing};
    let ff = solo();
    let leg = |s: f64| [0.0, 0.8 * s, -1.6 * s];
    let posture = [leg(1.0), leg(1.0), leg(-1.0), leg(-1.0)].concat();
    let feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
        .map(String::from)
        .to_vec();
    let cfg = StandingConfig {
        seconds: 60.0,
        effects,
        ..StandingConfig::new(feet, posture)
    };
    let log = simulate_standing(&ff, &cfg).unwrap();
    let mut theta = ff.params();
    theta.resize(ff.regressor_columns(), 0.0);
    diagnose_floating(&ff, &theta, &[log]).unwrap()
}

/// Standing, a payload is told from an offset of the four plates (whose
/// 24 parameters absorb most of its weight too: the payload's 10 are
/// preferred at a like closure).
#[test]
fn a_payload_is_found_while_standing() {
    let d = standing(FloatingEffects {
        payload: Some((0.3, [0.05, 0.0, 0.03])),
        ..Default::default()
    });
    assert_eq!(d.accepted, [FloatingEffect::Payload]);
}

/// On force plates too: an offset of every plate, found and measured.
#[test]
fn a_force_plate_offset_is_found_while_standing() {
    let offset = [1.0, -0.5, 2.0, 0.05, 0.02, -0.03];
    let d = standing(FloatingEffects {
        wrench_offset: Some(offset),
        ..Default::default()
    });
    assert_eq!(d.accepted, [FloatingEffect::WrenchOffset]);
    let c = d.rounds[0]
        .candidates
        .iter()
        .find(|c| c.effect == FloatingEffect::WrenchOffset)
        .unwrap();
    // each plate's force offset within 0.1 N (σ 0.2 N per sample, 42 s fitted)
    for (name, value) in c.values.iter().filter(|(n, _)| n.contains(".force_")) {
        let axis = ["force_x", "force_y", "force_z"]
            .iter()
            .position(|a| name.ends_with(a))
            .unwrap();
        assert!((value - offset[axis]).abs() < 0.1, "{name} = {value}");
    }
}

/// Two effects at once, standing: joint friction and an offset of every
/// plate, both found (in two rounds of the forward selection).
#[test]
fn two_effects_are_both_found() {
    let effects = FloatingEffects {
        joint_friction: Some([0.01, 0.05]),
        wrench_offset: Some([1.0, -0.5, 2.0, 0.05, 0.02, -0.03]),
        ..Default::default()
    };
    let d = standing(effects);
    let mut found = d.accepted.clone();
    found.sort_by_key(|e| e.name());
    assert_eq!(
        found,
        [FloatingEffect::JointFriction, FloatingEffect::WrenchOffset],
        "{:?}",
        d.accepted
    );
    assert!(d.final_fit().unwrap().gap_closed > 0.95);
}
