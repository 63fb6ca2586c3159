//! Inverse dynamics, the mass matrix, the regressor and contact forces of a
//! [`FreeFlyer`] (conventions in [`super::free_flyer`]).

use super::data::BodyRegressor;
use super::error::DynamicsError;
use super::free_flyer::{BaseState, FreeFlyer, FreeFlyerData, force_first};
use super::regressor::{body_regressor, check_load, regressor_blocks_from};
use super::rnea::{Root, check_len, rnea_from};
use super::spatial::{Transform, cross_force, inertia_times};
use nalgebra::{DMatrix, DVector, Vector6};

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
    /// Index into the tree's [`frames`](super::Model::frames).
    pub frame: usize,
    /// Force (N) then moment about the frame origin (N·m).
    pub wrench: [f64; 6],
    /// The axes they are expressed in.
    pub expressed: WrenchFrame,
}

impl FreeFlyer {
    /// Inverse dynamics: the generalized force `M(q) a + h(q, v)` (6 + n:
    /// base wrench, force then moment in base coordinates, then joint
    /// torques) into `data.tau`.
    pub fn rnea<'a>(
        &self,
        data: &'a mut FreeFlyerData,
        q: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> Result<&'a DVector<f64>, DynamicsError> {
        let s = self.base_state(q, v, a)?;
        self.inverse_dynamics(data, &s, [&q[7..], &v[6..], &a[6..]], true);
        Ok(&data.tau)
    }

    fn inverse_dynamics(
        &self,
        data: &mut FreeFlyerData,
        s: &BaseState,
        joints: [&[f64]; 3],
        gravity: bool,
    ) {
        let root = self.root(s, gravity);
        let f_tree = rnea_from(&self.tree, &mut data.tree, joints, &root);
        let p = &self.base.0;
        let f0 =
            inertia_times(p, &root.a) + cross_force(&root.v, &inertia_times(p, &root.v)) + f_tree;
        data.tau.rows_mut(0, 6).copy_from_slice(&force_first(&f0));
        let n = self.tree.dof();
        data.tau.rows_mut(6, n).copy_from(&data.tree.tau);
    }

    /// The mass matrix ((6 + n)², into `data.mass_matrix`), column by
    /// column as the inverse dynamics of unit accelerations at rest without
    /// gravity (Walker and Orin's first method).
    pub fn crba<'a>(
        &self,
        data: &'a mut FreeFlyerData,
        q: &[f64],
    ) -> Result<&'a DMatrix<f64>, DynamicsError> {
        let nv = self.nv();
        let zeros = vec![0.0; nv];
        let s = self.base_state(q, &zeros, &zeros)?;
        let mut unit = vec![0.0; nv];
        for j in 0..nv {
            unit[j] = 1.0;
            let mut sj = s;
            sj.acceleration = Vector6::from_column_slice(&unit[..6]);
            self.inverse_dynamics(data, &sj, [&q[7..], &zeros[6..], &unit[6..]], false);
            data.mass_matrix.set_column(j, &data.tau);
            unit[j] = 0.0;
        }
        Ok(&data.mass_matrix)
    }

    /// The regressor `Y` with `Y π = M a + h` for π = [`params`](Self::params)
    /// and the tree's friction columns (into `data.regressor`): rows as the
    /// generalized force, columns the base's 10 then the tree's layout
    /// ([`super::regressor`]); the base rows have no friction.
    pub fn regressor<'a>(
        &self,
        data: &'a mut FreeFlyerData,
        q: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> Result<&'a DMatrix<f64>, DynamicsError> {
        let s = self.base_state(q, v, a)?;
        check_load(&self.tree, &data.tree)?;
        let root = self.root(&s, true);
        let mut y = std::mem::take(&mut data.regressor);
        y.fill(0.0);
        let joints = [&q[7..], &v[6..], &a[6..]];
        regressor_blocks_from(&self.tree, &mut data.tree, joints, &root, |r, c0, vals| {
            for (c, x) in vals.iter().enumerate() {
                y[(6 + r, 10 + c0 + c)] += x;
            }
        });
        self.base_rows(data, &root, &mut y);
        data.regressor = y;
        Ok(&data.regressor)
    }

    /// The base rows: every body's `X_{body←base}ᵀ A(v, a)`, the base's own
    /// with the identity.
    fn base_rows(&self, data: &mut FreeFlyerData, root: &Root, y: &mut DMatrix<f64>) {
        self.chain_to_base(data);
        let n = self.tree.dof();
        let t = &data.tree;
        put_base_rows(
            y,
            0,
            &body_regressor(&root.v, &root.a),
            &Transform::identity(),
        );
        for i in 0..n {
            let a = body_regressor(&t.v[i], &t.a[i]);
            put_base_rows(y, 10 + 10 * i, &a, &data.x_base[i]);
        }
        for (k, r) in self.tree.rotors.iter().enumerate() {
            let x = match self.tree.joints[r.joint].parent {
                Some(p) => t.x_rotor[k].compose(&data.x_base[p]),
                None => t.x_rotor[k],
            };
            let a = body_regressor(&t.v_rotor[k], &t.a_rotor[k]);
            put_base_rows(y, 10 + 10 * (n + k), &a, &x);
        }
    }

    /// The generalized force of contact wrenches, `Σ_c J_cᵀ w_c` (6 + n),
    /// at configuration `q` (7 + n).
    pub fn contact_force(
        &self,
        data: &mut FreeFlyerData,
        q: &[f64],
        contacts: &[ContactWrench],
    ) -> Result<DVector<f64>, DynamicsError> {
        let zeros = vec![0.0; self.nv()];
        let s = self.base_state(q, &zeros, &zeros)?;
        for i in 0..self.tree.dof() {
            data.tree.x_up[i] = self.tree.joint_transform(i, q[7 + i]);
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
        data: &FreeFlyerData,
        world_to_base: &Transform,
        c: &ContactWrench,
        out: &mut DVector<f64>,
    ) -> Result<(), DynamicsError> {
        let frame = self
            .tree
            .frames
            .get(c.frame)
            .ok_or_else(|| DynamicsError::UnknownName {
                what: "contact frame index",
                name: c.frame.to_string(),
                valid: format!("0..{}", self.tree.frames.len()),
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
            out[6 + j] += self.tree.subspace(j).dot(&fb);
            fb = data.tree.x_up[j].apply_force_transpose(&fb);
            body = self.tree.joints[j].parent;
        }
        for (k, x) in force_first(&fb).iter().enumerate() {
            out[k] += x;
        }
        Ok(())
    }
}

/// Adds `Xᵀ A` (6 × 10, rows force first) at rows 0..6, columns `col0..`.
fn put_base_rows(y: &mut DMatrix<f64>, col0: usize, a: &BodyRegressor, x: &Transform) {
    for c in 0..10 {
        let f = force_first(&x.apply_force_transpose(&a.column(c).into_owned()));
        for (r, v) in f.iter().enumerate() {
            y[(r, col0 + c)] += v;
        }
    }
}
