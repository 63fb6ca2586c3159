//! # SDPA sparse format (`.dat-s`): reader, writer and conversion to [`conic`](crate::conic)
//!
//! The SDPA primal problem is
//!
//! ```text
//! minimise    cᵀx
//! subject to  F(x) = Σᵢ xᵢ Fᵢ − F₀ ⪰ 0
//! ```
//!
//! with F block-diagonal: a positive block size is a dense symmetric block
//! (a PSD cone), a negative one a diagonal (LP) block (a non-negative
//! orthant of its size). The file gives m, the number of blocks, the block
//! sizes, c, then one line `matno blkno i j value` per upper-triangle entry
//! (1-based; matrix 0 is F₀). Leading lines starting with `"` or `*` are
//! comments; `,{}()` are separators.
//!
//! The reader takes hostile input: it reads the header and every entry
//! before sizing anything from the header, checks every entry against the
//! declared sizes (an entry given twice is an error), rejects non-finite
//! numbers with their line, computes sizes with checked arithmetic, and
//! [estimates](SdpaProblem::memory_estimate) the memory of the solve against
//! a limit ([`SdpaOptions::max_memory_gib`], default 8 GiB) before building
//! the conic problem. The rules and limits are in docs/inputs.md
//! ("SDPA problems").

mod check;
pub mod cliques;
mod convert;
mod error;
mod format;
mod memory;
mod options;
mod problem;
#[cfg(test)]
mod tests;

pub use check::MAX_VARIABLES;
pub use error::SdpaError;
pub use memory::{
    BYTES_FIXED, BYTES_PER_DENSE, BYTES_PER_ENTRY, BYTES_PER_ROW, BYTES_PER_VARIABLE,
    MemoryEstimate, READ_BYTES_PER_FILE_BYTE,
};
pub use options::{DEFAULT_MAX_MEMORY_GIB, SdpaOptions};
pub use problem::SdpaProblem;
