//! A URDF written from a model alone (a built-in robot has no URDF): a
//! `base` link, and per body a link (its identified `<inertial>`, no
//! shapes) and a joint (origin, axis, limits, `<dynamics>`).

use super::checks::urdf_inertial;
use super::error::ExportError;
use crate::dynamics::{Friction, JointKind, Model};
use crate::urdf::write::inertial_xml;
use nalgebra::Rotation3;
use std::fmt::Write as _;

/// The base link's name (or, if a body has that name, `world`).
fn base_name(model: &Model) -> &'static str {
    let taken = |n: &str| model.joints.iter().any(|j| j.body == n);
    if taken("base") { "world" } else { "base" }
}

/// The URDF text of `model` with `friction` (see the module).
pub fn urdf_of_model(model: &Model, friction: &Friction) -> Result<String, ExportError> {
    let base = base_name(model);
    let mut s = format!(
        "<?xml version=\"1.0\"?>\n<robot name=\"{}\">\n  <!-- written by momentlmi from the built-in model: rotors and friction terms beyond <dynamics> are in the sidecar beside it -->\n  <link name=\"{base}\"/>\n",
        super::mjcf::escape(&model.name)
    );
    for (b, j) in model.joints.iter().enumerate() {
        let (m, c, i) = urdf_inertial(&j.body, &j.inertia)?;
        let inertial = inertial_xml("    ", "identified by momentlmi", m, c, i);
        let _ = writeln!(
            s,
            "  <link name=\"{}\">\n    {inertial}\n  </link>",
            super::mjcf::escape(&j.body)
        );
        let parent = j.parent.map_or(base, |p| model.joints[p].body.as_str());
        let kind = match (j.kind, j.limits.0.is_finite() && j.limits.1.is_finite()) {
            (JointKind::Prismatic, _) => "prismatic",
            (JointKind::Revolute, true) => "revolute",
            (JointKind::Revolute, false) => "continuous",
        };
        let (roll, pitch, yaw) =
            Rotation3::from_matrix_unchecked(j.x_tree.e.transpose()).euler_angles();
        let (r, a) = (j.x_tree.r, j.axis);
        let _ = writeln!(
            s,
            "  <joint name=\"{}\" type=\"{kind}\">\n    <parent link=\"{}\"/>\n    <child link=\"{}\"/>\n    <origin xyz=\"{:e} {:e} {:e}\" rpy=\"{roll:e} {pitch:e} {yaw:e}\"/>\n    <axis xyz=\"{:e} {:e} {:e}\"/>",
            super::mjcf::escape(&j.name),
            super::mjcf::escape(parent),
            super::mjcf::escape(&j.body),
            r.x,
            r.y,
            r.z,
            a.x,
            a.y,
            a.z
        );
        if kind != "continuous" {
            let _ = writeln!(
                s,
                "    <limit lower=\"{:e}\" upper=\"{:e}\" effort=\"0\" velocity=\"0\"/>",
                j.limits.0, j.limits.1
            );
        }
        let _ = writeln!(
            s,
            "    <dynamics damping=\"{:e}\" friction=\"{:e}\"/>\n  </joint>",
            friction.viscous.get(b).copied().unwrap_or(0.0),
            friction.coulomb.get(b).copied().unwrap_or(0.0)
        );
    }
    s += "</robot>\n";
    Ok(s)
}
