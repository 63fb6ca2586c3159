//! The free-flyer root joint ([`RootJoint::FreeFlyer`]): a [`Model`]'s tree
//! hanging from a free body, the base, that moves with six degrees of
//! freedom; its state and kinematics.
//!
//! Conventions (Pinocchio's free-flyer, so that logs from it read as they are):
//!
//! - configuration `q` (7 + n): the base origin `p` in the world (m), the
//!   base orientation as a unit quaternion `(x, y, z, w)` whose rotation `R`
//!   maps base coordinates to world coordinates, then the n joint positions;
//! - velocity `v` (6 + n): the base origin's linear velocity and the base's
//!   angular velocity, **both in base coordinates** (m/s, rad/s), then q̇;
//! - acceleration `a` (6 + n): the time derivative of `v` (its base part is
//!   the base's spatial acceleration in base coordinates: the classical
//!   acceleration of the base origin is `v̇ + ω × v`);
//! - generalized force (6 + n): the wrench on the base in base coordinates,
//!   force (N) then moment about the base origin (N·m), then joint torques.
//!
//! The base frame is the URDF root link's frame; gravity ([`Model::gravity`])
//! is in world coordinates. The equation of motion is
//! `M(q) a + h(q, v) = [0; τ] + Σ_c J_cᵀ w_c`: [`rnea`](super::rnea) gives
//! its left side, [`contact_force`](Model::contact_force) the contact part
//! of its right side.
//!
//! [`RootJoint::FreeFlyer`]: super::RootJoint::FreeFlyer

use super::data::Data;
use super::error::DynamicsError;
use super::model::Model;
use super::rnea::{RootMotion, check_len};
use super::spatial::Transform;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3, Vector6};

/// The largest `|‖quaternion‖ − 1|` accepted (a float32 log of a unit
/// quaternion is within 1e-7); the quaternion is normalised.
pub const QUATERNION_TOLERANCE: f64 = 1e-5;

/// The base's pose and motion at one sample, as the algorithms use them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaseState {
    /// Base origin in the world (m).
    pub position: Vector3<f64>,
    /// Base orientation (base → world).
    pub orientation: UnitQuaternion<f64>,
    /// Linear velocity (m/s) then angular velocity (rad/s), base coordinates.
    pub velocity: Vector6<f64>,
    /// Their time derivative.
    pub acceleration: Vector6<f64>,
}

impl Model {
    /// An error unless the root is a free flyer (`what` names the caller).
    pub(crate) fn need_free_flyer(&self, what: &'static str) -> Result<(), DynamicsError> {
        if self.is_floating() {
            return Ok(());
        }
        Err(DynamicsError::FixedBase {
            model: self.name.clone(),
            what,
        })
    }

    /// The index of a named frame (a URDF link) in [`frames`](Model::frames),
    /// for a [`ContactWrench`](super::ContactWrench); an unknown name is an
    /// error listing the known ones.
    pub fn frame_index(&self, name: &str) -> Result<usize, DynamicsError> {
        let frames = &self.frames;
        frames
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| DynamicsError::UnknownName {
                what: "contact frame",
                name: name.to_string(),
                valid: frames
                    .iter()
                    .map(|f| f.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// The base state of a free flyer's configuration, velocity and
    /// acceleration (each checked for length; the quaternion for unit norm
    /// within [`QUATERNION_TOLERANCE`]).
    pub fn base_state(&self, q: &[f64], v: &[f64], a: &[f64]) -> Result<BaseState, DynamicsError> {
        let (position, orientation) = self.base_pose(q)?;
        check_len("v", v, self.nv())?;
        check_len("a", a, self.nv())?;
        Ok(BaseState {
            position,
            orientation,
            velocity: Vector6::from_column_slice(&v[..6]),
            acceleration: Vector6::from_column_slice(&a[..6]),
        })
    }

    /// The base pose of a free flyer's configuration `q` (checked for
    /// length, the quaternion for unit norm within [`QUATERNION_TOLERANCE`]).
    pub fn base_pose(
        &self,
        q: &[f64],
    ) -> Result<(Vector3<f64>, UnitQuaternion<f64>), DynamicsError> {
        self.need_free_flyer("a base pose")?;
        check_len("q", q, self.nq())?;
        let quat = Quaternion::new(q[6], q[3], q[4], q[5]);
        let norm = quat.norm();
        if !((norm - 1.0).abs() <= QUATERNION_TOLERANCE) {
            return Err(DynamicsError::Quaternion {
                values: [q[3], q[4], q[5], q[6]],
                norm,
            });
        }
        Ok((
            Vector3::new(q[0], q[1], q[2]),
            UnitQuaternion::from_quaternion(quat),
        ))
    }

    /// The root motion the tree algorithms start from: `[ω; v]` and
    /// `[ω̇; v̇] − (0, Rᵀ g)` in base coordinates.
    pub(crate) fn root_motion(&self, s: &BaseState, with_gravity: bool) -> RootMotion {
        let swap = |x: &Vector6<f64>| Vector6::new(x[3], x[4], x[5], x[0], x[1], x[2]);
        let mut a = swap(&s.acceleration);
        if with_gravity {
            let g = s.orientation.inverse_transform_vector(&self.gravity);
            for k in 0..3 {
                a[3 + k] -= g[k];
            }
        }
        RootMotion {
            v: swap(&s.velocity),
            a,
        }
    }

    /// World → base as a spatial transform.
    pub fn base_transform(s: &BaseState) -> Transform {
        Self::pose_transform(&s.position, &s.orientation)
    }

    /// World → base as a spatial transform, from the base's pose.
    pub fn pose_transform(position: &Vector3<f64>, orientation: &UnitQuaternion<f64>) -> Transform {
        let rot: Matrix3<f64> = orientation.to_rotation_matrix().into_inner();
        Transform::from_pose(&rot, position)
    }

    /// The origins of `frames` (indices into [`frames`](Model::frames)) in
    /// base coordinates (m), at joint positions `joints` (n): the forward
    /// kinematics of contact points.
    pub fn frames_in_base(
        &self,
        data: &mut Data,
        joints: &[f64],
        frames: &[usize],
    ) -> Result<Vec<Vector3<f64>>, DynamicsError> {
        check_len("joint positions", joints, self.dof())?;
        for (i, &x) in joints.iter().enumerate() {
            data.x_up[i] = self.joint_transform(i, x);
        }
        self.chain_to_base(data);
        let known = self.frames.len();
        (frames.iter())
            .map(|&f| {
                let frame = self
                    .frames
                    .get(f)
                    .ok_or_else(|| DynamicsError::UnknownName {
                        what: "frame index",
                        name: f.to_string(),
                        valid: format!("0..{known}"),
                    })?;
                Ok(match frame.body {
                    Some(b) => frame.placement.compose(&data.x_base[b]).r,
                    None => frame.placement.r,
                })
            })
            .collect()
    }

    /// Fills `data.x_base` (base → each body) from `data.x_up`.
    pub(crate) fn chain_to_base(&self, data: &mut Data) {
        for i in 0..self.dof() {
            data.x_base[i] = match self.joints[i].parent {
                Some(p) => data.x_up[i].compose(&data.x_base[p]),
                None => data.x_up[i],
            };
        }
    }
}
