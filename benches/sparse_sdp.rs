//! A sparse SDP family that grows: the max-cut relaxation of random sparse
//! graphs (a weighted cycle plus n/2 random chords: mean degree 3), in
//! SDPA's primal form `min Σ yᵢ s.t. diag(y) − L/4 ⪰ 0`, one PSD cone of
//! side n. With the default (verified) chordal decomposition Clarabel works
//! on the cliques of the graph's chordal extension; without it on the whole
//! n(n+1)/2-row cone (Θ(n⁴) memory: n = 400 would need ~360 GB, so only the
//! smallest size is also timed undecomposed). Results: docs/benchmarks.md.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use momentlmi::conic::{Decomposition, DecompositionOutcome, Problem, Settings};
use std::hint::black_box;

#[path = "../tests/support/sparse_sdp.rs"]
mod support;

fn solve(p: &Problem, d: Decomposition) -> f64 {
    let s = p.solve(&Settings::default().decomposition(d)).unwrap();
    assert!(s.status.is_solved(), "{}", s.status);
    if d == Decomposition::Verified {
        assert_eq!(s.decomposition, DecompositionOutcome::Used);
    }
    s.primal_objective
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("max_cut_sparse");
    g.sample_size(10);
    for n in [50, 100, 200, 400] {
        let (p, _) = support::max_cut(n, n as u64);
        g.bench_with_input(BenchmarkId::new("verified", n), &p, |b, p| {
            b.iter(|| black_box(solve(p, Decomposition::Verified)))
        });
    }
    let (p, _) = support::max_cut(50, 50);
    g.bench_with_input(BenchmarkId::new("off", 50), &p, |b, p| {
        b.iter(|| black_box(solve(p, Decomposition::Off)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
