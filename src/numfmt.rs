//! Numbers in messages, as people write them.

/// Plain in 1e-4 … 1e6 (and 0, NaN, ±inf), else in e-notation: `1e300`, not
/// three hundred zeros.
pub fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) {
        v.to_string()
    } else {
        format!("{v:e}")
    }
}

/// `v` rounded to 4 significant digits, written as [`short`] writes it.
pub fn sig4(v: f64) -> String {
    // through the decimal text: scaling by 10^k in binary leaves 1e303 as
    // 1.0000000000000006e303
    let rounded = format!("{v:.3e}").parse().unwrap_or(v);
    short(rounded)
}

/// The longest text from a file quoted in a message (bytes).
const MAX_QUOTED: usize = 200;

/// `text` from a file as a message quotes it: whole up to 200 bytes, else
/// its start and its length (`abc… (15728640 bytes)`), so that a 15 MB
/// column name makes a short error.
pub fn clip(text: &str) -> std::borrow::Cow<'_, str> {
    if text.len() <= MAX_QUOTED {
        return text.into();
    }
    let mut end = MAX_QUOTED;
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}… ({} bytes)", &text[..end], text.len()).into()
}
