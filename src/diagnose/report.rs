//! The diagnosis' report: where the gap lies ([`JointWhere`] per joint),
//! each candidate's evaluation per round ([`EffectReport`]), how far the
//! accepted effects close it, and the held-out signals for plots.

use super::warning::DiagnoseWarning;
use super::where_::JointWhere;
use serde::Serialize;
use std::collections::BTreeMap;

/// One candidate's evaluation in one round.
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
    /// Joints whose held-out RMS it reduces by more than 1 %.
    pub joints: Vec<String>,
    /// Number of fitted parameters.
    pub params: usize,
    /// Held-out RMS per joint before (current model) (N·m).
    pub heldout_rms_before: Vec<f64>,
    /// Held-out RMS per joint with the effect added (N·m).
    pub heldout_rms_after: Vec<f64>,
    /// ΔBIC on the training part (negative: better).
    pub delta_bic: f64,
    /// Block-test z score of the held-out improvement.
    pub z: f64,
    /// Accepted into the model.
    pub accepted: bool,
    /// Candidates that explain the same within noise.
    pub tied_with: Vec<String>,
    /// Effects whose hypotheses span the same columns as this one's on
    /// these data (an offset and direction-dependent friction where the
    /// joints never stand still): one hypothesis, offered once under this
    /// name.
    pub same_as: Vec<String>,
    /// Why its fitted parameters are physically doubtful, if they are: a
    /// nonlinear parameter at the edge of its grid, an encoder offset beyond
    /// 0.2 rad. An accepted effect with a flag is also a warning.
    pub implausible: Option<String>,
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
    /// Held-out RMS per joint of the nominal model (N·m).
    pub heldout_rms_nominal: Vec<f64>,
    /// Held-out RMS per joint after the accepted effects (N·m).
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
