//! A robot's bounding volumes, computed when first needed: the sidecar's
//! ellipsoids at once, those of a URDF's geometry (meshes read, minimum-
//! volume ellipsoids solved) only when something asks for them — the
//! ellipsoid constraint level, a plot — so that a command which does not use
//! them pays nothing for them.

use super::model::Model;
use super::warning::DescriptionWarning;
use crate::moments::Ellipsoid;
use crate::moments::cache::{CacheKey, SolveCache};
use crate::moments::geometry::{Meshes, geometry_ellipsoids};
use crate::urdf::mesh::MeshPaths;
use std::collections::HashMap;
use std::fmt;
use std::sync::{Arc, OnceLock};

/// Bounding ellipsoids per body (links then rotors, body frames; several:
/// their union; none: unknown). Clones share what was computed.
#[derive(Clone)]
pub struct Bounding {
    given: Vec<Vec<Ellipsoid>>,
    geometry: Option<Arc<(crate::urdf::Robot, MeshPaths)>>,
    cache: Option<SolveCache>,
    computed: Arc<OnceLock<Computed>>,
}

/// What the geometry gave: the ellipsoids and the warnings on the way.
#[derive(Debug)]
struct Computed {
    per_body: Vec<Vec<Ellipsoid>>,
    warnings: Vec<DescriptionWarning>,
}

impl Bounding {
    /// The ellipsoids given per body (a sidecar's), and no geometry.
    pub fn given(given: Vec<Vec<Ellipsoid>>) -> Self {
        Self {
            given,
            geometry: None,
            cache: None,
            computed: Arc::new(OnceLock::new()),
        }
    }

    /// The geometry's ellipsoids are kept in, and taken from, `cache`
    /// across runs ([`crate::moments::cache`]); before they are computed.
    pub fn with_cache(self, cache: SolveCache) -> Self {
        Self {
            cache: Some(cache),
            computed: Arc::new(OnceLock::new()),
            ..self
        }
    }

    /// The given ellipsoids, and for the link bodies without one the
    /// geometry of `robot`'s links, its meshes found through `paths`
    /// (computed on first use).
    pub fn with_urdf(self, robot: crate::urdf::Robot, paths: MeshPaths) -> Self {
        Self {
            geometry: Some(Arc::new((robot, paths))),
            computed: Arc::new(OnceLock::new()),
            ..self
        }
    }

    /// Every body's bounding ellipsoids (computing the geometry's on first
    /// call); `model` is the robot's.
    pub fn get(&self, model: &Model) -> &[Vec<Ellipsoid>] {
        match &self.geometry {
            None => &self.given,
            Some(_) => &self.computed(model).per_body,
        }
    }

    /// What the geometry could not give (computing it on first call): a
    /// mesh that could not be used, a body with no ellipsoid.
    pub fn warnings(&self, model: &Model) -> &[DescriptionWarning] {
        match &self.geometry {
            None => &[],
            Some(_) => &self.computed(model).warnings,
        }
    }

    /// Whether the geometry's ellipsoids have been computed (or there is
    /// no geometry to compute them from).
    pub fn is_resolved(&self) -> bool {
        self.geometry.is_none() || self.computed.get().is_some()
    }

    fn computed(&self, model: &Model) -> &Computed {
        self.computed.get_or_init(|| {
            let (robot, paths) = &**self.geometry.as_ref().expect("called with geometry");
            let mut meshes = Meshes::new(paths.clone());
            if let Some(c) = &self.cache {
                meshes = meshes.with_cache(c.clone());
            }
            compute(&self.given, model, robot, &mut meshes)
        })
    }
}

/// The ellipsoid enclosing the bounding ellipsoids of the shapes of every
/// URDF link merged into each body without a given one (in the body's
/// frame); [`geometry_ellipsoids`] says which shapes and how a missing mesh
/// falls back.
fn compute(
    given: &[Vec<Ellipsoid>],
    model: &Model,
    robot: &crate::urdf::Robot,
    meshes: &mut Meshes,
) -> Computed {
    let mut per_body = given.to_vec();
    let mut warnings = vec![];
    let mut parts: Vec<Vec<Ellipsoid>> = vec![vec![]; model.num_bodies()];
    let links: HashMap<&str, &crate::urdf::Link> =
        robot.links.iter().map(|l| (l.name.as_str(), l)).collect();
    for f in &model.frames {
        let (Some(b), Some(link)) = (model.body_of_frame(f), links.get(f.name.as_str())) else {
            continue;
        };
        if !given[b].is_empty() {
            continue; // the sidecar's volume stands; its meshes are not read
        }
        let (es, notes) = geometry_ellipsoids(link, meshes);
        warnings.extend(
            notes
                .iter()
                .filter(|n| n.mesh)
                .map(|n| DescriptionWarning::Mesh {
                    link: f.name.clone(),
                    note: n.text.clone(),
                }),
        );
        // x_body = Eᵀ x_link + r
        let (e, r) = (f.placement.e.transpose(), f.placement.r);
        parts[b].extend(es.iter().map(|x| x.transformed(&e, &r)));
    }
    // one covering ellipsoid (an SDP) per body, in parallel
    let covers: Vec<_> = {
        use rayon::prelude::*;
        (parts.par_iter().enumerate())
            .filter(|(_, p)| !p.is_empty())
            .map(|(b, p)| (b, cover(p, meshes.cache())))
            .collect()
    };
    for (b, cover) in covers {
        match cover {
            Ok((e, stored)) => {
                per_body[b] = vec![e];
                stored.into_iter().for_each(|e| meshes.note_cache_error(e));
            }
            Err(m) => warnings.push(DescriptionWarning::NoBoundingEllipsoid {
                body: model.body_names()[b].clone(),
                reason: m.to_string(),
            }),
        }
    }
    if let Some(reason) = meshes.cache_error() {
        let reason = reason.to_string();
        warnings.push(DescriptionWarning::Cache { reason });
    }
    Computed { per_body, warnings }
}

/// The ellipsoid enclosing a body's `parts`, from `cache` when it holds
/// them (several parts: a conic solve), and a failure to store it.
fn cover(
    parts: &[Ellipsoid],
    cache: Option<&SolveCache>,
) -> Result<(Ellipsoid, Option<std::io::Error>), crate::moments::MomentsError> {
    match (parts, cache) {
        ([_, _, ..], Some(c)) => {
            let key = CacheKey::of_ellipsoids("cover", parts);
            c.get_or_solve(&key, || Ellipsoid::enclosing(parts))
        }
        _ => Ellipsoid::enclosing(parts).map(|e| (e, None)),
    }
}

impl fmt::Debug for Bounding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Bounding")
            .field("given", &self.given)
            .field("from_urdf", &self.geometry.is_some())
            .field("computed", &self.computed.get())
            .finish()
    }
}

/// Equal when the same ellipsoids are given and the same geometry (the
/// same URDF robot and mesh folders) gives the rest; nothing is computed.
impl PartialEq for Bounding {
    fn eq(&self, other: &Self) -> bool {
        self.given == other.given
            && match (&self.geometry, &other.geometry) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, b) || (a.0 == b.0 && a.1 == b.1),
                _ => false,
            }
    }
}
