//! The singular values of a stacked regressor with its columns scaled to
//! unit norm (a column at rounding level, ≤ 1e-10 of the largest, zeroed
//! rather than scaled up): the tests' own route to a numerical rank, apart
//! from the library's pivoted QR (`#[path = "support/rank.rs"] mod rank;`).
#![allow(dead_code)]

use faer::Mat;

/// The scaled singular values of the row-major `rows × p` regressor `y`,
/// largest first.
pub fn scaled_singular_values(y: &[f64], p: usize) -> Vec<f64> {
    let rows = y.len() / p;
    let mut m = Mat::<f64>::from_fn(rows, p, |i, j| y[i * p + j]);
    let norms: Vec<f64> = (0..p)
        .map(|j| (0..rows).map(|i| m[(i, j)].powi(2)).sum::<f64>().sqrt())
        .collect();
    let largest = norms.iter().cloned().fold(0.0, f64::max);
    for (j, &norm) in norms.iter().enumerate() {
        let s = if norm > 1e-10 * largest {
            1.0 / norm
        } else {
            0.0
        };
        (0..rows).for_each(|i| m[(i, j)] *= s);
    }
    m.singular_values().unwrap()
}
