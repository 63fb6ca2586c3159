//! The nominal model's friction law, refit on the diagnosed data: the
//! baseline every candidate is measured against. Friction changes from run
//! to run (the drives warm, the lubricant thins, a faster motion reaches
//! another part of the friction curve), so the coefficients of the terms
//! the nominal model has are free in every fit; its inertias, which do not
//! change between runs, are held, and a change there is a finding
//! (`payload`, `link_inertia`, `rotor_inertia`) — unless the data the
//! nominal was identified on are given: then its bodies are refit with the
//! law on those data and the fitting part ([`Law::with_bodies`],
//! `super::nominal_data`), kept consistent (`J ⪰ 0`) in the final fit. A
//! friction term the law lacks is a candidate like any other effect.

use super::refit::Group;
use super::store::{Prior, Store};
use crate::data::Dataset;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{DynamicsError, Friction, FrictionTerm, Model};

/// How far below its bound of 0 a fitted friction coefficient may come
/// out of the conic solver and still be that bound (N·m, N·m·s/rad or 1).
pub const SOLVER_HAIR: f64 = 1e-6;

/// The law's columns in the store.
pub struct Law {
    /// Its terms, in [`FrictionTerm::ALL`]'s order.
    pub terms: Vec<FrictionTerm>,
    /// One column per term and joint (term-major), with the bounds that
    /// keep an unsigned coefficient ≥ 0.
    pub group: Group,
    /// The term and joint of each column.
    pub labels: Vec<(FrictionTerm, usize)>,
    /// The nominal coefficient of each column.
    pub nominal: Vec<f64>,
    /// Body columns after the friction columns (10 per body of the model,
    /// in its parameter order) when the nominal's bodies are refit with
    /// the law ([`Law::with_bodies`]); 0 when they are held.
    pub bodies: usize,
}

/// The terms of the nominal law: those the model identifies
/// ([`Model::friction_terms`]) and any the nominal friction gives a
/// coefficient that is not zero.
pub fn terms(model: &Model, friction: &Friction) -> Vec<FrictionTerm> {
    FrictionTerm::ALL
        .into_iter()
        .filter(|t| {
            model.friction_terms().contains(t)
                || friction.coefficients(*t).iter().any(|c| *c != 0.0)
        })
        .collect()
}

impl Law {
    /// The law of `model` + `friction` on `data`, its columns added to
    /// `store`: term t of joint i holds `φ_t(q̇ᵢ)` in joint i's rows (the
    /// load term's load: the nominal model's rigid torque, as in
    /// [`Friction::torque`]).
    pub fn new(
        model: &Model,
        friction: &Friction,
        data: &Dataset,
        store: &mut Store,
    ) -> Result<Self, DynamicsError> {
        let terms = terms(model, friction);
        let n = model.dof();
        let rigid = match terms.contains(&FrictionTerm::Load) {
            true => Some(predict_torques(
                model,
                &Friction::zeros(n),
                &data.q,
                &data.qd,
                &data.qdd,
            )?),
            false => None,
        };
        let vs = friction.stribeck_velocity();
        let (mut ids, mut labels, mut nominal, mut lower) = (vec![], vec![], vec![], vec![]);
        for &t in &terms {
            for i in 0..n {
                let mut col = vec![0.0; data.len() * n];
                for k in 0..data.len() {
                    let load = rigid.as_ref().map_or(0.0, |r| r[k][i]);
                    col[k * n + i] = t.basis(data.qd[k][i], load, vs);
                }
                let c0 = friction.coefficients(t).get(i).copied().unwrap_or(0.0);
                ids.push(store.add(col));
                labels.push((t, i));
                nominal.push(c0);
                lower.push(if t.signed() { f64::NEG_INFINITY } else { -c0 });
            }
        }
        Ok(Self {
            terms,
            group: Group {
                ids,
                lower: Some(lower),
                ..Group::default()
            },
            labels,
            nominal,
            bodies: 0,
        })
    }

    /// The same law with the nominal's bodies refit with it: their
    /// regressor columns `cols` (10 per body) added to `store` and to the
    /// group after the friction columns, unbounded, and the rows of the
    /// data the nominal was identified on (`prior`, over those columns in
    /// order) set as the store's rows outside the folds — a change of the
    /// bodies costs what it costs on those data, so one they could not
    /// determine is part of the baseline, not a finding.
    pub fn with_bodies(
        mut self,
        (cols, params): (Vec<Vec<f64>>, &[f64]),
        prior: Prior,
        store: &mut Store,
    ) -> Self {
        let ids: Vec<usize> = cols.into_iter().map(|c| store.add_in(c, None)).collect();
        self.bodies = ids.len();
        let bodies = (params.chunks_exact(10))
            .map(|p| std::array::from_fn(|q| p[q]))
            .collect();
        self.group.push_bodies(&ids, bodies);
        store.set_prior(Prior { ids, ..prior });
        self
    }

    /// The friction columns alone (without refit bodies).
    pub fn friction_group(&self) -> Group {
        self.group.only(&(0..self.labels.len()).collect::<Vec<_>>())
    }

    /// The bodies' changes in a fit's coefficients `beta` (the law's
    /// first): empty when the bodies are held.
    pub fn body_delta<'b>(&self, beta: &'b [f64]) -> &'b [f64] {
        let k = self.labels.len();
        beta.get(k..k + self.bodies).unwrap_or(&[])
    }

    /// The nominal friction with the law's changes `delta` (one per column)
    /// added.
    pub fn friction(&self, nominal: &Friction, delta: &[f64]) -> Friction {
        let mut f = nominal.clone();
        let n = f.viscous.len();
        for ((t, i), d) in self.labels.iter().zip(delta) {
            let c = f.coefficients_mut(*t);
            if c.len() != n {
                c.resize(n, 0.0);
            }
            c[*i] += d;
            // a coefficient bounded at 0 that the conic solver leaves a
            // hair below it (its tolerance) is its bound, as a law requires
            if !t.signed() && c[*i] < 0.0 && c[*i] > -SOLVER_HAIR {
                c[*i] = 0.0;
            }
        }
        f
    }
}
