//! The withheld-effect confusion tables of docs/diagnosis.md: the built-in
//! leg and the Panda arm of `robots/panda`, with the same rules (the nominal
//! model identified at the ellipsoid level on 20 s of other data, seed 101;
//! 15 s of diagnosed data, seed 7; default noise and effect parameters).
//!
//! Run: `cargo run --release --example confusion` (`-- NAME`: only the
//! rows whose withheld effects contain NAME)

use momentlmi::diagnose::{DiagnoseOptions, Diagnosis, diagnose};
use momentlmi::dynamics::robots::load_robot;
use momentlmi::dynamics::{FrictionTerm, Model, RobotDescription, cheetah3};
use momentlmi::effects::simulate;
use momentlmi::identify::{IdentifyOptions, Level, identify};
use momentlmi::sim::{Effects, SimConfig};
use std::time::Instant;

/// (base effects, withheld effects, effect-parameter overrides).
type Case = (&'static str, &'static str, Vec<String>);

/// The out-of-library case: a torque periodic in the joint angle that no
/// candidate has, 0.8 sin(3 q + 1) N·m on every joint.
const OUTSIDE: &str = "outside the library: 0.8 sin(3q + 1)";

/// A torque periodic in time, 0.8 sin(2π·0.7 t + 1) N·m on every joint (a
/// neighbouring machine's vibration): outside the library on both robots
/// (the one above is `ripple`'s on a joint without a rotor).
const OUTSIDE_TIME: &str = "outside the library: 0.8 sin(2π·0.7 t + 1)";

/// The torque of an out-of-library case at time `t` and joint angle `q`.
fn outside_torque(case: &str, t: f64, q: f64) -> f64 {
    if case == OUTSIDE {
        0.8 * (3.0 * q + 1.0).sin()
    } else {
        0.8 * (2.0 * std::f64::consts::PI * 0.7 * t + 1.0).sin()
    }
}

fn main() {
    let leg = cheetah3::description();
    let base = "rotor_inertia,coulomb,viscous";
    let leg_cases: Vec<Case> = vec![
        (base, "", vec![]),
        ("rotor_inertia,viscous", "coulomb", vec![]),
        ("rotor_inertia,coulomb", "viscous", vec![]),
        (base, "stribeck", vec![]),
        (base, "asymmetric_friction", vec![]),
        (base, "load_friction", vec![]),
        (base, "friction_drift", vec![]),
        (base, "offset", vec![]),
        ("coulomb,viscous", "rotor_inertia", vec![]),
        (base, "payload", vec![]),
        (base, "time_delay", vec![]),
        (base, "cogging", vec![]),
        (base, "torque_gain", vec![]),
        (base, "elasticity", vec!["stiffness=300".into()]),
        (base, "elasticity", vec![]),
        (base, "backlash", vec![]),
        (base, "joint_offset", vec![]),
        (base, "offset,cogging", vec![]),
        (base, "payload,stribeck", vec![]),
        (base, "torque_gain,cogging", vec![]),
        (base, "stribeck,time_delay", vec![]),
        (base, OUTSIDE, vec![]),
        (base, OUTSIDE_TIME, vec![]),
    ];
    println!("### cheetah3-leg\n");
    table(&leg, &leg_cases);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let arm = load_robot(
        dir.join("panda.urdf").to_str().expect("a UTF-8 path"),
        Some(&dir.join("panda.toml")),
    )
    .expect("robots/panda loads");
    let base = "coulomb,viscous";
    let arm_cases: Vec<Case> = vec![
        (base, "", vec![]),
        ("viscous", "coulomb", vec![]),
        ("coulomb", "viscous", vec![]),
        (base, "stribeck", vec![]),
        (base, "asymmetric_friction", vec![]),
        (base, "load_friction", vec![]),
        (base, "friction_drift", vec![]),
        (base, "friction_drift", vec!["friction_drift=-1".into()]),
        (base, "offset", vec![]),
        (base, "payload", vec![]),
        (base, "time_delay", vec![]),
        (base, "torque_gain", vec![]),
        (base, "joint_offset", vec![]),
        (base, "offset,joint_offset", vec![]),
        (base, "payload,stribeck", vec![]),
        (base, "ripple", vec![]),
        (base, OUTSIDE, vec![]),
        (base, OUTSIDE_TIME, vec![]),
    ];
    println!("\n### Panda (robots/panda)\n");
    table(&arm, &arm_cases);
}

fn table(robot: &RobotDescription, cases: &[Case]) {
    let model = robot.model.clone();
    let sim = |effects: &str, params: &[String], seconds: f64, seed: u64| {
        let fx = Effects::parse(effects, params).expect("a valid case");
        let cfg = SimConfig::for_robot(robot, seconds, fx, seed);
        simulate(robot, &cfg, |_, _| {}).expect("the case simulates")
    };
    println!(
        "| withheld effect(s) | accepted (tied with) | held-out RMS before → after (N·m) | noise floor | unexplained | diagnosis (s) |"
    );
    println!("|---|---|---|---|---|---|");
    // `-- NAME`: only the rows whose withheld effects contain NAME
    let only = std::env::args().nth(1).unwrap_or_default();
    for (b, extra, params) in cases.iter().filter(|c| c.1.contains(only.as_str())) {
        let d = sim(b, &[], 20.0, 101);
        let opts = IdentifyOptions::for_robot(robot, Level::Ellipsoid, 1e-6).expect("options");
        let model = nominal_law(&model, extra);
        let (m, f) = identify(&model, &d, None, &opts)
            .and_then(|r| r.applied_to(&model))
            .expect("the nominal model identifies");
        let outside = extra.starts_with("outside");
        let effects = match *extra {
            "" => b.to_string(),
            _ if outside => b.to_string(),
            e => format!("{b},{e}"),
        };
        let mut data = sim(&effects, params, 15.0, 7);
        if outside {
            for ((tau, q), t) in data.tau.iter_mut().zip(&data.q).zip(&data.t) {
                for (ti, qi) in tau.iter_mut().zip(q) {
                    *ti += outside_torque(extra, *t, *qi);
                }
            }
        }
        let start = Instant::now();
        let dg = diagnose(&m, &f, &data, &DiagnoseOptions::default()).expect("diagnoses");
        let secs = start.elapsed().as_secs_f64();
        row(extra, params, &dg, secs);
    }
}

/// The model whose friction law lacks a withheld friction term: a model
/// that lacks Coulomb friction has no Coulomb term (a term it has is refit
/// by the diagnosis, whatever its nominal coefficient).
pub fn nominal_law(model: &Model, withheld: &str) -> Model {
    let terms: Vec<FrictionTerm> = (model.friction_terms().iter().copied())
        .filter(|t| !withheld.split(',').any(|w| w == t.name()))
        .collect();
    model.clone().with_friction_terms(&terms)
}

fn row(extra: &str, params: &[String], dg: &Diagnosis, secs: f64) {
    let acc: Vec<String> = dg
        .ranked_effects
        .iter()
        .filter(|e| e.accepted)
        .map(|e| {
            if e.tied_with.is_empty() {
                e.label()
            } else {
                format!("{} ({})", e.label(), e.tied_with.join(", "))
            }
        })
        .collect();
    let f3 = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.2}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let withheld = match (extra, params.is_empty()) {
        ("", _) => "none (null case)".to_string(),
        (e, true) => e.to_string(),
        (e, false) => format!("{e} [{}]", params.join(", ")),
    };
    println!(
        "| {withheld} | {} | ({}) → ({}) | ({}) | {} | {secs:.1} |",
        if acc.is_empty() {
            "—".into()
        } else {
            acc.join("; ")
        },
        f3(&dg.heldout_rms_nominal),
        f3(&dg.heldout_rms_final),
        f3(&dg.noise_floor),
        if dg.unexplained { "yes" } else { "no" }
    );
}
