//! What the floating-base tests share: the held-out residual computed from
//! the regressor directly (not through `identify::floating_fit`, so that a
//! fault there cannot hide in the tests' floor).

use momentlmi::data::Dataset;
use momentlmi::dynamics::{Data, Model};
use momentlmi::identify::Rows;
use momentlmi::identify::floating::measured;

/// RMS over the samples of `log` of the chosen rows of (measured − Y θ).
pub fn held_out_rms(ff: &Model, log: &Dataset, theta: &[f64], rows: Rows) -> f64 {
    let mut data = Data::new(ff);
    let (mut sum, mut count) = (0.0, 0usize);
    for k in 0..log.len() {
        let b = measured(ff, &mut data, log, k).unwrap();
        let (q, v, a) = log.state(k);
        let y = momentlmi::dynamics::regressor(ff, &mut data, &q, &v, &a).unwrap();
        for i in rows.range(ff.dof()) {
            let pred: f64 = (0..theta.len()).map(|j| y[(i, j)] * theta[j]).sum();
            sum += (b[i] - pred).powi(2);
            count += 1;
        }
    }
    (sum / count as f64).sqrt()
}

/// The generalized `q`, `v`, `a` of every sample, laid end to end
/// (`samples × nq`, `samples × nv`, `samples × nv`).
#[allow(dead_code)]
pub fn generalized(log: &Dataset) -> [Vec<f64>; 3] {
    let [mut q, mut v, mut a] = [vec![], vec![], vec![]];
    for k in 0..log.len() {
        let s = log.state(k);
        q.extend(s.0);
        v.extend(s.1);
        a.extend(s.2);
    }
    [q, v, a]
}
