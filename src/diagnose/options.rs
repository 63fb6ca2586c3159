//! [`DiagnoseOptions`]: the split, how many effects, the block test, the
//! memory limit and the effect library; validated at construction.

use super::error::DiagnoseError;
use super::floor::NoiseFloor;
use crate::data::Dataset;
use crate::effects::Library;
use std::sync::Arc;

/// Options, validated at construction ([`DiagnoseOptions::new`]).
#[derive(Clone, Debug, PartialEq)]
pub struct DiagnoseOptions {
    train_fraction: f64,
    max_effects: usize,
    blocks: usize,
    max_memory_bytes: u64,
    library: Library,
    noise_floor: Option<NoiseFloor>,
    folds: usize,
    nominal_data: Option<Arc<Dataset>>,
}

/// The memory a diagnosis may plan for by default (8 GiB).
pub const DEFAULT_MAX_MEMORY_BYTES: u64 = 8 << 30;

impl Default for DiagnoseOptions {
    /// 60 % training, at most 8 effects, 20 held-out blocks, 8 GiB, the
    /// built-in effect library.
    fn default() -> Self {
        Self {
            train_fraction: 0.6,
            max_effects: 8,
            blocks: 20,
            max_memory_bytes: DEFAULT_MAX_MEMORY_BYTES,
            library: Library::builtin(),
            noise_floor: None,
            folds: super::folds::TIME_FOLDS,
            nominal_data: None,
        }
    }
}

impl DiagnoseOptions {
    /// `train_fraction` of the samples (from the start) fit, in [0.1, 0.9];
    /// at most `max_effects` (≥ 1) effects are accepted; the held-out block
    /// test uses `blocks` (2 … 1000) blocks.
    pub fn new(
        train_fraction: f64,
        max_effects: usize,
        blocks: usize,
    ) -> Result<Self, DiagnoseError> {
        if !(train_fraction >= 0.1 && train_fraction <= 0.9) {
            return Err(DiagnoseError::Option {
                option: "train_fraction",
                value: train_fraction,
                message: "must be in [0.1, 0.9] (both parts need samples)",
            });
        }
        if max_effects == 0 {
            return Err(DiagnoseError::Option {
                option: "max_effects",
                value: 0.0,
                message: "must be at least 1",
            });
        }
        if !(2..=1000).contains(&blocks) {
            return Err(DiagnoseError::Option {
                option: "blocks",
                value: blocks as f64,
                message: "must be in 2 … 1000",
            });
        }
        Ok(Self {
            train_fraction,
            max_effects,
            blocks,
            ..Self::default()
        })
    }

    /// The data the nominal model was identified on (samples of its
    /// joints, with torques): its bodies are then refit with the friction
    /// law in every fit, on those data and the diagnosed fitting folds
    /// together, so that a change of the bodies those data could not
    /// determine is not named an effect (`diagnose::nominal_data`); the
    /// candidates that change the nominal's bodies (`link_inertia`,
    /// `rotor_inertia`) are then not proposed. Without them the bodies are
    /// held as given.
    pub fn with_nominal_data(mut self, data: Dataset) -> Self {
        self.nominal_data = Some(Arc::new(data));
        self
    }

    /// The data the nominal model was identified on, if given.
    pub fn nominal_data(&self) -> Option<&Dataset> {
        self.nominal_data.as_deref()
    }

    /// Fraction of the samples (from the start) used for fitting.
    pub fn train_fraction(&self) -> f64 {
        self.train_fraction
    }

    /// At most this many effects are accepted.
    pub fn max_effects(&self) -> usize {
        self.max_effects
    }

    /// Blocks of the block bootstrap over the cross-validated residual.
    pub fn blocks(&self) -> usize {
        self.blocks
    }

    /// Folds of time (3 … 50) when the data are one file (3 … 10 files
    /// are folds one each, [`super::folds::Folds`]); 5 by default.
    pub fn with_folds(mut self, folds: usize) -> Result<Self, DiagnoseError> {
        if !(super::folds::MIN_FOLDS..=50).contains(&folds) {
            return Err(DiagnoseError::Option {
                option: "folds",
                value: folds as f64,
                message: "must be in 3 … 50 (a per-joint choice of joints needs two other folds)",
            });
        }
        self.folds = folds;
        Ok(self)
    }

    /// Folds of time of one file.
    pub fn folds(&self) -> usize {
        self.folds
    }

    /// The memory the diagnosis may plan for ([`super::memory_estimate`]): beyond
    /// it the inertial candidates and the compliance searches are left out
    /// (with a warning each) and, if the rest of the library does not fit,
    /// the diagnosis is refused before it starts.
    pub fn with_max_memory(mut self, bytes: u64) -> Self {
        self.max_memory_bytes = bytes;
        self
    }

    /// The noise floor to measure the gap against (e.g. from two runs that
    /// repeat a trajectory, [`super::floor::repeat_floor`]) instead of the
    /// residual's first differences; one number per joint of the data.
    pub fn with_noise_floor(mut self, floor: NoiseFloor) -> Self {
        self.noise_floor = Some(floor);
        self
    }

    /// The noise floor given, if any.
    pub fn noise_floor(&self) -> Option<&NoiseFloor> {
        self.noise_floor.as_ref()
    }

    /// The memory limit (bytes).
    pub fn max_memory(&self) -> u64 {
        self.max_memory_bytes
    }

    /// The effects the diagnosis proposes, in the order it tries them (the
    /// built-in library by default; a user's own effects added with
    /// [`Library::add`]).
    pub fn with_library(mut self, library: Library) -> Self {
        self.library = library;
        self
    }

    /// The candidate effects.
    pub fn library(&self) -> &Library {
        &self.library
    }
}
