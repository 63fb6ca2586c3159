//! Errors of the effect library.

use super::params::Range;
use crate::dynamics::DynamicsError;
use crate::sim::SimError;

/// What goes wrong naming, configuring, simulating or building an effect.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EffectError {
    /// No effect of that name in the library.
    #[error("unknown effect '{name}' (valid: {})", valid.join(", "))]
    UnknownEffect {
        /// The name given.
        name: String,
        /// The library's effects.
        valid: Vec<String>,
    },
    /// No parameter of that name in the library.
    #[error("unknown effect parameter '{name}' (valid: {})", valid.join(", "))]
    UnknownParam {
        /// The name given.
        name: String,
        /// The library's parameters.
        valid: Vec<String>,
    },
    /// An override of a parameter whose effects are all off.
    #[error("effect parameter '{param}' belongs to {}, which is not switched on", effects.join(" / "))]
    NotOn {
        /// The parameter.
        param: String,
        /// The effects that have it.
        effects: Vec<String>,
    },
    /// A value outside its parameter's range.
    #[error("effect parameter '{param}' = {} is out of its range ({range})", crate::numfmt::short(*value))]
    OutOfRange {
        /// The parameter.
        param: &'static str,
        /// The value.
        value: f64,
        /// What it admits.
        range: Range,
    },
    /// A robot's `[effects]` table (its sidecar) names a parameter no effect
    /// of the library has, or gives a value out of range.
    #[error("{robot}: [effects]: {source}")]
    Defaults {
        /// The robot's files (built-in name, or URDF path and sidecar).
        robot: String,
        /// What is wrong.
        #[source]
        source: Box<EffectError>,
    },
    /// Two effects of one name in a library.
    #[error("the library already has an effect named '{0}'")]
    Duplicate(String),
    /// Two effects declare a parameter of one name differently.
    #[error(
        "effect '{effect}' declares parameter '{param}' unlike effect '{other}' does (a shared parameter must have one spec)"
    )]
    Conflict {
        /// The effect added.
        effect: String,
        /// The parameter.
        param: String,
        /// The effect that declared it first.
        other: String,
    },
    /// An effect asked for a parameter it does not declare.
    #[error("effect '{effect}' has no parameter '{param}' (declare it in its params())")]
    Undeclared {
        /// The effect.
        effect: String,
        /// The parameter.
        param: String,
    },
    /// An effect cannot be applied to this robot.
    #[error("effect '{effect}' cannot be simulated on this robot: {reason}")]
    NotApplicable {
        /// The effect.
        effect: String,
        /// Why.
        reason: &'static str,
    },
    /// The simulator failed.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// The nominal model's torques or linearisation failed.
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
    /// The regressor failed at a sample.
    #[error("the regressor at sample {sample}: {source}")]
    Regressor {
        /// The sample (0-based).
        sample: usize,
        /// Why.
        #[source]
        source: DynamicsError,
    },
    /// A result shared by several hypotheses (the nominal torques, the
    /// linearisation) failed; the first to ask got the error.
    #[error(transparent)]
    Shared(std::sync::Arc<EffectError>),
    /// An effect's own error (a user's effect: a joint it names that the
    /// robot lacks, …).
    #[error("effect '{effect}': {source}")]
    Own {
        /// The effect.
        effect: &'static str,
        /// What went wrong.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// A hypothesis searched by simulation found nothing that simulates.
    #[error("no hypothesis of the search could be simulated")]
    SearchFailed,
    /// A recorded variant that the effect cannot build again on these data.
    #[error(
        "effect '{effect}': no variant with {key} on these data (a searched fit is not rebuilt on other data)"
    )]
    NotReplayable {
        /// The effect.
        effect: String,
        /// The recorded key, in words.
        key: String,
    },
}
