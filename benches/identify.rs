//! Identification benchmarks: 10,000 samples of the 6-body leg with
//! ellipsoid constraints end to end (regressor + reduction + SDP), with the
//! entropic prior (`end_to_end/entropic/...`, issue 19's ≤ 50 ms target),
//! and the scaling of the streaming reduction with the number of samples.

use criterion::{Criterion, criterion_group, criterion_main};
use momentlmi::conic::Decomposition;
use momentlmi::dynamics::cheetah3;
use momentlmi::effects::simulate;
use momentlmi::identify::{
    IdentifyOptions, Level, Regularizer, StreamReducer, default_settings, reduce_samples,
    solve_identification,
};
use momentlmi::sim::{Effects, SimConfig};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let leg = cheetah3::description();
    let model = leg.model.clone();
    let fx = Effects::parse("rotor_inertia,coulomb,viscous", &[]).unwrap();
    let cfg = SimConfig::for_robot(&leg, 10.0, fx, 1);
    let d = simulate(&leg, &cfg, |_, _| {}).unwrap();
    let opts = |level| IdentifyOptions::for_robot(&leg, level, 1e-6).unwrap();
    let mut g = c.benchmark_group("identify_10000_samples_6_bodies");
    g.sample_size(30);
    for level in [Level::None, Level::Consistent, Level::Ellipsoid] {
        let o = opts(level);
        g.bench_function(format!("end_to_end/{}", level.as_str()), |b| {
            b.iter(|| {
                let red = reduce_samples(&model, &d.q, &d.qd, &d.qdd, &d.tau, 1024).unwrap();
                black_box(solve_identification(&model, &red, &o).unwrap().theta[0])
            })
        });
    }
    for level in [Level::Consistent, Level::Ellipsoid] {
        let o = IdentifyOptions::for_robot(&leg, level, 1e-2)
            .unwrap()
            .with_regularizer(Regularizer::Entropic);
        g.bench_function(format!("end_to_end/entropic/{}", level.as_str()), |b| {
            b.iter(|| {
                let red = reduce_samples(&model, &d.q, &d.qd, &d.qdd, &d.tau, 1024).unwrap();
                black_box(solve_identification(&model, &red, &o).unwrap().theta[0])
            })
        });
    }
    g.bench_function("reduction_only/parallel", |b| {
        b.iter(|| {
            black_box(
                reduce_samples(&model, &d.q, &d.qd, &d.qdd, &d.tau, 1024)
                    .unwrap()
                    .samples,
            )
        })
    });
    let red = reduce_samples(&model, &d.q, &d.qd, &d.qdd, &d.tau, 1024).unwrap();
    let o = opts(Level::Ellipsoid);
    g.bench_function("sdp_only/ellipsoid", |b| {
        b.iter(|| black_box(solve_identification(&model, &red, &o).unwrap().theta[0]))
    });
    // the same with Clarabel's chordal decomposition off (the default before
    // issue 18): the 4 × 4 blocks are dense, so the default only adds
    // Clarabel's sparsity analysis, which this pair measures
    let off = o
        .clone()
        .with_settings(default_settings().decomposition(Decomposition::Off))
        .unwrap();
    g.bench_function("sdp_only/ellipsoid/decomposition_off", |b| {
        b.iter(|| black_box(solve_identification(&model, &red, &off).unwrap().theta[0]))
    });
    g.finish();
    let mut g = c.benchmark_group("stream_reduction");
    g.sample_size(10);
    for &n in &[10_000usize, 100_000] {
        g.bench_function(format!("{n}_samples"), |b| {
            b.iter(|| {
                let mut r = StreamReducer::new(&model, 1024);
                for k in 0..n {
                    let s = k % d.len();
                    r.push(&d.q[s], &d.qd[s], &d.qdd[s], &d.tau[s]).unwrap();
                }
                black_box(r.finish().unwrap().samples)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
