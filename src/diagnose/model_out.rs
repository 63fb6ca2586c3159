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
use crate::moments::InertialParams;

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
    // bodies refit with the law (the nominal's own data given)
    (params.iter_mut().zip(law.body_delta(&beta[..k]))).for_each(|(p, d)| *p += d);
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
                onto_cone(&mut params[10 * body..10 * body + 10]);
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

/// How far below 0 (relative to the largest) an eigenvalue of a merged
/// body's pseudo-inertia may come out of the conic solver and still be
/// its bound: the fit constrained J ⪰ 0, and a body on the cone's boundary
/// (a thin rotor disc) comes back a hair outside it.
const CONE_HAIR: f64 = 1e-6;

/// A body's parameters whose pseudo-inertia has eigenvalues a hair below
/// 0 ([`CONE_HAIR`]) put back on the cone (those eigenvalues set to 0);
/// any other left as they are (a larger violation is the fit's own, and
/// the model file's reader names it).
fn onto_cone(p: &mut [f64]) {
    let mut a = [0.0; 10];
    a.copy_from_slice(p);
    let e = InertialParams::new(a).pseudo_inertia().symmetric_eigen();
    let top = e.eigenvalues.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let low = e.eigenvalues.iter().copied().fold(f64::INFINITY, f64::min);
    if !(low < 0.0 && low >= -CONE_HAIR * top) {
        return;
    }
    let clipped = nalgebra::Matrix4::from_diagonal(&e.eigenvalues.map(|x| x.max(0.0)));
    let j = &e.eigenvectors * clipped * e.eigenvectors.transpose();
    p.copy_from_slice(&InertialParams::from_pseudo_inertia(&j).as_array());
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

#[cfg(test)]
mod tests {
    use super::*;

    fn lowest(p: &[f64]) -> f64 {
        let mut a = [0.0; 10];
        a.copy_from_slice(p);
        let e = InertialParams::new(a).pseudo_inertia().symmetric_eigen();
        e.eigenvalues.iter().copied().fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn a_body_a_hair_outside_the_cone_is_put_back_and_a_far_one_is_not() {
        // a thin disc of 1 kg, radius 0.1 m, about z: on the cone's boundary
        let (m, r) = (1.0, 0.1);
        let (ixx, izz) = (m * r * r / 4.0, m * r * r / 2.0);
        let disc = [m, 0.0, 0.0, 0.0, ixx, 0.0, 0.0, ixx, 0.0, izz];
        let hair = {
            let mut p = disc;
            p[9] += 1e-9; // Izz beyond Ixx + Iyy by a solver's tolerance
            p
        };
        assert!(lowest(&hair) < 0.0);
        let mut fixed = hair;
        onto_cone(&mut fixed);
        assert!(lowest(&fixed) >= -1e-15, "{}", lowest(&fixed));
        assert!((fixed[9] - izz).abs() < 1e-8 && (fixed[0] - m).abs() < 1e-12);
        let far = {
            let mut p = disc;
            p[9] += 1e-3;
            p
        };
        let mut kept = far;
        onto_cone(&mut kept);
        assert_eq!(kept, far);
    }
}
