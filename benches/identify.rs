//! Identification benchmarks: 10,000 samples of the 6-body leg with
//! ellipsoid constraints end to end (regressor + reduction + SDP), with the
//! entropic prior (`end_to_end/entropic/...`, issue 19's ≤ 50 ms target),
//! the scaling of the streaming reduction with the number of samples, and
//! identification from a CSV log of 10³ … 10⁶ samples streamed from disk
//! (`from_csv/…`: reading, reduction, solve and checks, as `identify`
//! does them; issue 36).

use criterion::{Criterion, criterion_group, criterion_main};
use momentlmi::conic::Decomposition;
use momentlmi::data::{Dataset, ReadOptions};
use momentlmi::dynamics::cheetah3;
use momentlmi::effects::simulate;
use momentlmi::identify::{
    Identification, IdentifyOptions, Level, Regularizer, StreamReducer, default_settings,
    reduce_logs, reduce_samples, solve_identification,
};
use momentlmi::sim::{Effects, SimConfig};
use std::hint::black_box;
use std::io::Write;

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
    from_csv(c, &d);
}

/// `d`'s rows repeated (time shifted) to `n` samples, as `simulate` writes them.
fn csv_of(d: &Dataset, n: usize, path: &std::path::Path) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let header = d.to_csv();
    writeln!(f, "{}", header.lines().next().unwrap()).unwrap();
    let span = d.t[d.len() - 1] - d.t[0] + 1e-3;
    for k in 0..n {
        let s = k % d.len();
        write!(f, "{:e}", d.t[s] + span * (k / d.len()) as f64).unwrap();
        for x in [&d.q[s], &d.qd[s], &d.qdd[s], &d.tau[s]] {
            x.iter().for_each(|v| write!(f, ",{v:e}").unwrap());
        }
        writeln!(f).unwrap();
    }
}

/// Identification from a CSV file streamed from disk (ellipsoid level;
/// Euclidean prior w = 1e-6, entropic w = 1e-2), 10³ … 10⁶ samples.
fn from_csv(c: &mut Criterion, d: &Dataset) {
    let leg = cheetah3::description();
    let dir = tempfile::tempdir().unwrap();
    let euclid = Identification::for_robot(&leg, Level::Ellipsoid, 1e-6).unwrap();
    let entropic = Identification::for_robot(&leg, Level::Ellipsoid, 1e-2)
        .unwrap()
        .regularizer(Regularizer::Entropic);
    let mut g = c.benchmark_group("from_csv");
    g.sample_size(10);
    for n in [1_000usize, 10_000, 100_000, 1_000_000] {
        let path = dir.path().join(format!("{n}.csv"));
        csv_of(d, n, &path);
        for (name, id) in [("ellipsoid", &euclid), ("entropic", &entropic)] {
            g.bench_function(format!("{name}/{n}_samples"), |b| {
                b.iter(|| {
                    let opts = ReadOptions::default();
                    let t = reduce_logs(&leg.model, &[&path], &opts).unwrap().unwrap();
                    black_box(id.fit_streamed(&t.reduced).unwrap().theta[0])
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
