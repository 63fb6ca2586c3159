//! The model as MuJoCo holds it. MuJoCo has no geared rotor: a joint's
//! `armature` adds a constant to the diagonal of the mass matrix, which
//! is a rotor spinning on the fixed base. So each rotor becomes
//! - its rigid part, carried by the parent body (its mass and inertia
//!   added to the parent's, in the parent's frame, at spin angle 0);
//! - `armature = N² aᵀ Ī a`, its rotational inertia about its spin axis
//!   (through the rotor frame's origin) reflected through the gear.
//!
//! Dropped: the coupling of the rotor's spin with the parent body's
//! rotation (`N q̇ aᵀ Ī ω_parent` in the kinetic energy: off-diagonal mass
//! matrix terms and gyroscopic torques), a rotor's inertia that changes
//! with its spin angle, and rotors on the fixed base carry nothing more.
//! [`MujocoView::dropped`] measures what this changes in the torques.
//! Friction: `damping` = viscous, `frictionloss` = Coulomb; the other
//! terms (offset, asymmetric, load, Stribeck) have no MuJoCo joint
//! attribute and are listed in [`MujocoView::notes`].

use super::error::ExportError;
use crate::dynamics::{Data, Friction, FrictionTerm, Model, rnea};
use crate::sim::trajectory::Trajectory;

/// A model MuJoCo can hold exactly: links only, per-joint armature,
/// damping and friction loss.
#[derive(Clone, Debug)]
pub struct MujocoView {
    /// The links, each rotor's rigid part added to its parent body; no rotors.
    pub model: Model,
    /// Per joint: reflected rotor inertia N² aᵀ Ī a (kg·m², or kg for a
    /// prismatic joint).
    pub armature: Vec<f64>,
    /// Per joint: viscous friction (N·m·s/rad).
    pub damping: Vec<f64>,
    /// Per joint: Coulomb friction (N·m).
    pub frictionloss: Vec<f64>,
    /// What the view leaves out, one sentence each.
    pub notes: Vec<String>,
}

/// The torques the view leaves out over a motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Dropped {
    /// Per joint: RMS of (full model − view) rigid-body torques (N·m).
    pub rms: Vec<f64>,
    /// Per joint: RMS of the full model's rigid-body torques (N·m).
    pub rms_full: Vec<f64>,
    /// Samples and seconds of the motion.
    pub samples: usize,
}

impl MujocoView {
    /// The view of `model` with `friction` (rotors folded as the module says).
    pub fn new(model: &Model, friction: &Friction) -> Result<Self, ExportError> {
        let n = model.dof();
        // the rotors' rigid parts on their parent bodies (`Model::link_side`)
        let links = model.link_side();
        let mut armature = vec![0.0; n];
        let mut notes = vec![];
        for r in &model.rotors {
            let a = r.axis;
            armature[r.joint] = r.gear_ratio.powi(2) * (a.transpose() * r.inertia.inertia() * a)[0];
            if model.joints[r.joint].parent.is_none() && !model.is_floating() {
                notes.push(format!(
                    "rotor '{}' sits on the fixed base: only its spin (armature) moves",
                    r.name
                ));
            }
        }
        if !model.rotors.is_empty() {
            notes.push("the rotors' spin is joint armature: its coupling with the parent bodies' rotation (gyroscopic and off-diagonal inertia) is dropped".into());
        }
        for t in FrictionTerm::ALL {
            let kept = matches!(t, FrictionTerm::Viscous | FrictionTerm::Coulomb);
            if !kept && friction.coefficients(t).iter().any(|&x| x != 0.0) {
                notes.push(format!(
                    "friction term '{}' has no MuJoCo joint attribute: dropped",
                    t.name()
                ));
            }
        }
        let per_joint = |v: &[f64]| (0..n).map(|j| v.get(j).copied().unwrap_or(0.0)).collect();
        Ok(Self {
            model: links,
            armature,
            damping: per_joint(&friction.viscous),
            frictionloss: per_joint(&friction.coulomb),
            notes,
        })
    }

    /// Rigid-body and armature torques `M(q) q̈ + C q̇ + g + armature ⊙ q̈`
    /// (no friction), as MuJoCo's inverse dynamics gives them without
    /// passive and constraint forces (N·m or N; a free flyer's base wrench
    /// first, in its conventions: [`crate::dynamics::rnea`]).
    pub fn torques(
        &self,
        data: &mut Data,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> Result<Vec<f64>, ExportError> {
        let o = self.model.root_nv();
        let mut tau: Vec<f64> = rnea(&self.model, data, q, qd, qdd)?
            .iter()
            .copied()
            .collect();
        for (j, a) in self.armature.iter().enumerate() {
            tau[o + j] += a * qdd[o + j];
        }
        Ok(tau)
    }

    /// What the view changes in the rigid-body joint torques of `full` (the
    /// model it was made from) over `seconds` of `motion` at 1 kHz (a free
    /// flyer's base held at rest).
    pub fn dropped(
        &self,
        full: &Model,
        motion: &Trajectory,
        seconds: f64,
    ) -> Result<Dropped, ExportError> {
        let n = full.dof();
        let (mut full_data, mut data) = (Data::new(full), Data::new(&self.model));
        let (mut diff, mut sq) = (vec![0.0; n], vec![0.0; n]);
        let samples = (seconds * 1000.0).round().max(1.0) as usize;
        let o = full.root_nv();
        // a free flyer's base held at rest at the world origin
        let rooted = |x: Vec<f64>, pose: &[f64]| -> Vec<f64> {
            if o == 0 { x } else { [pose, &x].concat() }
        };
        let (at_rest, still) = ([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0], [0.0; 6]);
        for k in 0..samples {
            let Some((q, qd, qdd)) = motion.state(k as f64 * 1e-3) else {
                continue;
            };
            let (q, qd, qdd) = (rooted(q, &at_rest), rooted(qd, &still), rooted(qdd, &still));
            let view = self.torques(&mut data, &q, &qd, &qdd)?;
            let tau = rnea(full, &mut full_data, &q, &qd, &qdd)?;
            for j in 0..n {
                diff[j] += (tau[o + j] - view[o + j]).powi(2);
                sq[j] += tau[o + j].powi(2);
            }
        }
        let rms = |v: Vec<f64>| v.into_iter().map(|x| (x / samples as f64).sqrt()).collect();
        Ok(Dropped {
            rms: rms(diff),
            rms_full: rms(sq),
            samples,
        })
    }
}
