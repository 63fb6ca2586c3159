//! The withheld-effect confusion table of docs/diagnosis.md.
//!
//! Run: `cargo run --release --example confusion`

use momentlmi::diagnose::{DiagnoseOptions, diagnose};
use momentlmi::dynamics::cheetah3;
use momentlmi::identify::{IdentifyOptions, Level, identify};
use momentlmi::sim::{Effects, SimConfig, simulate};

fn main() {
    let leg = cheetah3::description();
    let model = leg.model.clone();
    let sim = |effects: &str, params: &[String], seconds: f64, seed: u64| {
        let cfg = SimConfig::for_robot(
            &leg,
            seconds,
            Effects::parse(effects, params).unwrap(),
            seed,
        );
        simulate(&leg, &cfg, |_, _| {}).unwrap()
    };
    let nominal = |base: &str| {
        let d = sim(base, &[], 20.0, 101);
        let opts = IdentifyOptions::for_robot(&leg, Level::Ellipsoid, 1e-6).unwrap();
        let r = identify(&model, &d, None, &opts).unwrap();
        r.applied_to(&model).unwrap()
    };
    let base = "rotor_inertia,coulomb,viscous";
    let cases: Vec<(&str, &str, Vec<String>)> = vec![
        (base, "", vec![]),
        ("rotor_inertia,viscous", "coulomb", vec![]),
        ("rotor_inertia,coulomb", "viscous", vec![]),
        (base, "stribeck", vec![]),
        (base, "asymmetric_friction", vec![]),
        (base, "offset", vec![]),
        ("coulomb,viscous", "rotor_inertia", vec![]),
        (base, "payload", vec![]),
        (base, "time_delay", vec![]),
        (base, "cogging", vec![]),
        (base, "torque_gain", vec![]),
        (base, "elasticity", vec!["stiffness=300".into()]),
        (base, "elasticity", vec![]),
        (base, "backlash", vec![]),
        (base, "offset,cogging", vec![]),
        (base, "payload,stribeck", vec![]),
        (base, "torque_gain,cogging", vec![]),
        (base, "stribeck,time_delay", vec![]),
    ];
    println!(
        "| withheld effect(s) | accepted (tied with) | held-out RMS before → after (N·m) | noise floor | unexplained |"
    );
    println!("|---|---|---|---|---|");
    for (b, extra, params) in cases {
        let (m, f) = nominal(b);
        let effects = if extra.is_empty() {
            b.to_string()
        } else {
            format!("{b},{extra}")
        };
        let d = sim(&effects, &params, 15.0, 7);
        let dg = diagnose(&m, &f, &d, &DiagnoseOptions::default()).unwrap();
        let acc: Vec<String> = dg
            .ranked_effects
            .iter()
            .filter(|e| e.accepted)
            .map(|e| {
                if e.tied_with.is_empty() {
                    e.effect.clone()
                } else {
                    format!("{} ({})", e.effect, e.tied_with.join(", "))
                }
            })
            .collect();
        let f3 = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{x:.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "| {} | {} | ({}) → ({}) | ({}) | {} |",
            if extra.is_empty() {
                "none (null case)".to_string()
            } else {
                format!(
                    "{extra}{}",
                    if params.is_empty() {
                        String::new()
                    } else {
                        format!(" [{}]", params.join(", "))
                    }
                )
            },
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
}
