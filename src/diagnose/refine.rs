//! The final model made consistent with how `predict` uses it. The
//! selection fits every effect's columns built on the nominal model (a gain
//! error's column is the nominal torque, a delay's its shift); `predict`
//! builds them on the model it is given — the nominal with its friction law
//! refit and the effects added. Where those differ (a Stribeck term added
//! changes the torque a delay shifts), the coefficients are refined by
//! Gauss–Newton on the residual `predict` leaves on the fitting part: each
//! pass builds every column again on the current model and refits the
//! changes, with every constraint kept at the current point.

use super::candidate::Candidate;
use super::error::DiagnoseError;
use super::folds::Folds;
use super::forward::Accepted;
use super::law::Law;
use super::model_out::{ModelOut, model_out};
use super::refit::{Group, fit, moved_bodies};
use super::store::Store;
use crate::data::Dataset;
use crate::dynamics::params_file::FittedEffect;
use crate::dynamics::{Friction, Model};
use crate::effects::fitted::predict_with;
use crate::effects::{Context, Library};

/// Gauss–Newton passes of the refinement.
pub const PASSES: usize = 3;

/// What the refinement works on.
pub struct Refine<'a> {
    /// The data.
    pub data: &'a Dataset,
    /// The folds (the first `fit` are the fitting part).
    pub folds: &'a Folds,
    /// The nominal model, friction and fitted effects.
    pub nominal: (&'a Model, &'a Friction, &'a [FittedEffect]),
    /// The nominal law.
    pub law: &'a Law,
    /// The accepted effects.
    pub accepted: &'a [Accepted],
    /// The candidates.
    pub candidates: &'a [Candidate],
    /// The columns the selection used (the bodies' regressor columns are
    /// taken from it).
    pub store: &'a Store,
    /// The effects' library.
    pub library: &'a Library,
}

impl Refine<'_> {
    /// The model of `beta` (the law's changes, then each accepted group's
    /// coefficients) refined; the model and its coefficients, and why the
    /// refinement stopped early if it did (a step's fit failed: the
    /// coefficients before it are kept).
    pub fn refine(
        &self,
        mut beta: Vec<f64>,
    ) -> Result<(ModelOut, Vec<f64>, Option<String>), DiagnoseError> {
        for pass in 0..PASSES {
            let out = self.model(&beta)?;
            let Some((store, groups)) = self.linearised(&out, &beta)? else {
                let why = "a term of the nominal law has no column on the refit model";
                return Ok((
                    out,
                    beta,
                    Some(format!("pass {} of {PASSES}: {why}", pass + 1)),
                ));
            };
            let refs: Vec<&Group> = groups.iter().collect();
            let on: Vec<bool> = (0..self.folds.len()).map(|k| k < self.folds.fit).collect();
            match fit(&store, &refs, &on, &vec![true; refs.len()]) {
                Ok(step) => beta.iter_mut().zip(&step.beta).for_each(|(b, d)| *b += d),
                Err(e) => {
                    return Ok((
                        out,
                        beta,
                        Some(format!("pass {} of {PASSES}: {e}", pass + 1)),
                    ));
                }
            }
        }
        Ok((self.model(&beta)?, beta, None))
    }

    fn model(&self, beta: &[f64]) -> Result<ModelOut, DiagnoseError> {
        model_out(self.nominal, self.law, self.accepted, self.candidates, beta)
            .map_err(DiagnoseError::Predict)
    }

    /// The residual `predict` leaves with `out`, and the groups of columns
    /// of a step from `beta`: built again on `out`, their constraints at
    /// the current point.
    fn linearised(
        &self,
        out: &ModelOut,
        beta: &[f64],
    ) -> Result<Option<(Store, Vec<Group>)>, DiagnoseError> {
        let (d, n) = (self.data, out.model.dof());
        let pred = predict_with(&out.model, &out.friction, &out.effects, d, self.library)
            .map_err(DiagnoseError::Effects)?;
        let r: Vec<f64> = (d.tau.iter().flatten().zip(pred.iter().flatten()))
            .map(|(a, b)| a - b)
            .collect();
        let mut store = Store::new(r, n, self.folds);
        let law =
            Law::new(&out.model, &out.friction, d, &mut store).map_err(DiagnoseError::Predict)?;
        let k = self.law.group.ids.len();
        let Some(law_group) = self.law_group(&law, &out.friction, &beta[..k], &mut store) else {
            return Ok(None);
        };
        let mut groups = vec![law_group];
        let zeros = vec![0.0; d.len() * n];
        let cx = Context::new(
            &out.model,
            &out.friction,
            d,
            &zeros,
            self.folds.first_heldout(),
        );
        let mut at = k;
        for a in self.accepted {
            let len = a.group.ids.len();
            groups.push(self.group(a, &beta[at..at + len], &cx, &mut store)?);
            at += len;
        }
        Ok(Some((store, groups)))
    }

    /// The law's columns for the nominal law's terms (`law` is built on the
    /// current model, whose law may have more terms), bounded at the
    /// current coefficients; with the bodies refit with the law, their
    /// columns (which do not change), their constraints at the current
    /// point and the nominal's own rows at the current change. `None` when
    /// a term of the nominal law has no column on the current model.
    fn law_group(
        &self,
        law: &Law,
        friction: &Friction,
        delta: &[f64],
        store: &mut Store,
    ) -> Option<Group> {
        let mut group = self.friction_group(law, friction, delta)?;
        let body_ids = &self.law.group.ids[self.law.labels.len()..];
        if let (Some(prior), false) = (self.store.prior(), body_ids.is_empty()) {
            let ids: Vec<usize> = (body_ids.iter())
                .map(|&id| store.add_in(self.store.col(id).values.clone(), None))
                .collect();
            let change = self.law.body_delta(delta);
            group.push_bodies(&ids, moved_bodies(&self.law.group.bodies, change));
            store.set_prior(prior.at(ids, change));
        }
        group.applied = Some(delta.to_vec());
        Some(group)
    }

    /// The law's friction columns for the nominal law's terms, bounded at
    /// the current coefficients (`None`: a term has no column there).
    fn friction_group(&self, law: &Law, friction: &Friction, delta: &[f64]) -> Option<Group> {
        let ids = (self.law.labels.iter())
            .map(|l| {
                law.labels
                    .iter()
                    .position(|m| m == l)
                    .map(|p| law.group.ids[p])
            })
            .collect::<Option<Vec<usize>>>()?;
        let lower = (self.law.labels.iter())
            .map(|(t, i)| match t.signed() {
                true => f64::NEG_INFINITY,
                false => -friction.coefficients(*t).get(*i).copied().unwrap_or(0.0),
            })
            .collect();
        Some(Group {
            ids,
            lower: Some(lower),
            applied: Some(delta[..self.law.labels.len().min(delta.len())].to_vec()),
            ..Group::default()
        })
    }

    /// An accepted effect's columns for a step from its coefficients `b`:
    /// a body correction's regressor columns (they do not change), any other
    /// effect's columns built again on the current model.
    fn group(
        &self,
        a: &Accepted,
        b: &[f64],
        cx: &Context,
        store: &mut Store,
    ) -> Result<Group, DiagnoseError> {
        let c = &self.candidates[a.candidate];
        let v = &c.variants[a.variant];
        let at: Vec<usize> = (a.group.ids.iter())
            .map(|id| v.group.ids.iter().position(|x| x == id).unwrap_or(0))
            .collect();
        let cols: Vec<Vec<f64>> = match v.columns.into_bodies.is_empty() {
            false => a
                .group
                .ids
                .iter()
                .map(|&id| self.store.col(id).values.clone())
                .collect(),
            true => {
                let mut replayed = c
                    .effect
                    .replay(cx, &v.columns.key)
                    .map_err(DiagnoseError::Effects)?;
                at.iter()
                    .map(|&p| std::mem::take(&mut replayed.cols[p]))
                    .collect()
            }
        };
        let ids = (cols.into_iter().zip(&at))
            .map(|(col, &p)| store.add_in(col, v.col_joints[p]))
            .collect();
        // the bodies' constraints at the current point: J(π + b + Δ) ⪰ 0
        Ok(Group {
            ids,
            bodies: moved_bodies(&a.group.bodies, b),
            nonneg: false,
            lower: a.group.nonneg.then(|| b.iter().map(|x| -x).collect()),
            applied: Some(b.to_vec()),
            ..Group::default()
        })
    }
}
