//! Effect parameters: what an effect declares ([`ParamSpec`]: name, unit,
//! meaning, nominal value, admissible range).

use std::fmt;

/// The largest magnitude of any effect parameter: beyond it the simulated
/// torques leave the range the data readers accept.
pub const MAX_ABS_EFFECT: f64 = 1e6;

/// The values an effect parameter admits (always finite and within
/// ±[`MAX_ABS_EFFECT`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// Any value.
    Any,
    /// `v > 0`.
    Positive,
    /// `v ≥ 0`.
    NonNegative,
    /// `v > lo`.
    Above(f64),
    /// `lo ≤ v ≤ hi`.
    Within(f64, f64),
}

impl Range {
    /// Whether `v` is admitted.
    pub fn admits(self, v: f64) -> bool {
        v.is_finite()
            && v.abs() <= MAX_ABS_EFFECT
            && match self {
                Range::Any => true,
                Range::Positive => v > 0.0,
                Range::NonNegative => v >= 0.0,
                Range::Above(lo) => v > lo,
                Range::Within(lo, hi) => (lo..=hi).contains(&v),
            }
    }
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Range::Any => write!(f, "finite, |v| ≤ {MAX_ABS_EFFECT:e}"),
            Range::Positive => f.write_str("> 0"),
            Range::NonNegative => f.write_str("≥ 0"),
            Range::Above(lo) => write!(f, "> {lo}"),
            Range::Within(lo, hi) => write!(f, "in [{lo}, {hi}]"),
        }
    }
}

/// One parameter of an effect. A name is unique in a library; two effects
/// that share a parameter (the transmission's stiffness, say) declare the
/// same spec.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// The name in `NAME=VALUE` overrides, a sidecar's `[effects]` table and
    /// records (`snake_case`).
    pub name: &'static str,
    /// Its unit (`"N·m"`, `"rad"`, `"1"` for a ratio).
    pub unit: &'static str,
    /// What it is, in a sentence.
    pub doc: &'static str,
    /// The nominal value, before a robot's `[effects]` table or an override.
    pub nominal: f64,
    /// The admissible values.
    pub range: Range,
}

impl ParamSpec {
    /// A parameter.
    pub const fn new(
        name: &'static str,
        unit: &'static str,
        nominal: f64,
        range: Range,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            doc,
            nominal,
            range,
        }
    }
}
