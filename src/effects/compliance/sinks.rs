//! Where an integration's outputs go: the whole trace, or only the sums a
//! search needs (its cost, or per joint its best scaled fit), accumulated
//! in the order a trace would be summed.

/// Where an integration's outputs go, in order (flat index `s·n + i`).
pub(super) trait Sink {
    type Out;
    fn push(&mut self, k: usize, v: f64);
    fn finish(self) -> Self::Out;
}

/// Every output: the simulated trace.
pub(super) struct Trace(pub(super) Vec<f64>);

impl Sink for Trace {
    type Out = Vec<f64>;
    #[inline(always)]
    fn push(&mut self, _: usize, v: f64) {
        self.0.push(v);
    }
    fn finish(self) -> Vec<f64> {
        self.0
    }
}

/// Per joint, the cost on the search window of a hypothesis scaled by its
/// best β ≥ 0 (the candidate's coefficient), so that the grid judges
/// timing, not amplitude: from the sums `Σ r h, Σ h², Σ r²` over the
/// samples from `from / n` on, accumulated in sample order (no trace kept).
pub(super) struct Projection<'a> {
    pub(super) r: &'a [f64],
    pub(super) n: usize,
    pub(super) from: usize,
    pub(super) sums: Vec<[f64; 3]>,
}

impl Sink for Projection<'_> {
    type Out = Vec<f64>;
    #[inline(always)]
    fn push(&mut self, k: usize, h: f64) {
        if k >= self.from {
            let a = self.r[k];
            let s = &mut self.sums[k % self.n];
            s[0] += a * h;
            s[1] += h * h;
            s[2] += a * a;
        }
    }
    fn finish(self) -> Vec<f64> {
        self.sums
            .iter()
            .map(|&[rh, hh, rr]| {
                let beta = if hh > 0.0 { (rh / hh).max(0.0) } else { 0.0 };
                rr - 2.0 * beta * rh + beta * beta * hh
            })
            .collect()
    }
}

/// Only `Σ_{k ≥ from} (r_k − h_k)²`, summed in the order a trace would be
/// (so the same number to the last bit), with no trace kept.
pub(super) struct Cost<'a> {
    pub(super) r: &'a [f64],
    pub(super) from: usize,
    pub(super) acc: f64,
}

impl Sink for Cost<'_> {
    type Out = f64;
    #[inline(always)]
    fn push(&mut self, k: usize, v: f64) {
        if k >= self.from {
            self.acc += (self.r[k] - v).powi(2);
        }
    }
    fn finish(self) -> f64 {
        self.acc
    }
}
