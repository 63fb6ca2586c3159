//! Conic layer benchmarks: compile + solve of a small SDP, and of a tall
//! least-squares problem with PSD blocks in both least-squares forms.

use criterion::{Criterion, criterion_group, criterion_main};
use momentlmi::conic::{AffExpr, LeastSquaresForm, MatExpr, Problem, Settings};
use nalgebra::DMatrix;
use std::hint::black_box;

struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Lovász θ of the Petersen graph: one 10×10 PSD cone, 16 equalities.
fn small_sdp() -> Problem {
    let n = 10;
    let mut edges: Vec<(usize, usize)> = (0..5).map(|i| (i, (i + 1) % 5)).collect();
    edges.extend((0..5).map(|i| (5 + i, 5 + (i + 2) % 5)));
    edges.extend((0..5).map(|i| (i, i + 5)));
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let xe = x.expr();
    p.add_eq(xe.trace(), 1.0).unwrap();
    for (i, j) in edges {
        p.add_eq(xe.get(i, j).unwrap().clone(), 0.0).unwrap();
    }
    p.add_psd(&xe).unwrap();
    p.maximize(xe.dot(&DMatrix::from_element(n, n, 1.0)));
    p
}

/// 10,000 samples × 3 rows of a random dense regressor over 66 parameters;
/// parameters 0..60 form six 4×4 symmetric blocks constrained PSD (as in
/// identification: one pseudo-inertia per body), 60..66 are ≥ 0.
fn tall_least_squares(rows: &[Vec<f64>], y: &[f64]) -> Problem {
    let mut p = Problem::new();
    let th = p.vector("theta", 66);
    for b in 0..6 {
        let v = &th[10 * b..10 * b + 10];
        let m = MatExpr::from_fn(4, 4, |i, j| {
            let (i, j) = if i <= j { (i, j) } else { (j, i) };
            AffExpr::from(v[j * (j + 1) / 2 + i])
        });
        p.add_psd(&m).unwrap();
    }
    p.add_nonneg(th[60..].iter().map(|&v| AffExpr::from(v)))
        .unwrap();
    let w = 1.0 / rows.len() as f64;
    p.add_squares(
        w,
        rows.iter()
            .zip(y)
            .map(|(r, &yy)| AffExpr::linear(&th, r, -yy).unwrap()),
    );
    p
}

fn tall_data() -> (Vec<Vec<f64>>, Vec<f64>) {
    let mut rng = Rng(3);
    let truth: Vec<f64> = (0..66)
        .map(|k| {
            if k < 60 && [0, 2, 5, 9].contains(&(k % 10)) {
                1.0
            } else {
                0.1 * rng.f()
            }
        })
        .collect();
    let rows: Vec<Vec<f64>> = (0..30_000)
        .map(|_| (0..66).map(|_| rng.f()).collect())
        .collect();
    let y = rows
        .iter()
        .map(|r| r.iter().zip(&truth).map(|(a, b)| a * b).sum::<f64>() + 0.01 * rng.f())
        .collect();
    (rows, y)
}

fn bench(c: &mut Criterion) {
    let s = Settings::default();
    c.bench_function("small_sdp/lovasz_petersen/compile+solve", |b| {
        let p = small_sdp();
        b.iter(|| black_box(p.solve(&s).unwrap().primal_objective))
    });
    let (rows, y) = tall_data();
    let mut g = c.benchmark_group("tall_lsq_10000x3_66p_6psd4");
    g.sample_size(20);
    g.bench_function("build", |b| {
        b.iter(|| black_box(tall_least_squares(&rows, &y).num_vars()))
    });
    let p = tall_least_squares(&rows, &y);
    for (name, form) in [
        ("quadratic", LeastSquaresForm::Quadratic),
        ("soc", LeastSquaresForm::SecondOrderCone),
    ] {
        let st = s.clone().least_squares(form);
        g.bench_function(format!("compile+solve/{name}"), |b| {
            b.iter(|| black_box(p.solve(&st).unwrap().primal_objective))
        });
        g.bench_function(format!("compile/{name}"), |b| {
            b.iter(|| black_box(p.compile(&st).unwrap().num_rows()))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
