//! The memory a solve will need, estimated from the sizes alone, before
//! anything is allocated from them.
//!
//! Clarabel keeps, for each PSD cone of side n, its scaling Hessian as a
//! dense `t × t` matrix with `t = n(n+1)/2`, puts that block's upper
//! triangle into the KKT matrix (values, row indices and a map), keeps a
//! permuted copy for the factorisation, and the LDLᵀ factor of a dense
//! block is dense too. All of that is `Θ(t²) = Θ(n⁴)`: measured peak memory
//! is 52–54 bytes per `t²` from n = 40 to n = 100 with either KKT solver
//! (n = 100: 1.31 GB), so a single block of side 250 needs about 48 GiB.
//! The estimate is
//!
//! ```text
//! bytes ≈ Σ_PSD blocks [ 56 t² + 16 (2 t mₖ + mₖ²) + 64 n² ]
//!       + 512 · rows + 768 · m + 256 · entries + 1024 · blocks + 32 MiB
//! ```
//!
//! with mₖ ≤ min(m, entries of block k) the variables block k touches (the
//! factor's fill between them and the block), rows = Σ t + Σ |LP sizes|.
//! Diagonal (LP) blocks are linear in their size. Fill-in between variables
//! through LP rows is not estimated (it is what a sparse LP costs anyway).
//!
//! With chordal decomposition (the default) a sparse block becomes several
//! smaller cones: [`MemoryEstimate::decomposed_dense_bytes`] charges the same
//! 56 bytes per t² to the estimated Σ t² of those cones (`sdpa::cliques`)
//! instead of the block's t². Which of the two totals is held against the
//! limit follows [`SdpaOptions::decomposition`].

use super::cliques::decomposed_t2;
use super::error::{SdpaError, gib};
use super::options::{GIB, SdpaOptions};
use super::problem::SdpaProblem;
use crate::conic::{AffExpr, Decomposition, Settings};
use std::path::Path;

/// Bytes per `t²` of a PSD block with `t = n(n+1)/2` rows.
pub const BYTES_PER_DENSE: f64 = 56.0;
/// Bytes per element of a PSD block's coupling with its variables.
const BYTES_PER_COUPLING: f64 = 16.0;
/// Bytes per `n²` of a PSD block of side n (the n × n expression built
/// once, the cone's n × n work matrices).
const BYTES_PER_SIDE_SQUARED: f64 = 64.0;
/// Bytes per conic row (expressions, the solver's vectors).
pub const BYTES_PER_ROW: f64 = 512.0;
/// Bytes per variable (names, the solver's vectors).
pub const BYTES_PER_VARIABLE: f64 = 768.0;
/// Bytes per entry of the file (stored, as a term, in A and its copies).
pub const BYTES_PER_ENTRY: f64 = 256.0;
/// Bytes per block (a constraint, a cone).
const BYTES_PER_BLOCK: f64 = 1024.0;
/// Bytes of the process and the solver whatever the size.
pub const BYTES_FIXED: f64 = 32.0 * 1024.0 * 1024.0;
/// Reading a file needs about this many bytes per byte of file (the text,
/// the entries and their line numbers).
pub const READ_BYTES_PER_FILE_BYTE: f64 = 8.0;

/// The estimated memory of converting and solving one SDPA problem
/// ([`SdpaProblem::memory_estimate`]); all sizes were computed with checked
/// arithmetic.
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryEstimate {
    /// Bytes of the PSD blocks' dense parts (`Θ(n⁴)` per block of side n).
    pub dense_bytes: f64,
    /// The same with the blocks that Clarabel's chordal decomposition is
    /// estimated to split charged for their cones instead (module docs);
    /// equal to `dense_bytes` when no block splits.
    pub decomposed_dense_bytes: f64,
    /// How many PSD blocks are estimated to split.
    pub decomposed_blocks: usize,
    /// Bytes linear in the rows, variables, entries and blocks, plus a
    /// fixed 32 MiB.
    pub linear_bytes: f64,
    /// Rows of the conic problem: Σ n(n+1)/2 over PSD blocks + Σ |n| over LP blocks.
    pub rows: usize,
    /// Side of the largest PSD block (0 without one).
    pub largest_psd_side: usize,
}

impl MemoryEstimate {
    /// Total bytes without decomposition.
    pub fn total_bytes(&self) -> f64 {
        self.dense_bytes + self.linear_bytes
    }

    /// Total bytes with chordal decomposition.
    pub fn decomposed_total_bytes(&self) -> f64 {
        self.decomposed_dense_bytes + self.linear_bytes
    }

    /// The total held against the limit: decomposed unless `opts` turn
    /// decomposition off.
    pub fn bytes_for(&self, opts: &SdpaOptions) -> f64 {
        match opts.decomposition_mode() {
            Decomposition::Off => self.total_bytes(),
            _ => self.decomposed_total_bytes(),
        }
    }

    /// `settings` with `opts`' decomposition, and with the fall-back to an
    /// undecomposed solve forbidden when that solve's estimate is above the
    /// limit (the solve then ends in
    /// [`ConicError::DecompositionRejected`](crate::conic::ConicError::DecompositionRejected)
    /// rather than allocate it).
    pub fn settings_for(&self, opts: &SdpaOptions, settings: Settings) -> Settings {
        let s = settings.decomposition(opts.decomposition_mode());
        if self.total_bytes() <= opts.max_memory_bytes() {
            return s;
        }
        s.forbid_decomposition_fallback(format!(
            "without decomposition the solve would need {} GiB, above the limit of {} GiB \
             (a higher max_memory_gib allows it)",
            gib(self.total_gib()),
            gib(opts.memory_limit_gib())
        ))
    }

    /// Total GiB.
    pub fn total_gib(&self) -> f64 {
        self.total_bytes() / GIB
    }

    /// The parts of the estimate, for a message.
    pub fn detail(&self) -> String {
        if self.decomposed_blocks > 0 {
            return format!(
                "{}; with chordal decomposition of {} block(s) {} GiB for their cones",
                self.undecomposed_detail(),
                self.decomposed_blocks,
                gib(self.decomposed_dense_bytes / GIB)
            );
        }
        self.undecomposed_detail()
    }

    fn undecomposed_detail(&self) -> String {
        let linear = format!(
            "{} GiB for {} rows, the variables and the entries",
            gib(self.linear_bytes / GIB),
            self.rows
        );
        if self.largest_psd_side == 0 {
            return linear;
        }
        format!(
            "{} GiB for the dense PSD blocks, the largest of side {}; {linear}",
            gib(self.dense_bytes / GIB),
            self.largest_psd_side
        )
    }

    /// [`SdpaError::TooLarge`] if the total ([`bytes_for`](Self::bytes_for))
    /// is above `opts`' limit.
    pub fn check(&self, opts: &SdpaOptions) -> Result<(), SdpaError> {
        opts.validate()?;
        let needed = self.bytes_for(opts);
        if needed <= opts.max_memory_bytes() {
            return Ok(());
        }
        Err(SdpaError::TooLarge {
            what: "the solve".into(),
            needed_gib: needed / GIB,
            limit_gib: opts.memory_limit_gib(),
            detail: self.detail(),
        })
    }
}

fn overflow(block: usize, n: u64, what: &str) -> SdpaError {
    SdpaError::Limit {
        what: format!("block {block} side"),
        value: n.to_string(),
        reason: format!("{what} overflows this machine's indices"),
    }
}

/// Rows of a PSD block of side n, n(n+1)/2, and a check that its n × n
/// expression is addressable.
fn psd_rows(block: usize, n: u64) -> Result<usize, SdpaError> {
    let n = usize::try_from(n).map_err(|_| overflow(block, n, "n"))?;
    let addressable = n
        .checked_mul(n)
        .and_then(|s| s.checked_mul(size_of::<AffExpr>()))
        .is_some_and(|bytes| bytes <= isize::MAX as usize);
    if !addressable {
        return Err(overflow(block, n as u64, "its n × n expression"));
    }
    n.checked_mul(n + 1)
        .map(|x| x / 2)
        .ok_or_else(|| overflow(block, n as u64, "n(n+1)/2"))
}

/// Bytes of a PSD block of side n with t rows touched by mₖ variables,
/// whole and decomposed as estimated from its off-diagonal pattern.
fn psd_block_bytes(t: usize, mk: f64, n: u64, pattern: &[(usize, usize)]) -> (f64, f64) {
    let (tf, nf) = (t as f64, n as f64);
    let rest = BYTES_PER_COUPLING * (2.0 * tf * mk + mk * mk) + BYTES_PER_SIDE_SQUARED * nf * nf;
    let whole = tf * tf;
    let split =
        decomposed_t2(n as usize, pattern.iter().copied()).map_or(whole, |t2| t2.min(whole));
    (
        BYTES_PER_DENSE * whole + rest,
        BYTES_PER_DENSE * split + rest,
    )
}

impl SdpaProblem {
    /// The memory converting and solving this problem will need (module
    /// docs of `sdpa::memory`, docs/inputs.md); an error if a size
    /// overflows. Takes O(entries) time and no memory of the declared sizes,
    /// plus the bounded clique analysis of each PSD block (`sdpa::cliques`).
    pub fn memory_estimate(&self) -> Result<MemoryEstimate, SdpaError> {
        let m = self.m() as f64;
        let mut per_block = vec![0usize; self.blocks.len()];
        for e in self.entries.iter().filter(|e| e.0 > 0) {
            if let Some(c) = per_block.get_mut(e.1) {
                *c += 1;
            }
        }
        let patterns = self.block_patterns();
        let (mut dense, mut decomposed, mut split) = (0.0, 0.0, 0usize);
        let (mut rows, mut largest) = (0usize, 0usize);
        for (b, (&size, &touched)) in self.blocks.iter().zip(&per_block).enumerate() {
            let n = size.unsigned_abs();
            let r = if size > 0 {
                let t = psd_rows(b + 1, n)?;
                let (d, dd) = psd_block_bytes(t, m.min(touched as f64), n, &patterns[b]);
                (dense, decomposed) = (dense + d, decomposed + dd);
                split += usize::from(dd < d);
                largest = largest.max(n as usize);
                t
            } else {
                usize::try_from(n).map_err(|_| overflow(b + 1, n, "n"))?
            };
            rows = rows.checked_add(r).ok_or_else(|| SdpaError::Limit {
                what: "rows of the conic problem".into(),
                value: format!("more than {}", usize::MAX),
                reason: format!("the sum overflows at block {}", b + 1),
            })?;
        }
        let linear = BYTES_FIXED
            + BYTES_PER_ROW * rows as f64
            + BYTES_PER_VARIABLE * m
            + BYTES_PER_ENTRY * self.entries.len() as f64
            + BYTES_PER_BLOCK * self.blocks.len() as f64;
        Ok(MemoryEstimate {
            dense_bytes: dense,
            decomposed_dense_bytes: decomposed,
            decomposed_blocks: split,
            linear_bytes: linear,
            rows,
            largest_psd_side: largest,
        })
    }
}

impl SdpaProblem {
    /// The off-diagonal positions (0-based) of each PSD block's entries, in
    /// one pass over the entries.
    fn block_patterns(&self) -> Vec<Vec<(usize, usize)>> {
        let mut p = vec![Vec::new(); self.blocks.len()];
        for e in self.entries.iter().filter(|e| e.2 != e.3) {
            if self.blocks.get(e.1).is_some_and(|&s| s > 0) {
                p[e.1].push((e.2, e.3));
            }
        }
        p
    }
}

/// [`SdpaError::TooLarge`] if reading a file of `len` bytes would need more
/// than the limit.
pub(crate) fn check_read(path: &Path, len: u64, opts: &SdpaOptions) -> Result<(), SdpaError> {
    let needed = READ_BYTES_PER_FILE_BYTE * len as f64;
    if needed <= opts.max_memory_bytes() {
        return Ok(());
    }
    Err(SdpaError::TooLarge {
        what: format!("reading {}", path.display()),
        needed_gib: needed / GIB,
        limit_gib: opts.memory_limit_gib(),
        detail: format!("{READ_BYTES_PER_FILE_BYTE} bytes per byte of its {len} bytes"),
    })
}
