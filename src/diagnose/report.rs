//! The diagnosis' report: where the gap lies ([`JointWhere`] per joint),
//! each candidate's evaluation per round ([`EffectReport`]), how far the
//! accepted effects close it, and the held-out signals for plots.

use super::warning::DiagnoseWarning;
use super::where_::JointWhere;
use serde::Serialize;
use std::collections::BTreeMap;

/// One candidate's evaluation in one round. Its three held-out errors are
/// cross-validated (each fold predicted by the fit on the others): the
/// nominal model as given, the current model refit (the friction law and
/// the effects accepted before this round) without the candidate, and
/// with it — so that the effect's own share is the last two's difference.
#[derive(Clone, Debug, Serialize)]
pub struct EffectReport {
    /// Effect name.
    pub effect: String,
    /// The chosen nonlinear parameter, or what the effect reports of its
    /// fit ([`crate::effects::Effect::detail`]; for `joint_offset`, the
    /// offsets fitted).
    pub detail: String,
    /// Fitted values an effect reports under their own key, in the JSON at
    /// the top level of this report ([`crate::effects::Effect::fitted`]):
    /// `joint_offsets`, the encoder zero offset δ_j per joint (rad, or m
    /// for a prismatic joint; true q = measured q + δ).
    #[serde(flatten)]
    pub fitted: BTreeMap<String, Vec<f64>>,
    /// Selection round (1-based).
    pub round: usize,
    /// Joints it is kept on (a per-joint hypothesis: those where it passes
    /// on its own; else every joint).
    pub joints: Vec<String>,
    /// Number of fitted parameters (columns kept and nonlinear ones).
    pub params: usize,
    /// Cross-validated held-out RMS per joint of the nominal model as
    /// given (N·m).
    pub heldout_rms_nominal: Vec<f64>,
    /// The same of the current model refit without the candidate (N·m).
    pub heldout_rms_before: Vec<f64>,
    /// The same with the candidate refit with it (N·m).
    pub heldout_rms_after: Vec<f64>,
    /// Per fold, the held-out mean-square gain on its joints ((N·m)²).
    pub fold_gains: Vec<f64>,
    /// Block-bootstrap z of the gain.
    pub z: f64,
    /// Accepted into the model.
    pub accepted: bool,
    /// Why it is accepted ([`super::rule`]), or the first clause it fails.
    pub rule: String,
    /// Candidates that explain the data as well on this motion (their
    /// held-out gains within noise): indistinguishable here.
    pub tied_with: Vec<String>,
    /// For each tied candidate: where the two differ and the motion that
    /// would tell them apart (said once, on the accepted effect).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ties: Vec<Tie>,
    /// Effects whose hypotheses span the same columns as this one's on
    /// these data (an offset and direction-dependent friction where the
    /// joints never stand still): one hypothesis, offered once under this
    /// name.
    pub same_as: Vec<String>,
    /// Why its fitted parameters are physically doubtful, if they are: a
    /// nonlinear parameter at the edge of its grid, an encoder offset beyond
    /// 0.2 rad. An accepted effect with a flag is also a warning.
    pub implausible: Option<String>,
    /// Its sizes ([`crate::effects::Effect::sizes`]): an accepted effect's
    /// fitted on the fitting part with 95 % intervals; another's fitted on
    /// all the data with the current model, without an interval (`low` =
    /// `high`): what it would be, had it been accepted.
    pub sizes: Vec<SizeReport>,
    /// An effect accepted in its round and removed in a later one, when
    /// the effects accepted after it explain what it did: why.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub removed: Option<String>,
}

/// Two candidates indistinguishable on this motion: what would separate
/// them.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Tie {
    /// The candidate tied with the accepted effect.
    pub effect: String,
    /// The joints where their held-out predictions differ most (RMS of the
    /// difference at least half its largest over the joints), largest
    /// first.
    pub joints: Vec<String>,
    /// Per joint, the RMS of the difference of their held-out predictions
    /// (N·m): how far apart this motion puts them.
    pub difference_rms: Vec<f64>,
    /// The kind of motion that shows each most
    /// ([`crate::effects::Effect::motion`]): the accepted effect's, then
    /// the tied one's.
    pub motions: [String; 2],
}

impl Tie {
    /// The tie in words.
    pub fn words(&self, accepted: &str) -> String {
        format!(
            "{accepted} and {} are indistinguishable on this motion; they differ most on {}; {accepted} shows under {}, {} under {}",
            self.effect,
            self.joints.join(", "),
            self.motions[0],
            self.effect,
            self.motions[1]
        )
    }
}

/// A fitted size with its 95 % interval (a delete-one-block jackknife over
/// the fitting part: correlated residuals stay inside a block).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SizeReport {
    /// What it is (`"gain error, lwr_1_joint"`).
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// The value.
    pub value: f64,
    /// The interval's lower end.
    pub low: f64,
    /// The interval's upper end.
    pub high: f64,
}

impl SizeReport {
    /// `value ± half-width unit`, in words.
    pub fn words(&self) -> String {
        let half = 0.5 * (self.high - self.low);
        format!(
            "{}: {} ± {} {}",
            self.name,
            sig(self.value),
            sig(half),
            self.unit
        )
    }
}

/// Three significant digits.
fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (2 - x.abs().log10().floor() as i32).clamp(0, 9) as usize;
    format!("{x:.digits$}")
}

/// A coefficient of the nominal friction law that the data move: holding
/// it at its nominal value makes every fold worse by the rule's amount on
/// its joint.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Reestimate {
    /// The friction term (`viscous`, `coulomb`, …).
    pub term: String,
    /// The joint.
    pub joint: String,
    /// The nominal coefficient.
    pub nominal: f64,
    /// The refit coefficient, with its 95 % interval.
    pub refit: SizeReport,
    /// Why it counts as moved.
    pub rule: String,
}

/// The diagnosis.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnosis {
    /// Joint names.
    pub joints: Vec<String>,
    /// Where the gap lies (held-out residual of the nominal model).
    #[serde(rename = "where")]
    pub where_: Vec<JointWhere>,
    /// One line per joint.
    pub summary: Vec<String>,
    /// Candidates per round, best first.
    pub ranked_effects: Vec<EffectReport>,
    /// Accepted effects in order.
    pub accepted: Vec<String>,
    /// The folds of the cross-validation, in words (`"5 blocks of time"`).
    pub folds: String,
    /// The nominal friction law's coefficients the data move.
    pub reestimated: Vec<Reestimate>,
    /// Every coefficient of the nominal friction law refit on the fitting
    /// part (with the accepted effects), with its 95 % interval.
    pub friction_refit: Vec<SizeReport>,
    /// Held-out RMS per joint of the nominal model as given, on the
    /// held-out part (the last file, or the last blocks of time) (N·m).
    pub heldout_rms_nominal: Vec<f64>,
    /// The same with the nominal friction law refit on the fitting part
    /// (and, with the nominal's own data given, its bodies) (N·m).
    pub heldout_rms_refit: Vec<f64>,
    /// The same with the law and the accepted effects refit on the fitting
    /// part: the model `--model-out` writes (N·m).
    pub heldout_rms_final: Vec<f64>,
    /// Noise floor per joint (N·m).
    pub noise_floor: Vec<f64>,
    /// Where the noise floor came from.
    pub noise_floor_source: super::FloorSource,
    /// Share of the gap above the noise floor closed, per joint.
    pub gap_closed: Vec<f64>,
    /// A remainder above the noise floor is left that no candidate explains.
    pub unexplained: bool,
    /// Where the unexplained remainder lies.
    pub unexplained_where: Vec<String>,
    /// Candidates left out or skipped and why (a failed fit, a compliance
    /// hypothesis that did not simulate), and accepted effects whose fit is
    /// doubtful.
    #[serde(serialize_with = "crate::warning::with_messages")]
    pub warnings: Vec<DiagnoseWarning>,
    /// Held-out signals and residuals for plots (not serialised).
    #[serde(skip)]
    pub heldout: HeldOut,
    /// The diagnosis' model: the nominal with its friction law refit and
    /// the accepted effects, fitted on the fitting part
    /// ([`Self::heldout_rms_final`] is its held-out error): what
    /// `--model-out` writes.
    pub model: crate::dynamics::params_file::ParamsFile,
}

impl Diagnosis {
    /// The first report of `effect` in [`Self::ranked_effects`] (listed by
    /// round: its report of round 1), if it was evaluated.
    pub fn effect(&self, effect: &str) -> Option<&EffectReport> {
        self.ranked_effects.iter().find(|e| e.effect == effect)
    }
}

impl EffectReport {
    /// The fitted values the effect reports under `key` (`joint_offsets`).
    pub fn fitted(&self, key: &str) -> Option<&[f64]> {
        self.fitted.get(key).map(Vec::as_slice)
    }

    /// The effect's name with the effects that are the same hypothesis on
    /// these data: `offset ≡ asymmetric_friction`.
    pub fn label(&self) -> String {
        std::iter::once(self.effect.as_str())
            .chain(self.same_as.iter().map(String::as_str))
            .collect::<Vec<_>>()
            .join(" ≡ ")
    }

    /// ` (tied with a, b)`, or nothing without ties.
    pub fn ties(&self) -> String {
        if self.tied_with.is_empty() {
            String::new()
        } else {
            format!(" (tied with {})", self.tied_with.join(", "))
        }
    }

    /// Whether `effect` is this one, one of the same hypothesis or tied
    /// with it.
    pub fn covers(&self, effect: &str) -> bool {
        self.effect == effect
            || self.same_as.iter().any(|a| a == effect)
            || self.tied_with.iter().any(|t| t == effect)
    }
}

/// The held-out part's signals and residuals, per joint (for plots).
#[derive(Clone, Debug, Default)]
pub struct HeldOut {
    /// Time (s).
    pub t: Vec<f64>,
    /// Positions per joint.
    pub q: Vec<Vec<f64>>,
    /// Velocities per joint.
    pub qd: Vec<Vec<f64>>,
    /// Residual of the nominal model per joint.
    pub nominal: Vec<Vec<f64>>,
    /// Residual after the accepted effects per joint.
    pub after: Vec<Vec<f64>>,
}
