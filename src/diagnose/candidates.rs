//! The library of candidate effects, each a group of extra regressor columns
//! built from the data and the nominal model's prediction τ̂.

use super::error::DiagnoseError;
use crate::data::Dataset;
use crate::dynamics::params_file::Friction;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Data, Effect, Model, regressor, sign};
use crate::moments::InertialParams;
use nalgebra::Matrix3;
use serde::Serialize;
use std::borrow::Cow;
use std::ops::Range;
use std::sync::OnceLock;

/// A hypothesis the diagnoser tries: an effect of the shared vocabulary
/// ([`Effect`]), or a refit of the link inertias.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Candidate {
    /// An effect the nominal model lacks.
    Effect(Effect),
    /// The link inertias are off (a correction of every link's 10 parameters).
    LinkInertia,
}

impl Candidate {
    /// Every candidate, in the order they are tried.
    pub const ALL: [Candidate; 14] = [
        Candidate::Effect(Effect::Coulomb),
        Candidate::Effect(Effect::Viscous),
        Candidate::Effect(Effect::Stribeck),
        Candidate::Effect(Effect::AsymmetricFriction),
        Candidate::Effect(Effect::Offset),
        Candidate::Effect(Effect::RotorInertia),
        Candidate::LinkInertia,
        Candidate::Effect(Effect::Payload),
        Candidate::Effect(Effect::TimeDelay),
        Candidate::Effect(Effect::Cogging),
        Candidate::Effect(Effect::TorqueGain),
        Candidate::Effect(Effect::Elasticity),
        Candidate::Effect(Effect::Backlash),
        Candidate::Effect(Effect::JointOffset),
    ];

    /// The name in reports (an effect's name, or `link_inertia`).
    pub fn name(self) -> &'static str {
        match self {
            Candidate::Effect(e) => e.name(),
            Candidate::LinkInertia => "link_inertia",
        }
    }

    /// Why it cannot apply to `model`, if it cannot: cogging ("per motor
    /// turn") and the transmission's compliance (between a motor side that
    /// the encoders measure and the links) need a rotor on some joint; a
    /// robot without rotors measures its links directly, and there the
    /// rigid link dynamics hold whatever the transmission does.
    pub fn inapplicable(self, model: &Model) -> Option<&'static str> {
        let needs_rotor = matches!(
            self,
            Candidate::Effect(Effect::Cogging | Effect::Elasticity | Effect::Backlash)
        );
        let has_rotor = (0..model.dof()).any(|j| model.rotor_of(j).is_some());
        (needs_rotor && !has_rotor).then_some(
            "not proposed: the model has no rotors, so no motor side whose turns or compliance the data could show",
        )
    }

    /// Whether it is a compliance hypothesis (fitted by simulation,
    /// [`super::compliance`]).
    pub fn is_compliance(self) -> bool {
        matches!(self, Candidate::Effect(e) if e.is_compliance())
    }
}

/// Columns of one candidate: `cols[c][k·n + i]` for sample k, joint i.
pub struct Columns {
    /// The candidate.
    pub candidate: Candidate,
    /// Description of the chosen nonlinear parameter, if any.
    pub detail: String,
    /// Column-major: one Vec per column, rows = samples × joints.
    pub cols: Vec<Vec<f64>>,
    /// Inertial correction: the nominal parameters of the corrected bodies
    /// (10 columns each, in order); the fit keeps `J(π + β) ⪰ 0` for each.
    pub bodies: Vec<[f64; 10]>,
    /// The coefficients must be ≥ 0 (a payload mass).
    pub nonneg: bool,
    /// Nonlinear parameters chosen by search before the linear fit (a delay,
    /// a Stribeck velocity, a stiffness per joint, …); they count in ΔBIC.
    pub nonlinear: usize,
    /// Why the nonlinear parameters found are physically doubtful, if they
    /// are (set where they are fitted).
    pub doubt: Option<String>,
    /// `XᵀX` of `cols` over the rows it was first asked for ([`Self::gram`]).
    pub(super) gram: OnceLock<(Range<usize>, Vec<f64>)>,
}

impl Columns {
    /// Plain linear columns (no nonlinear parameter, no constraint).
    fn linear(candidate: Candidate, cols: Vec<Vec<f64>>) -> Self {
        Self::variant(candidate, String::new(), cols, 0)
    }

    /// One variant of a nonlinear parameter's grid.
    fn variant(
        candidate: Candidate,
        detail: String,
        cols: Vec<Vec<f64>>,
        nonlinear: usize,
    ) -> Self {
        Self {
            candidate,
            detail,
            cols,
            bodies: vec![],
            nonneg: false,
            nonlinear,
            doubt: None,
            gram: OnceLock::new(),
        }
    }

    /// The candidate's name.
    pub fn name(&self) -> &'static str {
        self.candidate.name()
    }

    /// `XᵀX` of the columns over `rows` (k × k, row-major): kept from the
    /// first call (the selection fits every round on the training rows,
    /// only the residual changes), computed afresh for other rows.
    pub(super) fn gram(&self, rows: &Range<usize>) -> Cow<'_, [f64]> {
        let (at, g) = self
            .gram
            .get_or_init(|| (rows.clone(), gram_of(&self.cols, rows)));
        if at == rows {
            Cow::Borrowed(g)
        } else {
            Cow::Owned(gram_of(&self.cols, rows))
        }
    }

    /// Computes and keeps [`Self::gram`] over `rows`.
    pub(super) fn warm_gram(&self, rows: &Range<usize>) {
        self.gram(rows);
    }
}

/// `XᵀX` of `cols` over `rows`, row-major.
fn gram_of(cols: &[Vec<f64>], rows: &Range<usize>) -> Vec<f64> {
    let k = cols.len();
    let mut g = vec![0.0; k * k];
    for a in 0..k {
        for c in a..k {
            let v: f64 = rows.clone().map(|i| cols[a][i] * cols[c][i]).sum();
            g[a * k + c] = v;
            g[c * k + a] = v;
        }
    }
    g
}

fn zeros(rows: usize) -> Vec<f64> {
    vec![0.0; rows]
}

/// Per-joint columns from a per-sample scalar function of joint i.
fn per_joint(d: &Dataset, f: impl Fn(usize, usize) -> f64) -> Vec<Vec<f64>> {
    let n = d.joints.len();
    (0..n)
        .map(|i| {
            let mut c = zeros(d.len() * n);
            for k in 0..d.len() {
                c[k * n + i] = f(k, i);
            }
            c
        })
        .collect()
}

/// The nominal prediction τ̂ flattened (sample-major).
pub fn flat(v: &[Vec<f64>]) -> Vec<f64> {
    v.iter().flatten().copied().collect()
}

/// Builds the columns of a candidate (nonlinear parameters on a grid are
/// returned as separate variants; the caller picks the best on training
/// data). The compliance hypotheses are fitted by simulation instead
/// ([`super::compliance`]) and have no columns here.
pub fn build(
    candidate: Candidate,
    model: &Model,
    friction: &Friction,
    d: &Dataset,
) -> Result<Vec<Columns>, DiagnoseError> {
    let one = |cols| Ok(vec![Columns::linear(candidate, cols)]);
    let tau_hat =
        || predict_torques(model, friction, &d.q, &d.qd, &d.qdd).map_err(DiagnoseError::Predict);
    match candidate {
        Candidate::Effect(e) => match e {
            Effect::Coulomb => one(per_joint(d, |k, i| sign(d.qd[k][i]))),
            Effect::Viscous => one(per_joint(d, |k, i| d.qd[k][i])),
            Effect::Offset => one(per_joint(d, |_, _| 1.0)),
            Effect::AsymmetricFriction => one(per_joint(d, |k, i| sign(d.qd[k][i]).abs())),
            Effect::Stribeck => Ok(stribeck(d)),
            Effect::Cogging => Ok(cogging(model, d)),
            Effect::TorqueGain => one(vec![flat(&tau_hat()?)]),
            Effect::TimeDelay => Ok(time_delay(d, &tau_hat()?)),
            Effect::RotorInertia | Effect::Payload => inertial(candidate, model, d),
            Effect::Elasticity | Effect::Backlash => Ok(vec![]),
            Effect::JointOffset => one(joint_offset(model, friction, d)?),
        },
        Candidate::LinkInertia => inertial(candidate, model, d),
    }
}

/// Per joint j, `∂τ̂/∂q_j` by a central difference (h = 10⁻⁴ rad or m):
/// the torque change an encoder zero offset δ_j makes, to first order.
fn joint_offset(
    model: &Model,
    friction: &Friction,
    d: &Dataset,
) -> Result<Vec<Vec<f64>>, DiagnoseError> {
    const H: f64 = 1e-4;
    let n = d.joints.len();
    (0..n)
        .map(|j| {
            let at = |s: f64| -> Vec<Vec<f64>> {
                d.q.iter()
                    .map(|q| {
                        let mut q = q.clone();
                        q[j] += s;
                        q
                    })
                    .collect()
            };
            let plus = predict_torques(model, friction, &at(H), &d.qd, &d.qdd)
                .map_err(DiagnoseError::Predict)?;
            let minus = predict_torques(model, friction, &at(-H), &d.qd, &d.qdd)
                .map_err(DiagnoseError::Predict)?;
            Ok(flat(&plus)
                .iter()
                .zip(flat(&minus))
                .map(|(a, b)| (a - b) / (2.0 * H))
                .collect())
        })
        .collect()
}

fn stribeck(d: &Dataset) -> Vec<Columns> {
    [0.05, 0.1, 0.2, 0.5]
        .iter()
        .map(|&vs| {
            Columns::variant(
                Candidate::Effect(Effect::Stribeck),
                format!("Stribeck velocity {vs} rad/s"),
                per_joint(d, |k, i| {
                    (-(d.qd[k][i] / vs).powi(2)).exp() * sign(d.qd[k][i])
                }),
                1,
            )
        })
        .collect()
}

fn cogging(model: &Model, d: &Dataset) -> Vec<Columns> {
    let gear: Vec<f64> = (0..d.joints.len())
        .map(|i| model.rotor_of(i).map_or(1.0, |r| r.gear_ratio))
        .collect();
    (1..=12)
        .map(|p| {
            let p = p as f64;
            let mut cols = per_joint(d, |k, i| (p * gear[i] * d.q[k][i]).sin());
            cols.extend(per_joint(d, |k, i| (p * gear[i] * d.q[k][i]).cos()));
            Columns::variant(
                Candidate::Effect(Effect::Cogging),
                format!("period {p} per motor turn"),
                cols,
                1,
            )
        })
        .collect()
}

/// `τ̂(t − s·dt) − τ̂(t)` for a grid of shifts s.
fn time_delay(d: &Dataset, th: &[Vec<f64>]) -> Vec<Columns> {
    let n = d.joints.len();
    let dt = if d.len() > 1 {
        (d.t[d.len() - 1] - d.t[0]) / (d.len() - 1) as f64
    } else {
        1e-3
    };
    [1usize, 2, 3, 5, 8, 12, 20, 30]
        .iter()
        .map(|&s| {
            let mut c = zeros(d.len() * n);
            for k in 0..d.len() {
                let j = k.saturating_sub(s);
                for i in 0..n {
                    c[k * n + i] = th[j][i] - th[k][i];
                }
            }
            Columns::variant(
                Candidate::Effect(Effect::TimeDelay),
                format!("delay {:.0} ms", 1e3 * s as f64 * dt),
                vec![c],
                1,
            )
        })
        .collect()
}

/// Inertial corrections as regressor columns: every link's 10 parameters,
/// every rotor's, or a point mass at the model's tool point (none for a
/// model without rotors).
fn inertial(
    candidate: Candidate,
    model: &Model,
    d: &Dataset,
) -> Result<Vec<Columns>, DiagnoseError> {
    let n = d.joints.len();
    let rows = d.len() * n;
    let nl = 10 * model.dof();
    let nb = model.num_bodies();
    let payload = candidate == Candidate::Effect(Effect::Payload);
    let (lo, hi) = match candidate {
        Candidate::LinkInertia => (0, nl),
        Candidate::Effect(Effect::RotorInertia) => (nl, 10 * nb),
        _ => (0, 0),
    };
    let tool = model.tool.ok_or(DiagnoseError::NoTool)?;
    let unit = InertialParams::from_mass_com_inertia(1.0, tool.point, Matrix3::zeros());
    let mut cols: Vec<Vec<f64>> = vec![zeros(rows); if payload { 1 } else { hi - lo }];
    if cols.is_empty() {
        return Ok(vec![]);
    }
    let mut data = Data::new(model);
    for k in 0..d.len() {
        let y = regressor(model, &mut data, &d.q[k], &d.qd[k], &d.qdd[k])
            .map_err(|source| DiagnoseError::Regressor { sample: k, source })?;
        for i in 0..n {
            if payload {
                cols[0][k * n + i] = (0..10)
                    .map(|c| y[(i, 10 * tool.body + c)] * unit.0[c])
                    .sum();
            } else {
                for (c, col) in cols.iter_mut().enumerate() {
                    col[k * n + i] = y[(i, lo + c)];
                }
            }
        }
    }
    let p = model.params();
    Ok(vec![Columns {
        candidate,
        detail: String::new(),
        cols,
        bodies: (lo / 10..hi / 10)
            .map(|b| std::array::from_fn(|k| p[10 * b + k]))
            .collect(),
        nonneg: payload,
        nonlinear: 0,
        doubt: None,
        gram: OnceLock::new(),
    }])
}
