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

impl ReadOptions {
    /// The options that mean nothing whatever the file, refused before a
    /// file is read (a cut-off that is not a positive frequency; one given
    /// with prepared files that need none is still checked). Each file's own
    /// range (above a sample's worth, below Nyquist) is checked where the
    /// file is prepared.
    pub fn check(&self) -> Result<(), super::DataError> {
        match self.cutoff_hz {
            Some(c) if !(c > 0.0 && c.is_finite()) => Err(super::DataError::Option {
                option: "cutoff_hz",
                value: crate::numfmt::short(c),
                message: "must be a positive frequency (Hz)".into(),
            }),
            _ => Ok(()),
        }
    }
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
