//! Spatial algebra on nalgebra types (Featherstone's conventions).
//!
//! Spatial vectors are `[angular; linear]` (`Vector6`), expressed in a body
//! frame. A [`Transform`] `X` from frame A to frame B holds `E` (rotates
//! A-coordinates into B-coordinates) and `r` (B's origin in A-coordinates);
//! it maps motion vectors `m_B = X m_A` and, transposed, forces
//! `f_A = Xᵀ f_B`.

use nalgebra::{Matrix3, Vector3, Vector6};

/// A rigid transform between two frames (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Rotation from A-coordinates to B-coordinates.
    pub e: Matrix3<f64>,
    /// Position of B's origin in A-coordinates (m).
    pub r: Vector3<f64>,
}

#[inline]
fn ang(v: &Vector6<f64>) -> Vector3<f64> {
    Vector3::new(v[0], v[1], v[2])
}
#[inline]
fn lin(v: &Vector6<f64>) -> Vector3<f64> {
    Vector3::new(v[3], v[4], v[5])
}
#[inline]
fn join(a: Vector3<f64>, l: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(a.x, a.y, a.z, l.x, l.y, l.z)
}

impl Transform {
    /// The identity.
    pub fn identity() -> Self {
        Self {
            e: Matrix3::identity(),
            r: Vector3::zeros(),
        }
    }

    /// The transform to a frame B placed at `p` with axes `rot` (columns =
    /// B's axes in A-coordinates): `E = rotᵀ`, `r = p`.
    pub fn from_pose(rot: &Matrix3<f64>, p: &Vector3<f64>) -> Self {
        Self {
            e: rot.transpose(),
            r: *p,
        }
    }

    /// `X m` for a motion vector m in A-coordinates.
    #[inline]
    pub fn apply_motion(&self, m: &Vector6<f64>) -> Vector6<f64> {
        let w = ang(m);
        let v = lin(m) - self.r.cross(&w);
        join(self.e * w, self.e * v)
    }

    /// `Xᵀ f` for a force f in B-coordinates (result in A-coordinates).
    #[inline]
    pub fn apply_force_transpose(&self, f: &Vector6<f64>) -> Vector6<f64> {
        let n = self.e.transpose() * ang(f);
        let fl = self.e.transpose() * lin(f);
        join(n + self.r.cross(&fl), fl)
    }

    /// Composition: `(self ∘ inner)` maps A → C when `inner: A → B` and `self: B → C`.
    pub fn compose(&self, inner: &Transform) -> Transform {
        Transform {
            e: self.e * inner.e,
            r: inner.r + inner.e.transpose() * self.r,
        }
    }

    /// The inverse transform B → A.
    pub fn inverse(&self) -> Transform {
        Transform {
            e: self.e.transpose(),
            r: -(self.e * self.r),
        }
    }

    /// A point's coordinates: `x_B = E (x_A − r)`.
    pub fn apply_point(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.e * (x - self.r)
    }
}

/// Motion cross product `v × m`.
#[inline]
pub fn cross_motion(v: &Vector6<f64>, m: &Vector6<f64>) -> Vector6<f64> {
    let (w, vl) = (ang(v), lin(v));
    let (mw, ml) = (ang(m), lin(m));
    join(w.cross(&mw), w.cross(&ml) + vl.cross(&mw))
}

/// Force cross product `v ×* f`.
#[inline]
pub fn cross_force(v: &Vector6<f64>, f: &Vector6<f64>) -> Vector6<f64> {
    let (w, vl) = (ang(v), lin(v));
    let (fn_, fl) = (ang(f), lin(f));
    join(w.cross(&fn_) + vl.cross(&fl), w.cross(&fl))
}

/// `I v` for the spatial inertia of π (paper order) and a motion vector v.
#[inline]
pub fn inertia_times(pi: &[f64; 10], v: &Vector6<f64>) -> Vector6<f64> {
    let (w, vl) = (ang(v), lin(v));
    let h = Vector3::new(pi[1], pi[2], pi[3]);
    let iw = Vector3::new(
        pi[4] * w.x + pi[5] * w.y + pi[6] * w.z,
        pi[5] * w.x + pi[7] * w.y + pi[8] * w.z,
        pi[6] * w.x + pi[8] * w.y + pi[9] * w.z,
    );
    join(iw + h.cross(&vl), vl * pi[0] - h.cross(&w))
}

/// Elementary rotation by angle `q` about a unit axis (Rodrigues), returning
/// the matrix whose columns are the rotated frame's axes.
#[inline]
pub fn axis_rotation(axis: &Vector3<f64>, q: f64) -> Matrix3<f64> {
    let (s, c) = q.sin_cos();
    let k = crate::moments::skew(axis);
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}

/// `[n; f]` (the spatial order) to `[f; n]` (the generalized-force order).
pub(crate) fn force_first(w: &Vector6<f64>) -> [f64; 6] {
    [w[3], w[4], w[5], w[0], w[1], w[2]]
}
