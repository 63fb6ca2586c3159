//! Points on a URDF link's shapes, in the link frame: a mesh's vertices
//! (scaled) and points on the surface of the primitives, for plots of a
//! link's geometry beside its bounding and covariance ellipsoids
//! (`momentlmi check --out`).

use super::ellipsoid::rpy_rotation;
use super::urdf_check::Meshes;
use crate::urdf::{Geometry, Link, Shape};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Points of the link's shapes (collision, else visual; the shapes the
/// checker bounds), link frame (m), at most `max` of them (an even stride
/// through each shape's points). Shapes that cannot be read give none (the
/// checker warns about them).
pub fn geometry_points(link: &Link, meshes: &mut Meshes, max: usize) -> Vec<Vector3<f64>> {
    let (shapes, _) = super::urdf_check::bounded_shapes(link);
    let per_shape = max / shapes.len().max(1);
    let mut out = Vec::new();
    for s in shapes {
        let pts = shape_points(s, meshes);
        let stride = pts.len().div_ceil(per_shape.max(1)).max(1);
        let (r, p) = (rpy_rotation(s.origin.rpy), Vector3::from(s.origin.xyz));
        out.extend(pts.iter().step_by(stride).map(|x| r * x + p));
    }
    out
}

/// One shape's points in its own frame.
fn shape_points(s: &Shape, meshes: &mut Meshes) -> Vec<Vector3<f64>> {
    match &s.geometry {
        Geometry::Box { size } => box_points(Vector3::from(*size) / 2.0),
        Geometry::Cylinder { radius, length } => cylinder_points(*radius, *length / 2.0),
        Geometry::Capsule { radius, length } => {
            let mut v = cylinder_points(*radius, *length / 2.0);
            for z in [-1.0, 1.0] {
                let cap = sphere_points(*radius)
                    .into_iter()
                    .filter(|p| p.z * z >= 0.0);
                v.extend(cap.map(|p| p + Vector3::new(0.0, 0.0, z * length / 2.0)));
            }
            v
        }
        Geometry::Sphere { radius } => sphere_points(*radius),
        Geometry::Mesh { filename, scale } => {
            let s = Vector3::from(*scale);
            meshes
                .vertices(filename)
                .map(|v| v.iter().map(|p| p.component_mul(&s)).collect())
                .unwrap_or_default()
        }
        Geometry::Invalid { .. } => vec![],
    }
}

/// Points along the 12 edges of a box with half-sides `h`.
fn box_points(h: Vector3<f64>) -> Vec<Vector3<f64>> {
    let mut v = Vec::new();
    for axis in 0..3 {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        for (sa, sb) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
            for k in 0..=10 {
                let mut p = Vector3::zeros();
                p[axis] = h[axis] * (2.0 * k as f64 / 10.0 - 1.0);
                p[a] = sa * h[a];
                p[b] = sb * h[b];
                v.push(p);
            }
        }
    }
    v
}

/// Rings and generators of a cylinder about z, radius `r`, half-length `h`.
fn cylinder_points(r: f64, h: f64) -> Vec<Vector3<f64>> {
    let mut v = Vec::new();
    for k in 0..36 {
        let a = 2.0 * PI * k as f64 / 36.0;
        for z in 0..=4 {
            let z = h * (z as f64 / 2.0 - 1.0);
            v.push(Vector3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    v
}

/// Meridians and parallels of a sphere of radius `r`.
fn sphere_points(r: f64) -> Vec<Vector3<f64>> {
    let mut v = Vec::new();
    for i in 0..=12 {
        let th = PI * i as f64 / 12.0;
        for k in 0..24 {
            let ph = 2.0 * PI * k as f64 / 24.0;
            v.push(r * Vector3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()));
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitive_points_lie_on_their_surfaces() {
        let h = Vector3::new(0.1, 0.2, 0.3);
        for p in box_points(h) {
            let on_edge = (0..3)
                .filter(|&i| (p[i].abs() - h[i]).abs() < 1e-12)
                .count();
            assert!(on_edge >= 2, "{p:?}");
        }
        for p in cylinder_points(0.5, 0.2) {
            assert!((p.xy().norm() - 0.5).abs() < 1e-12 && p.z.abs() <= 0.2 + 1e-12);
        }
        for p in sphere_points(0.7) {
            assert!((p.norm() - 0.7).abs() < 1e-12);
        }
    }
}
