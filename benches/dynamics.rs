//! Dynamics benchmarks: regressor of the 6-body Cheetah 3 leg (3 links + 3
//! rotors + friction columns) on 10,000 samples, single-threaded and batched.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use momentlmi::dynamics::{Data, cheetah3, regressor, regressor_batch, rnea};
use std::hint::black_box;

fn states(n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut s = 0x2545F4914F6CDD1Du64;
    let mut f = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let q = (0..3 * n).map(|_| 2.0 * f()).collect();
    let qd = (0..3 * n).map(|_| 10.0 * f()).collect();
    let qdd = (0..3 * n).map(|_| 50.0 * f()).collect();
    (q, qd, qdd)
}

fn bench(c: &mut Criterion) {
    let model = cheetah3::model();
    let n = 10_000;
    let (q, qd, qdd) = states(n);
    let mut g = c.benchmark_group("cheetah3_leg_10000_samples");
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("regressor/one_core", |b| {
        let mut data = Data::new(&model);
        b.iter(|| {
            let mut acc = 0.0;
            for s in 0..n {
                let r = 3 * s..3 * s + 3;
                let y =
                    regressor(&model, &mut data, &q[r.clone()], &qd[r.clone()], &qdd[r]).unwrap();
                acc += y[(0, 0)];
            }
            black_box(acc)
        })
    });
    g.bench_function("regressor_batch/rayon", |b| {
        b.iter(|| black_box(regressor_batch(&model, &q, &qd, &qdd).unwrap().len()))
    });
    g.bench_function("rnea/one_core", |b| {
        let mut data = Data::new(&model);
        b.iter(|| {
            let mut acc = 0.0;
            for s in 0..n {
                let r = 3 * s..3 * s + 3;
                acc += rnea(&model, &mut data, &q[r.clone()], &qd[r.clone()], &qdd[r]).unwrap()[0];
            }
            black_box(acc)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
