//! Random states of a model, for structural questions (which parameters a
//! regressor can ever see): positions uniform within the joints' limits
//! (±1 rad or m where a joint has none), velocities and accelerations
//! uniform in ±2.

use super::model::Model;
use rand::{RngExt, SeedableRng};

/// `k` random states of `model` with `seed`: flat q, q̇, q̈, n per state.
pub fn random_states(model: &Model, k: usize, seed: u64) -> [Vec<f64>; 3] {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let n = model.dof();
    let mut s = [
        Vec::with_capacity(k * n),
        Vec::with_capacity(k * n),
        Vec::with_capacity(k * n),
    ];
    for _ in 0..k {
        for j in &model.joints {
            let (lo, hi) = j.limits;
            let (lo, hi) = if lo.is_finite() && hi.is_finite() {
                (lo, hi)
            } else {
                (-1.0, 1.0)
            };
            s[0].push(rng.random_range(lo..=hi));
            s[1].push(rng.random_range(-2.0..2.0));
            s[2].push(rng.random_range(-2.0..2.0));
        }
    }
    s
}
