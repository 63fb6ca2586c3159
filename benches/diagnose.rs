//! Diagnosis benchmarks: 15 s of 1 kHz data, the nominal model identified
//! (ellipsoid level) on 20 s of other data — the built-in leg with an offset
//! and cogging withheld (the demo's case), and the Panda arm of
//! `robots/panda` with an encoder zero offset withheld; and the real KUKA
//! LWR4+ of `robots/kuka-lwr4` (run 3 against the model identified on runs
//! 1–2, their repeatability as the floor: the null row of
//! `examples/confusion_real.rs`; and the same with runs 1–2 given as the
//! nominal's own data, `--nominal-data`).
//!
//! Run: `cargo bench --bench diagnose`

use criterion::{Criterion, criterion_group, criterion_main};
use momentlmi::data::Dataset;
use momentlmi::diagnose::{DiagnoseOptions, diagnose};
use momentlmi::dynamics::Friction;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::dynamics::{Model, RobotDescription, cheetah3};
use momentlmi::effects::simulate;
use momentlmi::identify::{IdentifyOptions, Level, identify};
use momentlmi::sim::{Effects, SimConfig};
use std::hint::black_box;

#[allow(dead_code)]
#[path = "../examples/confusion_real.rs"]
mod confusion_real;
use std::time::Duration;

/// (nominal model, its friction, the diagnosed data).
fn case(robot: &RobotDescription, base: &str, withheld: &str) -> (Model, Friction, Dataset) {
    let sim = |effects: &str, seconds, seed| {
        let fx = Effects::parse(effects, &[]).unwrap();
        simulate(
            robot,
            &SimConfig::for_robot(robot, seconds, fx, seed),
            |_, _| {},
        )
        .unwrap()
    };
    let opts = IdentifyOptions::for_robot(robot, Level::Ellipsoid, 1e-6).unwrap();
    let (m, f) = identify(&robot.model, &sim(base, 20.0, 101), None, &opts)
        .unwrap()
        .applied_to(&robot.model)
        .unwrap();
    (m, f, sim(&format!("{base},{withheld}"), 15.0, 7))
}

fn bench(c: &mut Criterion) {
    let leg = cheetah3::description();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let arm = load_robot(
        dir.join("panda.urdf").to_str().unwrap(),
        Some(&dir.join("panda.toml")),
    )
    .unwrap();
    let cases = [
        (
            "leg_offset_cogging",
            case(&leg, "rotor_inertia,coulomb,viscous", "offset,cogging"),
        ),
        (
            "arm_joint_offset",
            case(&arm, "coulomb,viscous", "joint_offset"),
        ),
    ];
    let mut g = c.benchmark_group("diagnose_15s_1khz");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(20));
    for (name, (m, f, d)) in &cases {
        g.bench_function(*name, |b| {
            b.iter(|| {
                black_box(
                    diagnose(m, f, d, &DiagnoseOptions::default())
                        .unwrap()
                        .accepted,
                )
            })
        });
    }
    let (_, m, f, floor, run3, runs12) = confusion_real::setup().unwrap();
    let opts = DiagnoseOptions::default().with_noise_floor(floor);
    g.bench_function("kuka_run3_real", |b| {
        b.iter(|| black_box(diagnose(&m, &f, &run3, &opts).unwrap().accepted))
    });
    // the same with the nominal's own data (runs 1–2): its bodies refit
    let opts = opts.with_nominal_data(runs12);
    g.bench_function("kuka_run3_real_nominal_data", |b| {
        b.iter(|| black_box(diagnose(&m, &f, &run3, &opts).unwrap().accepted))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
