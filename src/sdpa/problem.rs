//! [`SdpaProblem`]: the SDPA data, as read or built in code.

/// An SDPA problem: `min cᵀx s.t. Σ xᵢ Fᵢ − F₀ ⪰ 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct SdpaProblem {
    /// Cost vector c (length m).
    pub c: Vec<f64>,
    /// Block sizes: `n > 0` a dense `n × n` block, `n < 0` a diagonal block of size `|n|`.
    pub blocks: Vec<i64>,
    /// Entries `(matrix 0..=m, block 0-based, i, j, value)`, 0-based `i ≤ j`,
    /// each `(matrix, block, i, j)` at most once.
    pub entries: Vec<(usize, usize, usize, usize, f64)>,
}
