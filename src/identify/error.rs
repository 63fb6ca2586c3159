//! Errors of the identification.

use crate::conic::Status;
use crate::dynamics::DynamicsError;
use crate::moments::{Level, MomentsError};

/// What can stop an identification.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IdentifyError {
    /// An option that must be ≥ 0 and finite.
    #[error("identification option '{option}' = {}: must be ≥ 0 and finite", crate::numfmt::short(*value))]
    Negative {
        /// The option.
        option: &'static str,
        /// Its value.
        value: f64,
    },
    /// A prior entry that is not finite.
    #[error("identification option 'prior': entry {index} is not finite ({})", crate::numfmt::short(*value))]
    PriorNotFinite {
        /// The entry (10 per body, links then rotors).
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A prior whose length does not fit the model.
    #[error(
        "identification option 'prior': {found} numbers for {bodies} bodies (10 per body) with weight {weight}{}",
        if *mass_weight > 0.0 { format!(" and prior mass weight {mass_weight}") } else { String::new() }
    )]
    PriorLength {
        /// Numbers given.
        found: usize,
        /// The model's bodies.
        bodies: usize,
        /// The prior's weight.
        weight: f64,
        /// The masses' extra weight.
        mass_weight: f64,
    },
    /// Bounding ellipsoids that are not one per body.
    #[error(
        "identification option 'ellipsoids': {found} bounding ellipsoids for {bodies} bodies; give one per body"
    )]
    EllipsoidCount {
        /// Ellipsoids given.
        found: usize,
        /// The model's bodies.
        bodies: usize,
    },
    /// A body whose level needs a bounding ellipsoid it does not have.
    #[error("body '{body}' has no bounding ellipsoid for its {level} level")]
    NoEllipsoid {
        /// The body.
        body: String,
        /// Its level.
        level: Level,
    },
    /// A robot whose sidecar sets identification facts that
    /// `IdentifyOptions` cannot hold.
    #[error(
        "{robot}'s sidecar sets identification constraints ({}) that IdentifyOptions cannot hold; use Identification::for_robot",
        facts.join(", ")
    )]
    RobotFacts {
        /// The robot's files.
        robot: String,
        /// The facts set.
        facts: Vec<&'static str>,
    },
    /// A body without a prior for the entropic regulariser.
    #[error("body '{body}' has no prior for the entropic regulariser")]
    NoPrior {
        /// The body.
        body: String,
    },
    /// A prior body that is not strictly consistent, under the entropic
    /// regulariser.
    #[error(
        "body '{body}': its prior pseudo-inertia is not positive definite (smallest eigenvalue {min_eig:.3e}); the entropic regulariser needs a strictly consistent prior"
    )]
    PriorNotConsistent {
        /// The body.
        body: String,
        /// The smallest eigenvalue of its prior's J.
        min_eig: f64,
    },
    /// A prior body the entropic regulariser cannot use.
    #[error("body '{body}': its prior: {source}")]
    Prior {
        /// The body.
        body: String,
        /// Why.
        #[source]
        source: MomentsError,
    },
    /// A Gram matrix given as reduced data that is not one.
    #[error("reduced data: {0}")]
    Gram(GramProblem),
    /// Reduced data read from bytes, or added, that do not fit: not
    /// momentlmi's, another format version, another robot, cut short.
    #[error("reduced data: {0}")]
    Stored(String),
    /// An unknown body or joint name.
    #[error("unknown {what} '{name}' (known: {valid})")]
    UnknownName {
        /// A body or a joint.
        what: &'static str,
        /// The name given.
        name: String,
        /// The valid names.
        valid: String,
    },
    /// Rows with joints asked of a floating-base log without joint torques.
    #[error(
        "rows {rows}: a log has no joint torques (tau_<joint> columns); the base rows need none"
    )]
    NoTorquesForRows {
        /// The rows asked (`joints` or `all`).
        rows: &'static str,
    },
    /// The training data have no samples or no torques.
    #[error(
        "the training data need torques (tau_* columns) and at least one sample ({samples} samples, {torques} with torques)"
    )]
    NoTrainingData {
        /// Samples.
        samples: usize,
        /// Samples with torques.
        torques: usize,
    },
    /// Sample vectors of different lengths (q, q̇, q̈, τ).
    #[error("{what} has {found} samples, q has {expected}")]
    SampleCount {
        /// Which vector.
        what: &'static str,
        /// q's samples.
        expected: usize,
        /// Its samples.
        found: usize,
    },
    /// A sample with the wrong number of values.
    #[error("sample {sample}: {what} has {found} values, the model has {expected} joints")]
    SampleLength {
        /// The sample (0-based).
        sample: usize,
        /// Which vector.
        what: &'static str,
        /// Joints.
        expected: usize,
        /// Values found.
        found: usize,
    },
    /// Reduced data of other rows than the set-up's (a free-flyer's base
    /// rows solved as all rows).
    #[error(
        "reduced data hold rows {found:?} of each sample, the identification's set-up fits rows {expected:?} (reduce and solve with the same identify::Rows)"
    )]
    RowCount {
        /// The set-up's rows.
        expected: std::ops::Range<usize>,
        /// The reduced data's.
        found: std::ops::Range<usize>,
    },
    /// A fixed-base step asked of a free-flyer's set-up.
    #[error(
        "{what} needs a fixed-base model; a free-flyer is identified by Identification::for_free_flyer(..).solve(&reduce_floating(..)) (identify::floating)"
    )]
    FreeFlyerSetUp {
        /// The step.
        what: &'static str,
    },
    /// Reduced data of another model.
    #[error("reduced data have {found} columns, the model needs {expected}")]
    Columns {
        /// The model's regressor columns.
        expected: usize,
        /// The reduced data's.
        found: usize,
    },
    /// The regressor failed at a sample.
    #[error("the regressor at sample {sample}: {source}")]
    Regressor {
        /// The sample (0-based).
        sample: usize,
        /// Why.
        #[source]
        source: DynamicsError,
    },
    /// A sample with a non-finite regressor row or torque.
    #[error("sample {sample}: {what}")]
    NonFinite {
        /// The sample (0-based).
        sample: usize,
        /// What is not finite.
        what: &'static str,
    },
    /// A floating-base fit that leaves the whole robot without a mass (at
    /// most a millionth of its URDF's): the logs did not determine it.
    #[error(
        "the fit gives the whole robot a mass of {} kg: the logs do not determine it (a few samples far larger than the rest — velocities or accelerations out of scale — can dominate the fit)",
        crate::numfmt::sig4(*mass)
    )]
    NoWholeMass {
        /// The fitted whole-robot mass (kg).
        mass: f64,
    },
    /// A sum or product that left the floating-point range.
    #[error("{what} overflowed")]
    Overflow {
        /// What.
        what: &'static str,
    },
    /// The identification would need more memory than it may use.
    #[error(
        "identifying this robot would need about {needed_gib:.2} GiB, beyond the {limit_gib:.2} GiB limit: lock joints in the sidecar or raise the limit"
    )]
    TooLarge {
        /// Estimated need (GiB).
        needed_gib: f64,
        /// The limit (GiB).
        limit_gib: f64,
    },
    /// A dense factorisation failed (a value that is not finite, or no convergence).
    #[error("the {what} failed (a value that is not finite, or no convergence)")]
    Factorisation {
        /// Which (the eigen-decomposition of the Gram matrix, the SVD, …).
        what: &'static str,
    },
    /// A per-joint weighting of a reduction that did not keep each
    /// joint's Gram matrix.
    #[error(
        "weighting the joints needs each joint's Gram matrix of the reduction, which kept {kept} of {joints} (too large a robot, or a Gram matrix given whole)"
    )]
    JointGramsMissing {
        /// The model's joints.
        joints: usize,
        /// The per-joint matrices kept.
        kept: usize,
    },
    /// A load friction term fitted on a reduction without its samples.
    #[error(
        "the load friction term is refitted on the rigid torques of every training sample, which a reduction made while reading does not keep: read the data whole"
    )]
    LoadNeedsSamples,
    /// A choice from the data (the friction law, the prior's weight) asked
    /// of a reduction without its samples.
    #[error(
        "choosing the friction law or the prior's weight needs the training samples, which a reduction made while reading does not keep: read the data whole"
    )]
    ChoiceNeedsSamples,
    /// Row weights of a floating-base reduction that are not one finite
    /// number ≥ 0 per row.
    #[error("row weights: {found} given for {rows} rows, each finite and ≥ 0")]
    RowWeights {
        /// Weights given.
        found: usize,
        /// Rows of the generalized force (6 + n).
        rows: usize,
    },
    /// A grid of weights to choose from that is empty or has a weight
    /// that is not positive and finite.
    #[error("the weights to choose from: {what}")]
    WeightGrid {
        /// What is wrong.
        what: String,
    },
    /// A cross-validation fold too small to fit or to score on.
    #[error(
        "cross-validation: fold {fold} has {training} training and {held_out} held-out samples (each needs at least {min}); give longer data or fewer gaps"
    )]
    FoldTooSmall {
        /// The fold (0-based).
        fold: usize,
        /// Its training samples.
        training: usize,
        /// Its held-out samples.
        held_out: usize,
        /// The least each part needs.
        min: usize,
    },
    /// A cross-validation fit that failed, with its weight and fold.
    #[error("choosing the weight: the fit at weight {weight:e} on fold {fold} failed: {source}")]
    Fold {
        /// The weight.
        weight: f64,
        /// The fold (0-based).
        fold: usize,
        /// What failed.
        #[source]
        source: Box<IdentifyError>,
    },
    /// A body whose constraint set is empty.
    #[error("the constraint set of body '{body}' is infeasible")]
    InfeasibleBody {
        /// The body.
        body: String,
    },
    /// What is not supported (yet).
    #[error("not supported: {what}")]
    Unsupported {
        /// What.
        what: &'static str,
    },
    /// The solver ended without a solution.
    #[error("the solver ended with status {0}")]
    Solver(Status),
    /// The conic layer failed.
    #[error(transparent)]
    Conic(#[from] crate::conic::ConicError),
    /// Data problems.
    #[error(transparent)]
    Data(#[from] crate::data::DataError),
    /// Model problems.
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
}

/// What is wrong with a Gram matrix given as reduced data.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum GramProblem {
    /// Not square, or smaller than 2 × 2.
    #[error("a square matrix of side ≥ 2 is needed, got {rows}×{cols}")]
    Shape {
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// No samples.
    #[error("no samples")]
    NoSamples,
    /// An entry that is not finite.
    #[error("entry ({0}, {1}) is not finite")]
    NotFinite(usize, usize),
    /// Not symmetric.
    #[error("not symmetric at ({0}, {1})")]
    NotSymmetric(usize, usize),
}

/// The error for a name that is not one of `valid`.
pub(crate) fn unknown<'a>(
    what: &'static str,
    name: &str,
    valid: impl Iterator<Item = &'a str>,
) -> IdentifyError {
    IdentifyError::UnknownName {
        what,
        name: name.to_string(),
        valid: valid.collect::<Vec<_>>().join(", "),
    }
}
