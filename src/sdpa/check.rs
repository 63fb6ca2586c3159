//! The format's rules on entries, shared by the parser (errors with line
//! numbers) and by problems built in code (errors naming the field).

use super::error::SdpaError;
use super::problem::SdpaProblem;

/// Largest m: the conic layer indexes variables with 32 bits.
pub const MAX_VARIABLES: usize = u32::MAX as usize;

/// Why the entry (matrix `mat`, 1-based block `blk`, 1-based `i`, `j`)
/// does not fit the declared m and block sizes, if it does not.
pub(crate) fn entry_fault(
    m: usize,
    blocks: &[i64],
    mat: usize,
    blk: usize,
    i: usize,
    j: usize,
) -> Option<String> {
    if mat > m {
        return Some(format!("matrix number {mat} > m = {m}"));
    }
    if blk == 0 || blk > blocks.len() {
        return Some(format!("block number {blk} not in 1..={}", blocks.len()));
    }
    let b = blocks[blk - 1];
    let size = b.unsigned_abs();
    let outside = |k: usize| k == 0 || k as u64 > size;
    if outside(i) || outside(j) {
        return Some(format!(
            "entry ({i}, {j}) outside block {blk} of size {size} (rows and columns are 1..={size})"
        ));
    }
    if b < 0 && i != j {
        return Some(format!(
            "off-diagonal entry ({i}, {j}) in diagonal block {blk} (an LP block)"
        ));
    }
    None
}

/// The first repeated key among items `0..n` in order: (index of its
/// first occurrence, index of the repeat), the repeat being the earliest.
pub(crate) fn first_duplicate<K: Ord>(
    n: usize,
    key: impl Fn(usize) -> K,
) -> Option<(usize, usize)> {
    let mut idx: Vec<usize> = (0..n).collect();
    idx.sort_unstable_by(|&a, &b| key(a).cmp(&key(b)).then(a.cmp(&b)));
    idx.windows(2)
        .filter(|w| key(w[0]) == key(w[1]))
        .map(|w| (w[0], w[1]))
        .min_by_key(|&(_, later)| later)
}

fn invalid(what: String, message: String) -> SdpaError {
    SdpaError::Invalid { what, message }
}

impl SdpaProblem {
    /// Checks a problem against the format's rules: m ≤ [`MAX_VARIABLES`],
    /// finite c, non-zero block sizes, every entry inside its block
    /// (diagonal blocks: diagonal entries only) with a finite value and a
    /// matrix number ≤ m, and no entry given twice. Parsed problems pass by
    /// construction; [`SdpaProblem::to_problem`] calls this for problems
    /// built in code.
    pub fn validate(&self) -> Result<(), SdpaError> {
        let m = self.m();
        if m > MAX_VARIABLES {
            return Err(SdpaError::Limit {
                what: "m (the number of variables)".into(),
                value: m.to_string(),
                reason: format!("more than the limit {MAX_VARIABLES}"),
            });
        }
        if let Some(k) = self.c.iter().position(|v| !v.is_finite()) {
            return Err(invalid(
                format!("c[{k}]"),
                format!("{} is not finite", self.c[k]),
            ));
        }
        if let Some(k) = self.blocks.iter().position(|&b| b == 0) {
            return Err(invalid(format!("blocks[{k}]"), "block size 0".into()));
        }
        for (k, &(mat, blk, i, j, v)) in self.entries.iter().enumerate() {
            let one = |x: usize| x.saturating_add(1);
            if let Some(msg) = entry_fault(m, &self.blocks, mat, one(blk), one(i), one(j)) {
                return Err(invalid(format!("entries[{k}]"), msg));
            }
            if !v.is_finite() {
                return Err(invalid(
                    format!("entries[{k}]"),
                    format!("value {v} is not finite"),
                ));
            }
        }
        let key = |k: usize| {
            let (mat, blk, i, j, _) = self.entries[k];
            (mat, blk, i.min(j), i.max(j))
        };
        if let Some((a, b)) = first_duplicate(self.entries.len(), key) {
            let (mat, blk, i, j) = key(a);
            return Err(invalid(
                format!("entries[{b}]"),
                format!(
                    "entry (matrix {mat}, block {}, {}, {}) repeats entries[{a}]",
                    blk + 1,
                    i + 1,
                    j + 1
                ),
            ));
        }
        Ok(())
    }
}
