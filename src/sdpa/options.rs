//! Options of the SDPA reader: a builder with defaults, validated once.

use super::error::SdpaError;
use crate::conic::Decomposition;

/// Default memory limit in GiB (docs/inputs.md, "SDPA problems").
pub const DEFAULT_MAX_MEMORY_GIB: f64 = 8.0;

/// Options of [`SdpaProblem::read_with`](super::SdpaProblem::read_with) and
/// [`SdpaProblem::to_problem_with`](super::SdpaProblem::to_problem_with).
///
/// ```
/// use momentlmi::sdpa::SdpaOptions;
/// let o = SdpaOptions::default().max_memory_gib(2.0);
/// assert!(o.validate().is_ok());
/// assert_eq!(o.max_memory_bytes(), 2.0 * 1024f64.powi(3));
/// assert!(SdpaOptions::default().max_memory_gib(f64::NAN).validate().is_err());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SdpaOptions {
    max_memory_gib: f64,
    decomposition: Decomposition,
}

impl Default for SdpaOptions {
    fn default() -> Self {
        Self {
            max_memory_gib: DEFAULT_MAX_MEMORY_GIB,
            decomposition: Decomposition::Verified,
        }
    }
}

impl SdpaOptions {
    /// Largest memory, in GiB (2³⁰ bytes), that reading a file or solving
    /// its problem may need by [`MemoryEstimate`](super::MemoryEstimate)
    /// (default 8; finite and > 0).
    pub fn max_memory_gib(mut self, gib: f64) -> Self {
        self.max_memory_gib = gib;
        self
    }

    /// The chordal decomposition the solve will use (default
    /// [`Decomposition::Verified`], as [`Settings`](crate::conic::Settings)):
    /// it decides which memory estimate is held against the limit, and
    /// [`MemoryEstimate::settings_for`](super::MemoryEstimate::settings_for)
    /// passes it on to the solver.
    pub fn decomposition(mut self, d: Decomposition) -> Self {
        self.decomposition = d;
        self
    }

    /// The chordal decomposition chosen.
    pub fn decomposition_mode(&self) -> Decomposition {
        self.decomposition
    }

    /// The memory limit in GiB.
    pub fn memory_limit_gib(&self) -> f64 {
        self.max_memory_gib
    }

    /// The memory limit in bytes.
    pub fn max_memory_bytes(&self) -> f64 {
        self.max_memory_gib * GIB
    }

    /// Checks the options: the memory limit finite and positive.
    pub fn validate(&self) -> Result<(), SdpaError> {
        let g = self.max_memory_gib;
        if !(g.is_finite() && g > 0.0) {
            return Err(SdpaError::InvalidOption {
                name: "max_memory_gib",
                reason: format!("must be a finite number of GiB > 0, got {g}"),
            });
        }
        Ok(())
    }
}

/// Bytes in a GiB.
pub(crate) const GIB: f64 = 1024.0 * 1024.0 * 1024.0;
