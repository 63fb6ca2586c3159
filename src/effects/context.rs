//! What an effect's hypothesis is built from: the nominal model, the data,
//! the nominal residual, the training part, and what several hypotheses
//! share (the nominal torques, the linearised link dynamics), computed
//! once on first use.

use super::compliance::Linearisation;
use super::error::EffectError;
use crate::data::Dataset;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Data, Friction, Model, Samples, regressor};
use nalgebra::DMatrix;
use std::sync::{Arc, OnceLock};

/// The data and nominal model a hypothesis is built for.
pub struct Context<'a> {
    /// The nominal model (its parameters are the current estimate).
    pub model: &'a Model,
    /// Its friction.
    pub friction: &'a Friction,
    /// The measured data (its joints are the model's).
    pub data: &'a Dataset,
    /// The nominal model's residual `τ − τ̂`, sample-major: `r[k·n + i]` for
    /// sample k, joint i.
    pub residual: &'a [f64],
    /// Samples `0..train` are the training part: a search for nonlinear
    /// parameters may fit them only.
    pub train: usize,
    nominal: OnceLock<Result<Samples, Arc<EffectError>>>,
    rigid: OnceLock<Result<Samples, Arc<EffectError>>>,
    linearisation: OnceLock<Result<Linearisation, Arc<EffectError>>>,
}

impl<'a> Context<'a> {
    /// The context of `data` against `model` + `friction`.
    pub fn new(
        model: &'a Model,
        friction: &'a Friction,
        data: &'a Dataset,
        residual: &'a [f64],
        train: usize,
    ) -> Self {
        Self {
            model,
            friction,
            data,
            residual,
            train,
            nominal: OnceLock::new(),
            rigid: OnceLock::new(),
            linearisation: OnceLock::new(),
        }
    }

    /// Joints n.
    pub fn joints(&self) -> usize {
        self.data.joints.len()
    }

    /// Samples.
    pub fn samples(&self) -> usize {
        self.data.len()
    }

    /// Joint i's gear ratio (1 without a rotor).
    pub fn gear(&self, i: usize) -> f64 {
        self.model.rotor_of(i).map_or(1.0, |r| r.gear_ratio)
    }

    /// One column per joint: column i holds `f(k, i)` in joint i's row of
    /// every sample k, zero in the other joints' rows.
    pub fn per_joint(&self, f: impl Fn(usize, usize) -> f64) -> Vec<Vec<f64>> {
        (0..self.joints())
            .map(|i| self.joint_column(i, |k| f(k, i)))
            .collect()
    }

    /// One column for joint i: `f(k)` in joint i's row of every sample k,
    /// zero in the other joints' rows.
    pub fn joint_column(&self, i: usize, f: impl Fn(usize) -> f64) -> Vec<f64> {
        let n = self.joints();
        let mut c = vec![0.0; self.samples() * n];
        for k in 0..self.samples() {
            c[k * n + i] = f(k);
        }
        c
    }

    /// `count` columns from the nominal model's regressor
    /// ([`crate::dynamics::regressor`]): column c holds `f(Y, i, c)` in joint
    /// i's row of every sample, Y that sample's regressor.
    pub fn regressor_columns(
        &self,
        count: usize,
        f: impl Fn(&DMatrix<f64>, usize, usize) -> f64,
    ) -> Result<Vec<Vec<f64>>, EffectError> {
        let (n, d) = (self.joints(), self.data);
        let mut cols = vec![vec![0.0; d.len() * n]; count];
        let mut data = Data::new(self.model);
        let measured = d.tau.len() == d.len();
        for k in 0..d.len() {
            // the load friction column's load: the measured torque, when
            // there is one (data to predict on have none: no load)
            match measured {
                true => data
                    .load
                    .iter_mut()
                    .zip(&d.tau[k])
                    .for_each(|(l, t)| *l = *t),
                false => data.load.iter_mut().for_each(|l| *l = 0.0),
            }
            let y = regressor(self.model, &mut data, &d.q[k], &d.qd[k], &d.qdd[k])
                .map_err(|source| EffectError::Regressor { sample: k, source })?;
            for i in 0..n {
                for (c, col) in cols.iter_mut().enumerate() {
                    col[k * n + i] = f(y, i, c);
                }
            }
        }
        Ok(cols)
    }

    /// The nominal model's torques τ̂ at every sample (a row of n each).
    pub fn nominal_torques(&self) -> Result<&Samples, EffectError> {
        let d = self.data;
        self.nominal
            .get_or_init(|| {
                predict_torques(self.model, self.friction, &d.q, &d.qd, &d.qdd)
                    .map_err(|e| Arc::new(EffectError::Dynamics(e)))
            })
            .as_ref()
            .map_err(|e| EffectError::Shared(e.clone()))
    }

    /// The nominal model's rigid torques (links and rotors, no friction) at
    /// every sample: the load of the friction law's `load` term.
    pub fn rigid_torques(&self) -> Result<&Samples, EffectError> {
        let d = self.data;
        let none = Friction::zeros(self.model.dof());
        self.rigid
            .get_or_init(|| {
                predict_torques(self.model, &none, &d.q, &d.qd, &d.qdd)
                    .map_err(|e| Arc::new(EffectError::Dynamics(e)))
            })
            .as_ref()
            .map_err(|e| EffectError::Shared(e.clone()))
    }

    /// The link dynamics linearised along the data (for compliance
    /// hypotheses searched by simulation).
    pub fn linearisation(&self) -> Result<&Linearisation, EffectError> {
        self.linearisation
            .get_or_init(|| {
                Linearisation::new(self.model, self.data)
                    .map_err(|e| Arc::new(EffectError::Dynamics(e)))
            })
            .as_ref()
            .map_err(|e| EffectError::Shared(e.clone()))
    }
}
