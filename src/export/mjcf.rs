//! A MuJoCo model (MJCF) of a [`MujocoView`]: one `<body>` per model body
//! (a URDF link and the links merged into it by fixed or locked joints:
//! a locked joint is simply absent), placed by its joint frame, with
//! - `<inertial pos quat mass diaginertia>`: the CoM, the principal axes
//!   of the inertia about it (`quat`, w x y z, body frame) and the
//!   principal moments;
//! - a `hinge` or `slide` joint with its axis, `range` (finite limits),
//!   `armature`, `damping` and `frictionloss`;
//! - the links' collision shapes (visual ones for a link without any) as
//!   geoms; meshes referenced by their absolute path, STL, OBJ and MSH
//!   only (the formats MuJoCo reads: others are left out, noted);
//!
//! a free-flying root as a body with a `<freejoint>` (its qpos the base
//! position and quaternion w x y z, its qvel the linear velocity in world
//! axes and the angular velocity in the base's: docs/export.md), a
//! `<motor>` per joint (gear 1, unlimited: `ctrl` is the joint torque),
//! gravity, a 1 ms time step, and a joint `<equality>` per URDF `<mimic>`
//! (q = multiplier · q_leader + offset; momentlmi itself treats such
//! joints as free). `<compiler inertiafromgeom="false">`: the geoms add no
//! mass.

use super::error::ExportError;
use super::mujoco::MujocoView;
use crate::dynamics::spatial::Transform;
use crate::dynamics::{JointKind, Model};
use crate::moments::{InertialParams, rpy_rotation};
use crate::urdf::mesh::MeshPaths;
use crate::urdf::{Geometry, Pose, Robot, Shape};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use std::fmt::Write as _;

/// The written model and what it left out.
pub struct Mjcf {
    /// The MJCF text.
    pub text: String,
    /// What was left out (meshes MuJoCo cannot read, the view's notes).
    pub notes: Vec<String>,
}

/// The URDF's shapes, for geoms: the robot as read and where its meshes are.
pub struct Shapes<'a> {
    /// The URDF, read.
    pub robot: &'a Robot,
    /// Where its `package://` meshes are.
    pub meshes: &'a MeshPaths,
}

/// The smallest mass and principal moment MuJoCo takes for a moving body
/// (its `mjMINVAL`).
const MIN_VALUE: f64 = 1e-15;

/// Writes `view` (made from `full`, whose bodies, frames and limits it
/// uses) as MJCF, with the URDF's shapes as geoms when given. A moving
/// body MuJoCo would refuse (mass or a principal moment ≤ 1e-15, or
/// principal moments breaking A + B ≥ C beyond rounding: not physically
/// consistent) is an error naming it.
pub fn mjcf(view: &MujocoView, full: &Model, shapes: Option<&Shapes>) -> Result<Mjcf, ExportError> {
    let model = &view.model;
    let mut w = Writer {
        text: String::new(),
        assets: String::new(),
        notes: view.notes.clone(),
        meshes: 0,
    };
    let g = model.gravity;
    let _ = writeln!(
        w.text,
        "  <option gravity=\"{:e} {:e} {:e}\" timestep=\"0.001\"/>",
        g.x, g.y, g.z
    );
    let mut world = String::new();
    match model.base() {
        None => w.root_children(&mut world, view, shapes, "    ")?,
        Some(base) => {
            // a free-flying root: the base body with a free joint
            let _ = writeln!(world, "    <body name=\"{}\">", escape(&base.name));
            let _ = writeln!(world, "      <freejoint name=\"{}\"/>", escape(&base.name));
            let _ = writeln!(
                world,
                "      {}",
                inertial(&base.name, &base.inertia, true)?
            );
            w.root_children(&mut world, view, shapes, "      ")?;
            let _ = writeln!(world, "    </body>");
        }
    }
    let name = escape(&full.name);
    let mut text = format!(
        "<mujoco model=\"{name}\">\n  <!-- written by momentlmi: the identified model as MuJoCo holds it (docs/export.md) -->\n"
    );
    for n in &w.notes {
        let _ = writeln!(text, "  <!-- left out: {} -->", escape(n));
    }
    text += "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
    text += &w.text;
    if !w.assets.is_empty() {
        let _ = write!(text, "  <asset>\n{}  </asset>\n", w.assets);
    }
    let _ = write!(text, "  <worldbody>\n{world}  </worldbody>\n");
    text += &actuators_and_mimics(model, shapes);
    text += "</mujoco>\n";
    Ok(Mjcf {
        text,
        notes: w.notes,
    })
}

struct Writer {
    text: String,
    assets: String,
    notes: Vec<String>,
    meshes: usize,
}

impl Writer {
    /// The geoms of the links on the base and the bodies hanging from it,
    /// indented by `pad`.
    fn root_children(
        &mut self,
        out: &mut String,
        view: &MujocoView,
        shapes: Option<&Shapes>,
        pad: &str,
    ) -> Result<(), ExportError> {
        self.geoms(out, &view.model, None, shapes, pad)?;
        for (b, joint) in view.model.joints.iter().enumerate() {
            if joint.parent.is_none() {
                self.body(out, view, b, shapes, pad)?;
            }
        }
        Ok(())
    }

    /// Body `b` and its subtree, indented by `pad`.
    fn body(
        &mut self,
        out: &mut String,
        view: &MujocoView,
        b: usize,
        shapes: Option<&Shapes>,
        pad: &str,
    ) -> Result<(), ExportError> {
        let model = &view.model;
        let j = &model.joints[b];
        let x = &j.x_tree;
        let _ = writeln!(
            out,
            "{pad}<body name=\"{}\" {}>",
            escape(&j.body),
            placement(x)
        );
        let inner = format!("{pad}  ");
        let _ = writeln!(out, "{inner}{}", inertial(&j.body, &j.inertia, true)?);
        let kind = match j.kind {
            JointKind::Revolute => "hinge",
            JointKind::Prismatic => "slide",
        };
        let a = j.axis;
        let mut attrs = format!(
            "name=\"{}\" type=\"{kind}\" axis=\"{:e} {:e} {:e}\" armature=\"{:e}\" damping=\"{:e}\" frictionloss=\"{:e}\"",
            escape(&j.name),
            a.x,
            a.y,
            a.z,
            view.armature[b],
            view.damping[b],
            view.frictionloss[b]
        );
        if j.limits.0.is_finite() && j.limits.1.is_finite() {
            let _ = write!(
                attrs,
                " limited=\"true\" range=\"{:e} {:e}\"",
                j.limits.0, j.limits.1
            );
        }
        let _ = writeln!(out, "{inner}<joint {attrs}/>");
        self.geoms(out, model, Some(b), shapes, &inner)?;
        for (c, child) in model.joints.iter().enumerate() {
            if child.parent == Some(b) {
                self.body(out, view, c, shapes, &inner)?;
            }
        }
        let _ = writeln!(out, "{pad}</body>");
        Ok(())
    }

    /// The geoms of every URDF link on `body` (`None`: the base).
    fn geoms(
        &mut self,
        out: &mut String,
        model: &Model,
        body: Option<usize>,
        shapes: Option<&Shapes>,
        pad: &str,
    ) -> Result<(), ExportError> {
        let Some(shapes) = shapes else { return Ok(()) };
        for f in model.frames.iter().filter(|f| f.body == body) {
            let Some(link) = shapes.robot.links.iter().find(|l| l.name == f.name) else {
                continue;
            };
            let list = if link.collisions.is_empty() {
                &link.visuals
            } else {
                &link.collisions
            };
            for s in list {
                if let Some(g) = self.geom(s, &f.placement, shapes, &link.name) {
                    let _ = writeln!(out, "{pad}{g}");
                }
            }
        }
        Ok(())
    }

    /// A geom for shape `s` of link `link` placed by `x` (body → link).
    fn geom(&mut self, s: &Shape, x: &Transform, shapes: &Shapes, link: &str) -> Option<String> {
        let at = placement(&pose(&s.origin).compose(x));
        let shape = match &s.geometry {
            Geometry::Box { size } => format!(
                "type=\"box\" size=\"{:e} {:e} {:e}\"",
                size[0] / 2.0,
                size[1] / 2.0,
                size[2] / 2.0
            ),
            Geometry::Cylinder { radius, length } => {
                format!("type=\"cylinder\" size=\"{radius:e} {:e}\"", length / 2.0)
            }
            Geometry::Capsule { radius, length } => {
                format!("type=\"capsule\" size=\"{radius:e} {:e}\"", length / 2.0)
            }
            Geometry::Sphere { radius } => format!("type=\"sphere\" size=\"{radius:e}\""),
            Geometry::Mesh { filename, scale } => {
                let name = self.mesh(filename, scale, shapes, link)?;
                format!("type=\"mesh\" mesh=\"{name}\"")
            }
            Geometry::Invalid { message } => {
                self.notes
                    .push(format!("a shape of link '{link}': {message}"));
                return None;
            }
        };
        Some(format!("<geom {shape} {at}/>"))
    }

    /// The asset name of a mesh MuJoCo can read, added to the assets.
    fn mesh(
        &mut self,
        filename: &str,
        scale: &[f64; 3],
        shapes: &Shapes,
        link: &str,
    ) -> Option<String> {
        let path = match shapes.meshes.resolve(filename) {
            Ok(p) => p,
            Err(e) => {
                self.notes.push(format!("mesh of link '{link}': {e}"));
                return None;
            }
        };
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        if !matches!(ext.as_str(), "stl" | "obj" | "msh") {
            self.notes.push(format!(
                "mesh {} of link '{link}': MuJoCo reads STL, OBJ and MSH only",
                path.display()
            ));
            return None;
        }
        if ext == "stl" && ascii_stl(&path) {
            self.notes.push(format!(
                "mesh {} of link '{link}': an ASCII STL (MuJoCo reads binary STL only)",
                path.display()
            ));
            return None;
        }
        let path = std::fs::canonicalize(&path).unwrap_or(path);
        let name = format!("mesh{}", self.meshes);
        self.meshes += 1;
        let _ = writeln!(
            self.assets,
            "    <mesh name=\"{name}\" file=\"{}\" scale=\"{:e} {:e} {:e}\" inertia=\"shell\"/>",
            escape(&path.display().to_string()),
            scale[0],
            scale[1],
            scale[2]
        );
        Some(name)
    }
}

/// Whether an STL file is ASCII: it starts with `solid` and its size is
/// not the binary format's (84 + 50 bytes per triangle, the count at byte 80).
fn ascii_stl(path: &std::path::Path) -> bool {
    use std::io::Read;
    let Ok(mut f) = std::fs::File::open(path) else {
        return false;
    };
    let mut head = [0u8; 84];
    if f.read_exact(&mut head).is_err() {
        return head.starts_with(b"solid");
    }
    let count = u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64;
    let size = std::fs::metadata(path).map_or(0, |m| m.len());
    head.starts_with(b"solid") && size != 84 + 50 * count
}

/// `pos="…" quat="…"` of frame B given X (A → B).
fn placement(x: &Transform) -> String {
    let q = quat(&x.e.transpose());
    format!(
        "pos=\"{:e} {:e} {:e}\" quat=\"{:e} {:e} {:e} {:e}\"",
        x.r.x, x.r.y, x.r.z, q[0], q[1], q[2], q[3]
    )
}

/// The quaternion (w, x, y, z) of a rotation matrix.
fn quat(r: &Matrix3<f64>) -> [f64; 4] {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r));
    [q.w, q.i, q.j, q.k]
}

fn pose(p: &Pose) -> Transform {
    Transform::from_pose(&rpy_rotation(p.rpy), &Vector3::from(p.xyz))
}

/// `<inertial>` of body `name` with parameters `p` (its frame), checked to
/// be one MuJoCo takes when the body moves.
fn inertial(name: &str, p: &InertialParams, moving: bool) -> Result<String, ExportError> {
    let bad = |message: String| ExportError::Body {
        body: name.into(),
        message,
    };
    let m = p.to_mass_com_inertia();
    if !(m.mass > MIN_VALUE) && moving {
        return Err(bad(format!(
            "mass {:e} kg: MuJoCo needs a moving body's mass above 1e-15",
            m.mass
        )));
    }
    let eig = m.inertia_com.symmetric_eigen();
    let mut axes = eig.eigenvectors;
    if axes.determinant() < 0.0 {
        axes.set_column(2, &(-axes.column(2)));
    }
    let mut d = [eig.eigenvalues[0], eig.eigenvalues[1], eig.eigenvalues[2]];
    balanced(&mut d).map_err(bad)?;
    let q = quat(&axes);
    let c = m.com;
    Ok(format!(
        "<inertial pos=\"{:e} {:e} {:e}\" quat=\"{:e} {:e} {:e} {:e}\" mass=\"{:e}\" diaginertia=\"{:e} {:e} {:e}\"/>",
        c.x, c.y, c.z, q[0], q[1], q[2], q[3], m.mass, d[0], d[1], d[2]
    ))
}

/// Principal moments MuJoCo takes: each above 1e-15 and A + B ≥ C; a
/// breach within rounding (1e-9 of the largest) is closed (C = A + B).
fn balanced(d: &mut [f64; 3]) -> Result<(), String> {
    let top = d.iter().fold(0.0f64, |a, &b| a.max(b));
    if d.iter().any(|&x| !(x > MIN_VALUE)) {
        return Err(format!(
            "principal moments {d:?} kg·m²: MuJoCo needs each above 1e-15 (a point mass or rod: identify at the ellipsoid level or with a prior)"
        ));
    }
    for k in 0..3 {
        let (a, b) = (d[(k + 1) % 3], d[(k + 2) % 3]);
        if a + b < d[k] {
            if d[k] - (a + b) > 1e-9 * top {
                return Err(format!(
                    "principal moments {d:?} kg·m² break A + B ≥ C: not physically consistent"
                ));
            }
            d[k] = a + b;
        }
    }
    Ok(())
}

/// `<actuator>` (a motor per joint) and `<equality>` (a joint equality per
/// URDF mimic between two model joints).
fn actuators_and_mimics(model: &Model, shapes: Option<&Shapes>) -> String {
    let mut s = String::from("  <actuator>\n");
    for j in &model.joints {
        let n = escape(&j.name);
        let _ = writeln!(s, "    <motor name=\"{n}\" joint=\"{n}\" gear=\"1\"/>");
    }
    s += "  </actuator>\n";
    let is_joint = |n: &str| model.joints.iter().any(|j| j.name == n);
    let mimics: Vec<String> = shapes
        .map(|sh| sh.robot.joints.iter())
        .into_iter()
        .flatten()
        .filter_map(|j| Some((j, j.mimic.as_ref()?)))
        .filter(|(j, m)| is_joint(&j.name) && is_joint(&m.joint))
        .map(|(j, m)| {
            format!(
                "    <joint joint1=\"{}\" joint2=\"{}\" polycoef=\"{:e} {:e} 0 0 0\"/>\n",
                escape(&j.name),
                escape(&m.joint),
                m.offset,
                m.multiplier
            )
        })
        .collect();
    if !mimics.is_empty() {
        s += &format!("  <equality>\n{}  </equality>\n", mimics.concat());
    }
    s
}

/// Text for an XML attribute value.
pub(super) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
