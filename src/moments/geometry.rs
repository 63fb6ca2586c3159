//! A URDF link's geometry, the one home of what the checker, the robot
//! description and the plots share: where its meshes come from
//! ([`Meshes`]: found, read once, or replaced by given ellipsoids), the
//! bounding ellipsoids of its shapes ([`geometry_ellipsoids`]) and points on
//! them ([`geometry_points`], for `momentlmi check --out`).

use super::cache::{CacheKey, SolveCache};
use super::ellipsoid::{Ellipsoid, rpy_rotation};
use crate::urdf::mesh::{MeshPaths, read_vertices};
use crate::urdf::{Geometry, Link, Pose, Shape};
use nalgebra::Vector3;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::PathBuf;

fn pose_of(p: &Pose) -> (nalgebra::Matrix3<f64>, Vector3<f64>) {
    (rpy_rotation(p.rpy), Vector3::from(p.xyz))
}

/// Where link geometry comes from: where meshes are found, the vertices of
/// those read so far (a mesh several links use is read once), and bounding
/// ellipsoids given for links by name (a sidecar's `[[body]] bounding`),
/// which replace the ones of the link's shapes.
pub struct Meshes {
    pub(super) paths: Option<MeshPaths>,
    read: HashMap<PathBuf, Result<Vec<Vector3<f64>>, String>>,
    given: HashMap<String, Vec<Ellipsoid>>,
    /// Mesh ellipsoids by content (the distinct vertices' and the scale's
    /// bits, hashed): a mesh several links or files share is solved once.
    solved: HashMap<CacheKey, Ellipsoid>,
    /// Where solved ellipsoids are kept between runs, if anywhere.
    cache: Option<SolveCache>,
    /// The first failure to store in [`Self::cache`] (the results stand).
    cache_error: Option<String>,
}

impl Meshes {
    /// Meshes found through `paths`.
    pub fn new(paths: MeshPaths) -> Self {
        Self::found_through(Some(paths))
    }

    fn found_through(paths: Option<MeshPaths>) -> Self {
        Self {
            paths,
            read: HashMap::new(),
            given: HashMap::new(),
            solved: HashMap::new(),
            cache: None,
            cache_error: None,
        }
    }

    /// The link `link`'s bounding volume is the union of `ellipsoids` (link
    /// frame), whatever its shapes.
    pub fn with_bounding(mut self, link: &str, ellipsoids: Vec<Ellipsoid>) -> Self {
        self.given.insert(link.to_string(), ellipsoids);
        self
    }

    /// Solved ellipsoids are kept in, and taken from, `cache`
    /// ([`crate::moments::cache`]).
    pub fn with_cache(mut self, cache: SolveCache) -> Self {
        self.cache = Some(cache);
        self
    }

    /// The cache given with [`Meshes::with_cache`].
    pub fn cache(&self) -> Option<&SolveCache> {
        self.cache.as_ref()
    }

    /// The first failure to store a solved ellipsoid in the cache (folder
    /// and reason), if any: the ellipsoids are right, the next run solves
    /// them again.
    pub fn cache_error(&self) -> Option<&str> {
        self.cache_error.as_deref()
    }

    /// Notes a failure to store in the cache (the first one is kept).
    pub fn note_cache_error(&mut self, e: std::io::Error) {
        if self.cache_error.is_none() {
            let dir = self.cache.as_ref().map(|c| c.dir().display().to_string());
            self.cache_error = Some(format!("{}: {e}", dir.unwrap_or_default()));
        }
    }

    /// The links given a bounding volume with [`Meshes::with_bounding`].
    pub fn given_links(&self) -> impl Iterator<Item = &str> {
        self.given.keys().map(String::as_str)
    }

    /// No mesh is read (a URDF given as text has no folder).
    pub fn none() -> Self {
        Self::found_through(None)
    }

    /// The distinct vertices of the mesh `filename` names.
    pub(crate) fn vertices(&mut self, filename: &str) -> Result<&[Vector3<f64>], String> {
        read_through(self.paths.as_ref(), &mut self.read, filename)
    }
}

/// The distinct vertices of the mesh `filename` names, found through
/// `paths` and read once into `read` (a function of those fields alone, so
/// that a caller can hold the vertices and use the other fields).
fn read_through<'a>(
    paths: Option<&MeshPaths>,
    read: &'a mut HashMap<PathBuf, Result<Vec<Vector3<f64>>, String>>,
    filename: &str,
) -> Result<&'a [Vector3<f64>], String> {
    let Some(paths) = paths else {
        return Err(format!(
            "mesh '{filename}': no folder to look in (URDF text)"
        ));
    };
    let file = paths.resolve(filename).map_err(|e| e.to_string())?;
    let v = read.entry(file.clone()).or_insert_with(|| {
        read_vertices(&file)
            .map(distinct)
            .map_err(|e| e.to_string())
    });
    v.as_deref().map_err(Clone::clone)
}

impl Meshes {
    /// The minimum-volume ellipsoid enclosing the mesh `filename`'s
    /// vertices, scaled; solved once per content (and kept in the cache,
    /// if one is given, across runs).
    fn mesh_ellipsoid(&mut self, filename: &str, scale: [f64; 3]) -> Result<Ellipsoid, String> {
        let v = read_through(self.paths.as_ref(), &mut self.read, filename)?;
        let inputs = scale
            .into_iter()
            .chain(v.iter().flat_map(|p| [p.x, p.y, p.z]));
        let key = CacheKey::new(&format!("mesh-mvee tol={MESH_MVEE_TOL:e}"), inputs);
        if let Some(e) = self.solved.get(&key) {
            return Ok(*e);
        }
        let (e, unstored) = match &self.cache {
            None => (mesh_ellipsoid(v, scale)?, None),
            Some(c) => c.get_or_solve(&key, || mesh_ellipsoid(v, scale))?,
        };
        unstored.into_iter().for_each(|e| self.note_cache_error(e));
        self.solved.insert(key, e);
        Ok(e)
    }
}

/// The distinct points of a vertex list (an STL repeats each vertex for
/// every triangle that has it).
fn distinct(v: Vec<[f64; 3]>) -> Vec<Vector3<f64>> {
    let mut seen = std::collections::HashSet::with_capacity(v.len());
    v.into_iter()
        .filter(|p| seen.insert(p.map(f64::to_bits)))
        .map(Vector3::from)
        .collect()
}

/// The relative tolerance of a mesh's minimum-volume ellipsoid.
pub const MESH_MVEE_TOL: f64 = 1e-7;

/// The minimum-volume ellipsoid enclosing a mesh's vertices, scaled.
fn mesh_ellipsoid(points: &[Vector3<f64>], scale: [f64; 3]) -> Result<Ellipsoid, String> {
    let s = Vector3::from(scale);
    let scaled: Vec<Vector3<f64>> = points.iter().map(|p| p.component_mul(&s)).collect();
    Ellipsoid::minimum_volume_enclosing(&scaled, MESH_MVEE_TOL).map_err(|e| e.to_string())
}

/// Why one shape gave no bounding ellipsoid.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeNote {
    /// The reason, naming the shape (`collision 2: …`).
    pub text: String,
    /// A mesh that could not be found or read (a warning of the report,
    /// not only a note on the link).
    pub mesh: bool,
}

/// The bounding ellipsoid of one shape, in the link frame, or why there is
/// none (and whether it is a mesh that could not be used).
fn shape_ellipsoid(s: &Shape, meshes: &mut Meshes) -> Result<Ellipsoid, (bool, String)> {
    let e = match &s.geometry {
        Geometry::Box { size } => Ellipsoid::bounding_box(Vector3::from(*size)),
        Geometry::Cylinder { radius, length } => Ellipsoid::bounding_cylinder(*radius, *length),
        Geometry::Capsule { radius, length } => Ellipsoid::bounding_capsule(*radius, *length),
        Geometry::Sphere { radius } => Ellipsoid::bounding_sphere(*radius),
        Geometry::Mesh { filename, scale } => {
            let e = meshes
                .mesh_ellipsoid(filename, *scale)
                .map_err(|m| (true, format!("mesh '{filename}': {m}")))?;
            Ok(e)
        }
        Geometry::Invalid { message } => return Err((false, message.clone())),
    }
    .map_err(|e| (false, e.to_string()))?;
    let (r, p) = pose_of(&s.origin);
    Ok(e.transformed(&r, &p))
}

/// The shapes that bound a link: its collision shapes, else its visual
/// ones, and which they are.
pub fn bounded_shapes(link: &Link) -> (&[Shape], &'static str) {
    if link.collisions.is_empty() {
        (&link.visuals, "visual")
    } else {
        (&link.collisions, "collision")
    }
}

/// Bounding ellipsoids of a link's shapes (link frame), and notes on the
/// shapes that gave none; the given ones instead when
/// [`Meshes::with_bounding`] names the link. The shapes are the collision
/// ones, else the visual ones. A collision mesh that cannot be used (not
/// found, unreadable, flat) falls back to the link's visual geometry,
/// bounded with the remaining collision shapes, and its note says so; with
/// no usable visual geometry, the other collision shapes bound the link
/// alone, and the note says that too.
pub fn geometry_ellipsoids(link: &Link, meshes: &mut Meshes) -> (Vec<Ellipsoid>, Vec<ShapeNote>) {
    if let Some(es) = meshes.given.get(&link.name) {
        return (es.clone(), vec![]);
    }
    let (shapes, kind) = bounded_shapes(link);
    let (mut es, mut notes) = shapes_ellipsoids(shapes, kind, meshes);
    if kind != "collision" || !notes.iter().any(|n| n.mesh) {
        return (es, notes);
    }
    let (visual, visual_notes) = shapes_ellipsoids(&link.visuals, "visual", meshes);
    let fallback = if !visual.is_empty() && visual_notes.is_empty() {
        let names: Vec<String> = link.visuals.iter().map(shape_name).collect();
        es.extend(visual);
        format!(
            "the link's visual geometry ({}) bounds it instead",
            names.join(", ")
        )
    } else if !es.is_empty() {
        "no usable visual geometry: its other collision shapes bound the link alone".into()
    } else {
        "no usable visual geometry either: the link has no bounding ellipsoid".into()
    };
    for n in notes.iter_mut().filter(|n| n.mesh) {
        n.text = format!("{}; {fallback}", n.text);
    }
    (es, notes)
}

/// The bounding ellipsoids of `shapes` (`kind`: collision or visual, for
/// the notes) and notes on those that gave none.
fn shapes_ellipsoids(
    shapes: &[Shape],
    kind: &str,
    meshes: &mut Meshes,
) -> (Vec<Ellipsoid>, Vec<ShapeNote>) {
    let mut es = vec![];
    let mut notes = vec![];
    for (k, s) in shapes.iter().enumerate() {
        if matches!(s.geometry, Geometry::Invalid { .. }) {
            continue; // a warning of the report
        }
        match shape_ellipsoid(s, meshes) {
            Ok(e) => es.push(e),
            Err((mesh, m)) => notes.push(ShapeNote {
                text: format!("{kind} {}: {m}", k + 1),
                mesh,
            }),
        }
    }
    (es, notes)
}

/// A shape as the notes name it: its mesh's file name, or its kind.
fn shape_name(s: &Shape) -> String {
    match &s.geometry {
        Geometry::Mesh { filename, .. } => format!("mesh '{filename}'"),
        Geometry::Box { .. } => "a box".into(),
        Geometry::Cylinder { .. } => "a cylinder".into(),
        Geometry::Capsule { .. } => "a capsule".into(),
        Geometry::Sphere { .. } => "a sphere".into(),
        Geometry::Invalid { .. } => "an invalid shape".into(),
    }
}

/// Points of the link's shapes (collision, else visual; the shapes the
/// checker bounds), link frame (m), at most `max` of them (an even stride
/// through each shape's points). Shapes that cannot be read give none (the
/// checker warns about them).
pub fn geometry_points(link: &Link, meshes: &mut Meshes, max: usize) -> Vec<Vector3<f64>> {
    let (shapes, _) = bounded_shapes(link);
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
