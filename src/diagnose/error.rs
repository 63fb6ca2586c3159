//! Errors of the diagnosis.

use crate::dynamics::DynamicsError;

/// What stops a diagnosis. (A candidate whose fit fails does not stop it: it
/// is skipped with a warning in [`super::Diagnosis::warnings`].)
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DiagnoseError {
    /// Too few samples, or no torques.
    #[error("diagnosis needs at least {needed} samples with torques, the data have {found}")]
    TooFewSamples {
        /// The minimum.
        needed: usize,
        /// The samples with torques.
        found: usize,
    },
    /// The data's joints are not the model's.
    #[error("the data have joints {found:?}, the model {expected:?}")]
    Joints {
        /// The model's joints.
        expected: Vec<String>,
        /// The data's joints.
        found: Vec<String>,
    },
    /// An option out of range.
    #[error("diagnosis option '{option}' = {}: {message}", crate::numfmt::short(*value))]
    Option {
        /// The option.
        option: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        message: &'static str,
    },
    /// A reported number that is not finite (an overflow in the data's
    /// arithmetic); no verdict is given on it.
    #[error("{what} is not finite: an overflow in the data or the model")]
    NonFinite {
        /// Which number.
        what: &'static str,
    },
    /// Two runs given as repeats of one trajectory that are not, or a
    /// noise floor that does not fit the data.
    #[error("the repeated runs for the noise floor: {why}")]
    NotRepeats {
        /// Why.
        why: String,
    },
    /// No joint moves in the data: nothing about the dynamics can be told.
    #[error("no joint moves in the data (every q is constant): a diagnosis needs motion")]
    NoMotion,
    /// The diagnosis would need more memory than it may use.
    #[error(
        "the diagnosis would need about {needed_gib:.2} GiB for its candidate library, beyond the {limit_gib:.2} GiB limit: use fewer samples, lock joints in the sidecar, or raise the limit"
    )]
    TooLarge {
        /// Estimated need (GiB).
        needed_gib: f64,
        /// The limit (GiB).
        limit_gib: f64,
    },
    /// The nominal model's prediction failed.
    #[error("the nominal model's torques: {0}")]
    Predict(#[source] DynamicsError),
    /// The fitted effects of a model could not be applied.
    #[error("the model's fitted effects: {0}")]
    Effects(#[source] crate::effects::EffectError),
    /// The regressor failed at a sample.
    #[error("the regressor at sample {sample}: {source}")]
    Regressor {
        /// The sample (0-based).
        sample: usize,
        /// Why.
        #[source]
        source: DynamicsError,
    },
    /// The data the nominal model was identified on do not fit it.
    #[error("the data the nominal model was identified on: {0}")]
    NominalData(#[source] Box<DiagnoseError>),
    /// The data diagnosed are among the data the nominal was identified on.
    #[error(
        "{rows} of the {total} samples diagnosed are also among the data the nominal model was identified on: its rows join every fit, so the folds held out would be fitted; give the runs it was not identified on"
    )]
    Overlap {
        /// The samples found in both.
        rows: usize,
        /// The samples diagnosed.
        total: usize,
    },
    /// The model has no tool point (no moving body) for the payload candidate.
    #[error("the model has no tool point (no moving body) for the payload candidate")]
    NoTool,
    /// A floating-base diagnosis given no log.
    #[error("floating base: no log to diagnose")]
    NoLogs,
    /// A floating-base log that does not fit the robot (1-based).
    #[error("floating base: log {log}: {source}")]
    Log {
        /// The log (1-based).
        log: usize,
        /// Why.
        #[source]
        source: crate::data::DataError,
    },
    /// A floating-base log whose contacts are not the first log's.
    #[error("floating base: log {log} has other contacts ({found}) than the first ({first})")]
    Contacts {
        /// The log (1-based).
        log: usize,
        /// Its contacts (frame and axes).
        found: String,
        /// The first log's.
        first: String,
    },
    /// A floating-base log too short to split into fitted and held-out parts.
    #[error(
        "floating base: log {log} has {found} samples; a diagnosis needs at least {needed} (its last 30 % held out)"
    )]
    ShortLog {
        /// The log (1-based).
        log: usize,
        /// Its samples.
        found: usize,
        /// The minimum.
        needed: usize,
    },
    /// The nominal model's residual of a floating-base log failed.
    #[error("floating base: log {log}: the nominal residual: {source}")]
    Residual {
        /// The log (1-based).
        log: usize,
        /// Why.
        #[source]
        source: crate::identify::IdentifyError,
    },
    /// A fit the diagnosis cannot do without failed.
    #[error("{what}: {source}")]
    Fit {
        /// Which fit.
        what: &'static str,
        /// Why.
        #[source]
        source: FitError,
    },
}

/// Why one candidate's fit failed (the candidate is then skipped, with a warning).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FitError {
    /// The normal equations could not be factorised (non-finite columns).
    #[error("the least-squares normal equations could not be factorised")]
    Factorisation,
    /// The constrained fit could not be built or solved.
    #[error(transparent)]
    Conic(#[from] crate::conic::ConicError),
    /// The constrained fit ended without a solution.
    #[error("the constrained fit ended with status {0}")]
    Status(crate::conic::Status),
    /// The compliance hypothesis could not be simulated.
    #[error("{0}")]
    Compliance(&'static str),
}
