//! Deterministic xorshift for test data (shared by the integration tests
//! with `#[path = "support/rng.rs"] mod rng;`).
#![allow(dead_code)]

use nalgebra::DMatrix;

/// A xorshift64 generator; the seed must not be 0.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [−1, 1).
    pub fn f(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    /// Three entries uniform in [−s, s).
    pub fn v(&mut self, s: f64) -> Vec<f64> {
        (0..3).map(|_| s * self.f()).collect()
    }

    /// A random symmetric n × n matrix, entries in [−1, 1).
    pub fn sym(&mut self, n: usize) -> DMatrix<f64> {
        let m = DMatrix::from_fn(n, n, |_, _| self.f());
        (&m + m.transpose()) * 0.5
    }

    /// A random symmetric positive definite n × n matrix (λ ≥ 0.5).
    pub fn spd(&mut self, n: usize) -> DMatrix<f64> {
        let m = DMatrix::from_fn(n, n, |_, _| self.f());
        &m * m.transpose() + DMatrix::identity(n, n) * 0.5
    }
}
