//! Sparse SDP families built in code, shared by `tests/conic_decomposition.rs`
//! and `benches/sparse_sdp.rs` (each includes this file with `#[path]`).

#![allow(dead_code)] // each includer uses part of it

use momentlmi::conic::{AffExpr, ConstraintId, MatExpr, Problem};
use nalgebra::DMatrix;

/// A 64-bit linear congruential generator (Knuth's MMIX constants), so the
/// data do not depend on a random-number crate's version.
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// An n × n matrix uniform in [−scale, scale).
    pub fn matrix(&mut self, n: usize, scale: f64) -> DMatrix<f64> {
        DMatrix::from_fn(n, n, |_, _| scale * (2.0 * self.uniform() - 1.0))
    }
}

/// The Laplacian of a weighted cycle plus n/2 random chords (mean degree
/// 3), weights uniform in [1, 2).
pub fn laplacian(n: usize, seed: u64) -> DMatrix<f64> {
    let mut rng = Lcg(seed);
    let mut lap = DMatrix::zeros(n, n);
    let mut edge = |i: usize, j: usize, w: f64| {
        lap[(i, j)] -= w;
        lap[(j, i)] -= w;
        lap[(i, i)] += w;
        lap[(j, j)] += w;
    };
    for i in 0..n {
        edge(i, (i + 1) % n, 1.0 + rng.uniform());
    }
    for _ in 0..n / 2 {
        let i = (rng.uniform() * n as f64) as usize;
        let j = (rng.uniform() * n as f64) as usize;
        if i != j {
            edge(i, j, 1.0 + rng.uniform());
        }
    }
    lap
}

/// The max-cut relaxation of [`laplacian`]'s graph in SDPA's primal form,
/// `min Σ yᵢ s.t. diag(y) − L/4 ⪰ 0` (one PSD cone of side n), and that
/// constraint, whose dual is the max-cut matrix X.
pub fn max_cut(n: usize, seed: u64) -> (Problem, ConstraintId) {
    let lap = laplacian(n, seed);
    let mut p = Problem::new();
    let y = p.vector("y", n);
    let m = MatExpr::diag(y.iter().map(|&v| AffExpr::from(v)).collect())
        .try_sub(&MatExpr::constant(&(lap / 4.0)))
        .unwrap();
    let c = p.add_psd(m).unwrap();
    p.minimize(y.iter().fold(AffExpr::zero(), |s, &v| s + AffExpr::from(v)));
    (p, c)
}

/// The SDPLIB "control" family (control1 is n = 5): maximise λ subject to
///
/// ```text
/// [ AᵀP + PA − Cᵀ diag(d) C   PB      ]
/// [ BᵀP                       diag(d) ] − λ I ⪰ 0,     P ⪰ I,
/// ```
///
/// over symmetric P (n × n), d ∈ ℝⁿ and λ, with A, B, C uniform in ±50. The
/// 2n × 2n block's pattern is a dense n × n core with n leaves, each tied to
/// the whole core: n overlapping cliques, which Clarabel's merge joins into
/// fewer.
pub fn control(n: usize, seed: u64) -> Problem {
    let mut rng = Lcg(seed);
    let (a, b, c) = (
        rng.matrix(n, 50.0),
        rng.matrix(n, 50.0),
        rng.matrix(n, 50.0),
    );
    let mut p = Problem::new();
    let pm = p.symmetric("P", n).expr();
    let d = p.vector("d", n);
    let lam = p.scalar("lambda");
    let mut top = pm
        .left_mul(&a.transpose())
        .unwrap()
        .try_add(&pm.right_mul(&a).unwrap())
        .unwrap();
    for (i, &di) in d.iter().enumerate() {
        let ci = c.row(i).transpose();
        let cc = &ci * ci.transpose();
        let term = MatExpr::from_fn(n, n, |r, s| AffExpr::term(di, -cc[(r, s)]));
        top = top.try_add(&term).unwrap();
    }
    let pb = pm.right_mul(&b).unwrap();
    let dd = MatExpr::diag(d.iter().map(|&v| AffExpr::from(v)).collect());
    let pbt = pb.transpose();
    let rows = [vec![Some(&top), Some(&pb)], vec![Some(&pbt), Some(&dd)]];
    let m = MatExpr::block(&rows)
        .unwrap()
        .plus_identity(AffExpr::term(lam, -1.0))
        .unwrap();
    p.add_psd(m).unwrap();
    p.add_psd(pm.plus_identity(AffExpr::constant(-1.0)).unwrap())
        .unwrap();
    p.maximize(lam);
    p
}
