//! # SDPA sparse format (`.dat-s`): reader, writer and conversion to [`conic`](crate::conic)
//!
//! The SDPA primal problem is
//!
//! ```text
//! minimise    cᵀx
//! subject to  F(x) = Σᵢ xᵢ Fᵢ − F₀ ⪰ 0
//! ```
//!
//! with F block-diagonal: a positive block size is a dense symmetric block, a
//! negative one a diagonal (LP) block. The file gives m, the number of
//! blocks, the block sizes, c, then one line `matno blkno i j value` per
//! upper-triangle entry (1-based; matrix 0 is F₀). Leading lines starting
//! with `"` or `*` are comments; `,{}()` are separators.

mod error;
mod format;

pub use error::SdpaError;
pub use format::SdpaProblem;
