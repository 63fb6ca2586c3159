//! The URDF inertia checker behind `momentlmi check`.
//!
//! For every link with an `<inertial>` block: mass, CoM, principal moments
//! and a [`Verdict`]; where the link has box / cylinder / sphere / capsule
//! collision geometry (visual geometry if it has no collision), whether its
//! inertia is density realizable in their bounding ellipsoids (one ellipsoid:
//! Theorem 4; several: their union, Corollary 2). A mesh's bounding
//! ellipsoid is the minimum-volume ellipsoid enclosing its vertices (scaled).
//!
//! The file is read once by the shared reader ([`crate::urdf`]) and held to
//! the same rules as the model loader ([`crate::urdf::validate`]). Input
//! errors, never panics: malformed XML, a file beyond the reader's limits,
//! duplicate names, joints that do not form one tree, an `<inertial>`
//! without `<mass>` or `<inertia>`, non-numeric or non-finite values and
//! negative masses are [`UrdfError`]s naming the file and the link or joint.
//! Shapes whose geometry cannot be used are warnings
//! ([`UrdfReport::warnings`]). Time and memory are linear in the file.

use super::check::{DEFAULT_TOL, Verdict, check_consistency, check_realizable};
use super::ellipsoid::Ellipsoid;
use super::geometry::{Meshes, geometry_ellipsoids};
use super::nearest::{NearestOptions, nearest_consistent};
use super::params::InertialParams;
use super::union::{UnionRealization, realize_on_union};
use crate::urdf::mesh::MeshPaths;
use crate::urdf::write::{apply_edits, indent_before, inertial_xml};
use crate::urdf::{Robot, UrdfError, geometry_warnings, read_file, read_str, validate};
use nalgebra::Vector3;
use serde::Serialize;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// One link's findings.
#[derive(Clone, Debug, Serialize)]
pub struct LinkReport {
    /// Link name.
    pub name: String,
    /// Mass (kg).
    pub mass: f64,
    /// CoM in the link frame (m).
    pub com: [f64; 3],
    /// Principal moments about the CoM, ascending (kg·m²).
    pub principal_moments: [f64; 3],
    /// `ok`, `placeholder`, `nonpositive_mass`, `not_positive_definite` or `triangle_violation`.
    pub status: &'static str,
    /// The worst triangle margin relative to the largest principal moment
    /// (negative: violated by that fraction).
    pub triangle_margin_rel: f64,
    /// Smallest eigenvalue of the pseudo-inertia.
    pub pseudo_inertia_min_eig: f64,
    /// Number of shapes (primitives and meshes) whose bounding ellipsoids
    /// were used.
    pub geometry_primitives: usize,
    /// Density realizable in the bounding ellipsoid(s) of the shapes
    /// (`None` without usable shapes or when the inertia is not consistent).
    pub realizable_in_geometry: Option<bool>,
    /// Shapes whose geometry could not be used, and why (a mesh not found
    /// or not readable, also in [`UrdfReport::warnings`]; a primitive
    /// without a bounding ellipsoid; a failed union solve). Unreadable or out-of-range shapes are in
    /// [`UrdfReport::warnings`] instead.
    pub geometry_notes: Vec<String>,
    /// The parameters in the paper's order (link frame).
    pub params: [f64; 10],
    /// A consistent inertia whose pseudo-inertia J is singular: `point
    /// mass` (rank 1), `rod` (rank 2) or `thin plate` (rank 3). Theorem 3's
    /// J ≻ 0 fails, Corollary 1 accepts it; simulators such as MuJoCo do
    /// not. A warning (`check --strict` makes it a finding).
    pub degenerate: Option<&'static str>,
    /// The bounding ellipsoids used for `realizable_in_geometry` (link frame).
    #[serde(rename = "bounding_ellipsoids", serialize_with = "ellipsoids_json")]
    pub(crate) ellipsoids: Vec<Ellipsoid>,
    /// Which of `geometry_notes` are meshes that could not be used.
    #[serde(skip)]
    pub(crate) mesh_notes: Vec<bool>,
    #[serde(skip)]
    pub(crate) verdict: Verdict,
    #[serde(skip)]
    pub(crate) inertial_range: Range<usize>,
}

impl LinkReport {
    /// The bounding ellipsoids of the link's shapes (link frame), one per
    /// shape that gave one.
    pub fn bounding_ellipsoids(&self) -> &[Ellipsoid] {
        &self.ellipsoids
    }

    /// The notes on meshes that could not be found or read (also in
    /// [`UrdfReport::warnings`]).
    pub fn mesh_warnings(&self) -> impl Iterator<Item = &str> {
        self.notes_where(true)
    }

    /// The notes on the other shapes that gave no bounding ellipsoid (a
    /// primitive without one, a failed union solve).
    pub fn shape_notes(&self) -> impl Iterator<Item = &str> {
        self.notes_where(false)
    }

    fn notes_where(&self, mesh: bool) -> impl Iterator<Item = &str> {
        let flag = |k: usize| self.mesh_notes.get(k).copied().unwrap_or(false);
        (0..self.geometry_notes.len())
            .filter(move |&k| flag(k) == mesh)
            .map(|k| self.geometry_notes[k].as_str())
    }

    /// The verdict.
    pub fn verdict(&self) -> Verdict {
        self.verdict
    }

    /// A one-line human status.
    pub fn describe(&self) -> String {
        match self.verdict {
            Verdict::Ok => match self.degenerate {
                Some(kind) => format!("ok, degenerate: a {kind} (J singular)"),
                None => "ok".into(),
            },
            Verdict::Placeholder => "zero placeholder (m = 0, I = 0)".into(),
            Verdict::NonpositiveMass => "non-positive mass".into(),
            Verdict::NotPositiveDefinite => "inertia not positive definite".into(),
            Verdict::TriangleViolation => {
                format!(
                    "violates the triangle inequality by {:.3} %",
                    -100.0 * self.triangle_margin_rel
                )
            }
        }
    }
}

/// Ellipsoids as `{center, semi_axes, rotation}` (rotation: rows of the
/// matrix whose columns are the axes).
fn ellipsoids_json<S: serde::Serializer>(es: &[Ellipsoid], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeSeq;
    let mut seq = s.serialize_seq(Some(es.len()))?;
    for e in es {
        let r = e.rotation;
        seq.serialize_element(&serde_json::json!({
            "center": [e.center.x, e.center.y, e.center.z],
            "semi_axes": [e.semi_axes.x, e.semi_axes.y, e.semi_axes.z],
            "rotation": (0..3).map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]).collect::<Vec<_>>(),
        }))?;
    }
    seq.end()
}

/// Which degenerate body a consistent π is, from the rank of J (eigenvalues
/// above 1e-10 of the largest).
fn degeneracy(pi: &InertialParams) -> Option<&'static str> {
    let eig = nalgebra::SymmetricEigen::new(pi.pseudo_inertia()).eigenvalues;
    let top = eig.iter().fold(0.0f64, |a, &x| a.max(x));
    match eig.iter().filter(|&&x| x > 1e-10 * top).count() {
        1 => Some("point mass"),
        2 => Some("rod"),
        3 => Some("thin plate"),
        _ => None,
    }
}

/// A warning of the URDF check.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum CheckWarning {
    /// The robot has no link: nothing to check.
    NoLink,
    /// A shape that cannot be used.
    Geometry(crate::urdf::GeometryWarning),
    /// A mesh that could not be found or read.
    Mesh {
        /// The link.
        link: String,
        /// Why.
        note: String,
    },
}

impl std::fmt::Display for CheckWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CheckWarning::NoLink => f.write_str("the <robot> has no <link>: nothing to check"),
            CheckWarning::Geometry(g) => g.fmt(f),
            CheckWarning::Mesh { link, note } => write!(f, "link '{link}': {note}"),
        }
    }
}

/// The whole robot's findings.
#[derive(Clone, Debug, Serialize)]
pub struct UrdfReport {
    /// Robot name.
    pub robot: String,
    /// One report per link with an `<inertial>` block, in file order.
    pub links: Vec<LinkReport>,
    /// Links without `<inertial>` (massless frames).
    pub links_without_inertial: Vec<String>,
    /// Shapes whose origin or geometry cannot be read or is out of range
    /// ([`geometry_warnings`]), meshes that could not be used, a robot with
    /// no link; in the JSON each with its `kind` and `message`.
    #[serde(serialize_with = "crate::warning::with_messages")]
    pub warnings: Vec<CheckWarning>,
    /// Some link has an `<inertial>`, and every one is `ok` or a
    /// `placeholder` (false when there is nothing to check).
    pub consistent: bool,
}

impl UrdfReport {
    /// No link has an `<inertial>`: nothing was checked.
    pub fn nothing_to_check(&self) -> bool {
        self.links.is_empty()
    }
}

/// Whether π is density realizable in the ellipsoids (one: Theorem 4;
/// several: their union, Corollary 2); `None` when there are none.
fn realizable_in(pi: &InertialParams, ellipsoids: &[Ellipsoid]) -> Result<Option<bool>, String> {
    match ellipsoids {
        [] => Ok(None),
        [e] => Ok(Some(check_realizable(pi, e, 1e-9).realizable)),
        many => realize_on_union(pi, many)
            .map(|r| Some(matches!(r, UnionRealization::Realizable(_))))
            .map_err(|e| format!("the union test failed: {e}")),
    }
}

/// One link's report (`None`: no `<inertial>`); the link has passed
/// [`validate`].
fn link_report(link: &crate::urdf::Link, meshes: &mut Meshes) -> Option<LinkReport> {
    let inertial = link.inertial.as_ref()?;
    let pi = InertialParams::from_urdf(
        inertial.mass,
        inertial.origin.xyz,
        inertial.origin.rpy,
        inertial.inertia,
    );
    let (ellipsoids, notes) = geometry_ellipsoids(link, meshes);
    let mesh_notes: Vec<bool> = notes.iter().map(|n| n.mesh).collect();
    let mut geometry_notes: Vec<String> = notes.into_iter().map(|n| n.text).collect();
    let rep = check_consistency(&pi, DEFAULT_TOL);
    let realizable = if rep.consistent {
        realizable_in(&pi, &ellipsoids).unwrap_or_else(|m| {
            geometry_notes.push(m);
            None
        })
    } else {
        None
    };
    let com = if pi.mass() > 0.0 {
        pi.com()
    } else {
        Vector3::zeros()
    };
    let degenerate = (rep.verdict == Verdict::Ok)
        .then(|| degeneracy(&pi))
        .flatten();
    Some(LinkReport {
        degenerate,
        name: link.name.clone(),
        mass: pi.mass(),
        com: [com.x, com.y, com.z],
        principal_moments: rep.principal_moments,
        status: rep.verdict.as_str(),
        triangle_margin_rel: rep.triangle_margin_rel(),
        pseudo_inertia_min_eig: rep.pseudo_inertia_min_eig,
        geometry_primitives: ellipsoids.len(),
        realizable_in_geometry: realizable,
        geometry_notes,
        mesh_notes,
        params: pi.0,
        verdict: rep.verdict,
        ellipsoids,
        inertial_range: inertial.range.clone(),
    })
}

/// Checks a robot read by [`crate::urdf`] (first against [`validate`]);
/// `path` names it in messages. No mesh is read ([`check_robot_with`]).
pub fn check_robot(robot: &Robot, path: &str) -> Result<UrdfReport, UrdfError> {
    check_robot_with(robot, path, &mut Meshes::none())
}

/// [`check_robot`] with the bounding volumes of mesh shapes too; a mesh that
/// cannot be found or read is a warning naming the link, never a failure.
pub fn check_robot_with(
    robot: &Robot,
    path: &str,
    meshes: &mut Meshes,
) -> Result<UrdfReport, UrdfError> {
    if robot.links.is_empty() {
        // nothing to check is a finding (exit 1), not an unreadable file
        return Ok(UrdfReport {
            robot: robot.name.clone(),
            links: vec![],
            links_without_inertial: vec![],
            warnings: vec![CheckWarning::NoLink],
            consistent: false,
        });
    }
    validate(robot, path)?;
    let mut links = Vec::new();
    let mut without = Vec::new();
    let mut warnings: Vec<CheckWarning> = geometry_warnings(robot)
        .into_iter()
        .map(CheckWarning::Geometry)
        .collect();
    for l in &robot.links {
        let report = link_report(l, meshes);
        if let Some(r) = &report
            && meshes.paths.is_some()
        {
            warnings.extend(r.mesh_warnings().map(|n| CheckWarning::Mesh {
                link: l.name.clone(),
                note: n.to_string(),
            }));
        }
        match report {
            Some(r) => links.push(r),
            None => without.push(l.name.clone()),
        }
    }
    let consistent = !links.is_empty()
        && links
            .iter()
            .all(|l| matches!(l.verdict, Verdict::Ok | Verdict::Placeholder));
    Ok(UrdfReport {
        robot: robot.name.clone(),
        links,
        links_without_inertial: without,
        warnings,
        consistent,
    })
}

/// Checks the URDF text; `path` names it in messages.
pub fn check_urdf_str(text: &str, path: &str) -> Result<UrdfReport, UrdfError> {
    check_robot(&read_str(text, path)?, path)
}

/// Reads and checks a URDF file with its meshes (found beside it, in
/// `package_paths` and in `ROS_PACKAGE_PATH`); also returns its text (for
/// [`repair_urdf`]).
pub fn check_urdf_file(
    path: &Path,
    package_paths: &[PathBuf],
) -> Result<(String, UrdfReport), UrdfError> {
    let mut meshes = Meshes::new(MeshPaths::for_urdf(path, package_paths));
    check_urdf_file_with(path, &mut meshes).map(|(text, _, rep)| (text, rep))
}

/// [`check_urdf_file`] with the caller's [`Meshes`] (kept for more use,
/// e.g. [`geometry_points`](super::geometry::geometry_points)); also
/// returns the robot read.
pub fn check_urdf_file_with(
    path: &Path,
    meshes: &mut Meshes,
) -> Result<(String, Robot, UrdfReport), UrdfError> {
    let (text, robot) = read_file(path)?;
    let rep = check_robot_with(&robot, &path.display().to_string(), meshes)?;
    Ok((text, robot, rep))
}

/// The note [`repair_urdf`] adds to a consistent link it leaves as it is
/// (no inertia inside its bounding volume found).
pub const LEFT_AS_IS: &str =
    "(left as it is: no nearby inertia inside its geometry's bounding volume was found)";

/// What `check --repair` projects an inertial onto.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "clap",
    derive(clap::ValueEnum),
    value(rename_all = "snake_case")
)]
pub enum RepairTarget {
    /// Repair the inconsistent inertials (inside the link's geometry when
    /// that is possible, else consistent only, with a note).
    #[default]
    Consistent,
    /// Also repair consistent inertials that are not density realizable in
    /// the link's bounding volume (the union of its shapes' ellipsoids).
    Geometry,
}

/// How `check --repair` repairs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RepairOptions {
    /// What to project onto.
    pub target: RepairTarget,
    /// The relative margin ε of [`NearestOptions::eps`] (default 1e-6). A
    /// projection lands on the boundary of its set, often a rod or a thin
    /// plate; a margin such as 1e-3 keeps the repaired body's thinnest
    /// direction at about √ε of the length scale.
    pub margin: f64,
}

impl Default for RepairOptions {
    fn default() -> Self {
        Self {
            target: RepairTarget::Consistent,
            margin: 1e-6,
        }
    }
}

impl RepairTarget {
    /// Whether a link's inertial is repaired.
    fn wants(self, rep: &LinkReport) -> bool {
        match rep.verdict {
            Verdict::TriangleViolation | Verdict::NotPositiveDefinite => true,
            Verdict::Ok => self == Self::Geometry && rep.realizable_in_geometry == Some(false),
            Verdict::Placeholder | Verdict::NonpositiveMass => false,
        }
    }
}

/// The nearest consistent π to a link's inertial (mass kept), inside the
/// union of its bounding ellipsoids when it has some and that succeeds, and
/// a note when the geometry had to be dropped.
fn nearest_for(
    rep: &LinkReport,
    path: &str,
    margin: f64,
) -> Result<(InertialParams, Option<&'static str>), UrdfError> {
    let pi = InertialParams(rep.params);
    let fail = |e: String| UrdfError::Link {
        path: path.into(),
        link: rep.name.clone(),
        message: format!("repair failed: {e}"),
    };
    let opts = NearestOptions {
        within: rep.ellipsoids.clone(),
        eps: margin,
        ..Default::default()
    };
    let outside = Some("not inside its geometry's bounding volume");
    match nearest_consistent(&pi, &opts) {
        Ok(f)
            if matches!(
                realizable_in(&f.params, &rep.ellipsoids),
                Ok(None | Some(true))
            ) =>
        {
            Ok((f.params, None))
        }
        Ok(_) | Err(_) if !rep.ellipsoids.is_empty() => {
            let plain = NearestOptions {
                eps: margin,
                ..Default::default()
            };
            let f = nearest_consistent(&pi, &plain).map_err(|e| fail(e.to_string()))?;
            Ok((f.params, outside))
        }
        Ok(f) => Ok((f.params, None)),
        Err(e) => Err(fail(e.to_string())),
    }
}

/// [`nearest_for`] as URDF text indented like the element it replaces.
fn repaired_inertial(
    text: &str,
    rep: &LinkReport,
    path: &str,
    margin: f64,
) -> Result<(String, Option<&'static str>), UrdfError> {
    let (fixed, note) = nearest_for(rep, path, margin)?;
    let (m, c, i) = fixed.to_urdf();
    let pad = indent_before(text, rep.inertial_range.start);
    let what = match note {
        None if !rep.ellipsoids.is_empty() => "nearest inertia density realizable in its geometry",
        _ => "nearest physically consistent inertia",
    };
    let comment = format!("repaired by momentlmi check: {what}");
    Ok((inertial_xml(pad, &comment, m, c, i), note))
}

/// The URDF text with every inconsistent (non-placeholder, positive-mass)
/// inertial, and with [`RepairTarget::Geometry`] every one not realizable in
/// its link's bounding volume, replaced by the nearest one that is (mass
/// kept, strict margin [`RepairOptions::margin`], see [`nearest_consistent`]). Everything else in
/// the file is kept byte for byte. `report` must come from this `text`
/// (checked). Returns the text and the repaired links (with a note where the
/// repair could not keep the link inside its bounding volume; a consistent
/// link for which no inertia inside its volume was found is left as it is
/// and named so).
pub fn repair_urdf(
    text: &str,
    report: &UrdfReport,
    path: &str,
    opts: &RepairOptions,
) -> Result<(String, Vec<String>), UrdfError> {
    let mut edits: Vec<(Range<usize>, String)> = Vec::new();
    let mut repaired = Vec::new();
    for rep in &report.links {
        if !opts.target.wants(rep) {
            continue;
        }
        let r = rep.inertial_range.clone();
        if !text
            .get(r.clone())
            .is_some_and(|s| s.starts_with("<inertial"))
        {
            return Err(UrdfError::Link {
                path: path.into(),
                link: rep.name.clone(),
                message:
                    "the report is not of this text (its <inertial> is not where the report says)"
                        .into(),
            });
        }
        let (xml, note) = repaired_inertial(text, rep, path, opts.margin)?;
        if note.is_some() && rep.verdict == Verdict::Ok {
            // consistent already, and no inertia inside its geometry found:
            // the nearest consistent one would be itself; left as it is
            repaired.push(format!("{} {LEFT_AS_IS}", rep.name));
            continue;
        }
        edits.push((r, xml));
        repaired.push(match note {
            Some(n) => format!("{} ({n})", rep.name),
            None => rep.name.clone(),
        });
    }
    // one pass, in file order (replacing in place would move the rest of
    // the text once per edit)
    let out = apply_edits(text, edits).ok_or_else(|| UrdfError::Robot {
        path: path.into(),
        message: "the report is not of this text (two of its <inertial> elements overlap)".into(),
    })?;
    Ok((out, repaired))
}
