//! Inverse dynamics and contact forces of a free-flying root (conventions
//! in [`super::free_flyer`]); [`super::rnea`] and [`super::regressor`] call
//! the former.

use super::data::Data;
use super::error::DynamicsError;
use super::free_flyer::BaseState;
use super::model::Model;
use super::rnea::{check_len, rnea_from};
use super::spatial::{Transform, cross_force, force_first, inertia_times};
use nalgebra::{DVector, Matrix3, Vector3, Vector6};

/// How a contact wrench's components are expressed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WrenchFrame {
    /// In the contact frame's own axes (a force-torque sensor's).
    Local,
    /// In world-aligned axes at the contact frame's origin (a force plate's;
    /// Pinocchio's `LOCAL_WORLD_ALIGNED`).
    WorldAligned,
}

/// A wrench the environment applies to the robot at a named frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactWrench {
    /// Index into the model's [`frames`](super::Model::frames).
    pub frame: usize,
    /// Force (N) then moment about the frame origin (N·m).
    pub wrench: [f64; 6],
    /// The axes they are expressed in.
    pub expressed: WrenchFrame,
}

impl Model {
    /// The whole robot at configuration `q` (a free flyer's): its mass
    /// (kg), centre of mass (m) and rotational inertia about it (kg·m²), in
    /// base coordinates (from the mass matrix's base block, the composite
    /// inertia).
    pub fn centroidal(
        &self,
        data: &mut Data,
        q: &[f64],
    ) -> Result<(f64, Vector3<f64>, Matrix3<f64>), DynamicsError> {
        self.need_free_flyer("the centroidal inertia")?;
        let m6 = super::crba(self, data, q)?
            .fixed_view::<6, 6>(0, 0)
            .into_owned();
        let mass = m6[(0, 0)];
        // M_bb = [[m 1, −m [c]×], [m [c]×, I_o]] in (linear, angular) order
        let mc = m6.fixed_view::<3, 3>(3, 0).into_owned();
        let c = Vector3::new(mc[(2, 1)], mc[(0, 2)], mc[(1, 0)]) / mass;
        let sc = crate::moments::skew(&c);
        let io = m6.fixed_view::<3, 3>(3, 3).into_owned();
        Ok((mass, c, io + mass * sc * sc))
    }

    /// A free flyer's inverse dynamics from its base state and joint state
    /// (n each) into `data.tau` (6 + n).
    pub(crate) fn free_flyer_inverse_dynamics(
        &self,
        data: &mut Data,
        s: &BaseState,
        joints: [&[f64]; 3],
        gravity: bool,
    ) {
        let root = self.root_motion(s, gravity);
        let f_tree = rnea_from(self, data, joints, &root);
        let p = &self.base().expect("a free flyer").inertia.0;
        let f0 =
            inertia_times(p, &root.a) + cross_force(&root.v, &inertia_times(p, &root.v)) + f_tree;
        data.tau.rows_mut(0, 6).copy_from_slice(&force_first(&f0));
    }

    /// The generalized force of contact wrenches, `Σ_c J_cᵀ w_c` (6 + n),
    /// at configuration `q` (7 + n).
    pub fn contact_force(
        &self,
        data: &mut Data,
        q: &[f64],
        contacts: &[ContactWrench],
    ) -> Result<DVector<f64>, DynamicsError> {
        let zeros = vec![0.0; self.nv()];
        let s = self.base_state(q, &zeros, &zeros)?;
        for i in 0..self.dof() {
            data.x_up[i] = self.joint_transform(i, q[7 + i]);
        }
        self.chain_to_base(data);
        let mut out = DVector::zeros(self.nv());
        let world_to_base = Self::base_transform(&s);
        for c in contacts {
            self.add_contact(data, &world_to_base, c, &mut out)?;
        }
        Ok(out)
    }

    fn add_contact(
        &self,
        data: &Data,
        world_to_base: &Transform,
        c: &ContactWrench,
        out: &mut DVector<f64>,
    ) -> Result<(), DynamicsError> {
        let frame = self
            .frames
            .get(c.frame)
            .ok_or_else(|| DynamicsError::UnknownName {
                what: "contact frame index",
                name: c.frame.to_string(),
                valid: format!("0..{}", self.frames.len()),
            })?;
        let w = &c.wrench;
        check_len("contact wrench", w, 6)?;
        let (mut n, mut f) = (
            nalgebra::Vector3::new(w[3], w[4], w[5]),
            nalgebra::Vector3::new(w[0], w[1], w[2]),
        );
        if c.expressed == WrenchFrame::WorldAligned {
            let to_body = match frame.body {
                Some(b) => data.x_base[b].compose(world_to_base),
                None => *world_to_base,
            };
            let e = frame.placement.compose(&to_body).e;
            (n, f) = (e * n, e * f);
        }
        let spatial = Vector6::new(n.x, n.y, n.z, f.x, f.y, f.z);
        let mut fb = frame.placement.apply_force_transpose(&spatial);
        let mut body = frame.body;
        while let Some(j) = body {
            out[6 + j] += self.subspace(j).dot(&fb);
            fb = data.x_up[j].apply_force_transpose(&fb);
            body = self.joints[j].parent;
        }
        for (k, x) in force_first(&fb).iter().enumerate() {
            out[k] += x;
        }
        Ok(())
    }
}
