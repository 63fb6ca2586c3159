//! The diagnosis' model: the nominal model with the friction law refit and
//! the accepted effects added where a model file holds them — an inertial
//! correction or a payload in its bodies, a friction term in the law, any
//! other effect as a fitted effect ([`FittedEffect`]) — so that `predict`,
//! `identify --prior` and `export` take it, and `predict` with it gives the
//! held-out error the diagnosis reports.

use super::candidate::Candidate;
use super::forward::{Accepted, full_beta};
use super::law::Law;
use crate::dynamics::params_file::{FittedEffect, ParamsFile};
use crate::dynamics::{DynamicsError, Friction, FrictionTerm, Model};
use crate::effects::fitted::record;

/// The final model's parts.
pub struct ModelOut {
    /// The nominal model with the bodies corrected.
    pub model: Model,
    /// The friction law refit, with accepted friction terms.
    pub friction: Friction,
    /// The nominal's fitted effects and the accepted ones no body or law
    /// term holds.
    pub effects: Vec<FittedEffect>,
}

impl ModelOut {
    /// The parameter file.
    pub fn file(&self) -> ParamsFile {
        ParamsFile {
            effects: self.effects.clone(),
            ..ParamsFile::from_model(&self.model, self.friction.clone())
        }
    }
}

/// The model of the final fit's coefficients `beta` (the law's, then each
/// accepted group's) on the nominal `model` + `friction` + `effects`.
pub fn model_out(
    (model, friction, effects): (&Model, &Friction, &[FittedEffect]),
    law: &Law,
    accepted: &[Accepted],
    candidates: &[Candidate],
    beta: &[f64],
) -> Result<ModelOut, DynamicsError> {
    let k = law.group.ids.len();
    let mut out = ModelOut {
        model: model.clone(),
        friction: law.friction(friction, &beta[..k]),
        effects: effects.to_vec(),
    };
    let mut params = model.params();
    let joints: Vec<String> = model.joint_names().iter().map(|s| s.to_string()).collect();
    let mut at = k;
    for a in accepted {
        let c = &candidates[a.candidate];
        let v = &c.variants[a.variant];
        let len = a.group.ids.len();
        let b = full_beta(v, &a.group, &beta[at..at + len]);
        at += len;
        if !v.columns.into_bodies.is_empty() {
            for (block, &body) in v.columns.into_bodies.iter().enumerate() {
                (0..10).for_each(|q| params[10 * body + q] += b[10 * block + q]);
            }
        } else if let Some(term) = c.effect.law_term() {
            add_term(
                &mut out.friction,
                term,
                &v.col_joints,
                &b,
                v.columns.key_value("stribeck_velocity"),
            );
        } else {
            out.effects.push(record(
                c.effect.as_ref(),
                &v.columns,
                &v.col_joints,
                &b,
                &joints,
            ));
        }
    }
    out.model.set_params(&params)?;
    Ok(out)
}

/// Adds the coefficients `b` of a friction term's columns (one joint each)
/// to `f`; a Stribeck term brings its velocity.
fn add_term(
    f: &mut Friction,
    term: FrictionTerm,
    joints: &[Option<usize>],
    b: &[f64],
    vs: Option<f64>,
) {
    let n = f.viscous.len();
    let c = f.coefficients_mut(term);
    c.resize(n, 0.0);
    for (j, x) in joints.iter().zip(b) {
        if let Some(j) = j {
            c[*j] += x;
            // a coefficient bounded at 0 that the conic solver leaves a
            // hair below it (its tolerance): 0, as a friction law requires
            if !term.signed() && c[*j] < 0.0 && c[*j] > -super::law::SOLVER_HAIR {
                c[*j] = 0.0;
            }
        }
    }
    if term == FrictionTerm::Stribeck
        && let Some(vs) = vs
    {
        f.stribeck_velocity = Some(vs);
    }
}
