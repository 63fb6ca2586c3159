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

/// `v` rounded to 4 significant digits, written as [`short`] writes it.
pub(crate) fn sig4(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return short(v);
    }
    let e = v.abs().log10().floor() as i32;
    let scale = 10f64.powi(3 - e);
    short((v * scale).round() / scale)
}
