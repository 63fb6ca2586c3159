//! The one RMS helper every layer uses.

/// The root mean square of `values` (0 when there are none), summed in order.
pub fn rms(values: impl IntoIterator<Item = f64>) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for v in values {
        sum += v * v;
        count += 1;
    }
    (sum / count.max(1) as f64).sqrt()
}

/// Per joint, the RMS of sample-major rows (`rows[k·n + i]`: sample k,
/// joint i).
pub fn rms_per_joint(rows: &[f64], n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| rms(rows.iter().skip(i).step_by(n).copied()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{rms, rms_per_joint};

    #[test]
    fn rms_of_values_and_per_joint() {
        assert_eq!(rms([3.0, 4.0]), (12.5f64).sqrt());
        assert_eq!(rms([]), 0.0);
        assert_eq!(rms_per_joint(&[1.0, 2.0, -1.0, 2.0], 2), vec![1.0, 2.0]);
    }
}
