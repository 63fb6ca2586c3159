//! How logs are read: the options every reader takes.

use super::mapping::Mapping;
use super::prepare::Velocity;

/// Options for reading.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadOptions {
    /// The low-pass cut-off (Hz) of raw logs; `None`: chosen from the data.
    pub cutoff_hz: Option<f64>,
    /// Where a raw log's q̇ comes from.
    pub velocity: Velocity,
    /// Whether torques are required.
    pub require_tau: bool,
    /// Which array or column is what (default: each format's own names).
    pub mapping: Option<Mapping>,
    /// Whether `mapping` is only the robot's default (its sidecar's), not
    /// the user's: a file that has its format's own time name (`t`) and not
    /// the mapping's is then read with the format's own names (a log that
    /// `simulate` wrote, say).
    pub mapping_is_default: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            cutoff_hz: None,
            velocity: Velocity::Differentiate,
            require_tau: true,
            mapping: None,
            mapping_is_default: false,
        }
    }
}
