//! Numbers in messages, as people write them.

/// Plain in 1e-4 … 1e6 (and 0, NaN, ±inf), else in e-notation: `1e300`, not
/// three hundred zeros.
pub(crate) fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) {
        v.to_string()
    } else {
        format!("{v:e}")
    }
}
