//! The identified model written into a copy of the robot's own URDF.
//!
//! Each model body is one rigid body made of its joint's child link and
//! every link merged into it (through fixed or locked joints), and the
//! identification gives only the whole: the whole goes into the child
//! link's `<inertial>` (in the link frame, which is the body frame), and
//! the `<inertial>` of each link merged into it becomes a comment saying
//! where its mass went. A simulator that merges fixed joints (MuJoCo's,
//! Gazebo's, Pinocchio's URDF readers do) then has the same bodies;
//! locked joints are still movable in the copy: lock them there too.
//! Links on a fixed base keep their elements; with a free-flying root the
//! root link holds the base body's identified whole, as the moving bodies'
//! links do (the root stays a plain link: ROS's convention for a floating
//! base, which its readers are told of, as Pinocchio's `JointModelFreeFlyer`).

use super::checks::{has_friction, urdf_inertial};
use super::error::ExportError;
use crate::dynamics::{Friction, Model};
use crate::moments::InertialParams;
use crate::urdf::write::{Edit, apply_edits, indent_before, inertial_xml};
use crate::urdf::{Link, Robot};

/// The URDF a model was built from: its text, as read, and its path (for
/// messages).
pub struct UrdfSource<'a> {
    /// The text.
    pub text: &'a str,
    /// The text, read ([`crate::urdf::read_str`]).
    pub robot: &'a Robot,
    /// Its path, for messages.
    pub path: &'a str,
}

/// The URDF text of `source` with `model`'s identified bodies and
/// friction: each body's `<inertial>` (mass, `origin xyz` the CoM in the
/// link frame, `rpy="0 0 0"`, the inertia about the CoM in the link frame's
/// axes: no rotation, so the numbers read back exactly), each moving
/// joint's `<dynamics damping="B" friction="B_c">` when friction was
/// identified (viscous and Coulomb; other terms and the rotors go into a
/// comment after `<robot>` and into the sidecar). Every byte outside the
/// replaced elements is kept.
pub fn urdf_with_params(
    source: &UrdfSource,
    model: &Model,
    friction: &Friction,
) -> Result<String, ExportError> {
    let mut edits = Vec::new();
    if let Some(base) = model.base() {
        // a free-flying root: the root link holds the base body's whole
        let link = link_of(source, &base.name)?;
        edits.push(body_inertial(source, link, &base.inertia)?);
        for f in model.frames.iter().filter(|f| f.body.is_none()) {
            if f.name != base.name {
                edits.extend(merged_inertial(link_of(source, &f.name)?, &base.name));
            }
        }
    }
    for (b, joint) in model.joints.iter().enumerate() {
        let link = link_of(source, &joint.body)?;
        edits.push(body_inertial(source, link, &joint.inertia)?);
        for f in model.frames.iter().filter(|f| f.body == Some(b)) {
            if f.name != joint.body {
                edits.extend(merged_inertial(link_of(source, &f.name)?, &joint.body));
            }
        }
    }
    if has_friction(friction) {
        for (j, joint) in model.joints.iter().enumerate() {
            edits.push(joint_dynamics(source, &joint.name, friction, j)?);
        }
    }
    edits.push(summary_comment(source, model, friction)?);
    apply_edits(source.text, edits).ok_or_else(|| not_this(source, "edits overlap".into()))
}

fn not_this(source: &UrdfSource, message: String) -> ExportError {
    ExportError::NotThisUrdf {
        path: source.path.into(),
        message,
    }
}

/// The URDF link named `name`, its element checked to be in the text.
fn link_of<'r>(source: &UrdfSource<'r>, name: &str) -> Result<&'r Link, ExportError> {
    let link = (source.robot.links.iter().find(|l| l.name == name))
        .ok_or_else(|| not_this(source, format!("no <link name=\"{name}\">")))?;
    let element = source.text.get(link.range.clone());
    if !element.is_some_and(|e| e.starts_with("<link")) {
        return Err(not_this(
            source,
            format!("link '{name}' is not where it was read"),
        ));
    }
    Ok(link)
}

/// The edit giving `link` the inertial `p` (its own frame).
fn body_inertial(
    source: &UrdfSource,
    link: &Link,
    p: &InertialParams,
) -> Result<Edit, ExportError> {
    let (m, c, i) = urdf_inertial(&link.name, p)?;
    let comment = "identified by momentlmi (the whole body: this link and the links fixed to it)";
    match &link.inertial {
        Some(old) => {
            let pad = indent_before(source.text, old.range.start);
            Ok((old.range.clone(), inertial_xml(pad, comment, m, c, i)))
        }
        None => Ok(inserted_child(source, link, |pad| {
            inertial_xml(pad, comment, m, c, i)
        })),
    }
}

/// The edit turning a merged link's `<inertial>` into a comment.
fn merged_inertial(link: &Link, body: &str) -> Option<Edit> {
    let old = link.inertial.as_ref()?;
    let note = format!(
        "<!-- <inertial> merged into link '{body}' by momentlmi: identified as one rigid body with it -->"
    );
    Some((old.range.clone(), note))
}

/// An edit inserting a child element into `link` (written by `child`, given
/// the indentation of the link's children): after its start tag, or the
/// self-closing element rewritten with a body.
fn inserted_child(source: &UrdfSource, link: &Link, child: impl Fn(&str) -> String) -> Edit {
    let r = link.range.clone();
    let element = &source.text[r.clone()];
    let pad = indent_before(source.text, r.start);
    let inner = format!("{pad}  ");
    if let Some(open) = element.strip_suffix("/>") {
        let open = open.trim_end();
        return (
            r,
            format!("{open}>\n{inner}{}\n{pad}</link>", child(&inner)),
        );
    }
    let end = r.start + start_tag_len(element);
    (end..end, format!("\n{inner}{}", child(&inner)))
}

/// The length of an element's start tag (up to its first `>` outside quotes).
fn start_tag_len(element: &str) -> usize {
    let mut quote = None;
    for (k, c) in element.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '>') => return k + 1,
            _ => {}
        }
    }
    element.len()
}

/// The edit setting joint `name`'s `<dynamics>` (model joint `j`).
fn joint_dynamics(
    source: &UrdfSource,
    name: &str,
    friction: &Friction,
    j: usize,
) -> Result<Edit, ExportError> {
    let joint = (source.robot.joints.iter().find(|x| x.name == name))
        .ok_or_else(|| not_this(source, format!("no <joint name=\"{name}\">")))?;
    let (element, dynamics) = &joint.ranges;
    let xml = format!(
        "<dynamics damping=\"{:e}\" friction=\"{:e}\"/>",
        friction.viscous[j], friction.coulomb[j]
    );
    if let Some(d) = dynamics {
        return Ok((d.clone(), xml));
    }
    let text = source.text.get(element.clone()).unwrap_or_default();
    let Some(close) = text.rfind("</joint>") else {
        return Err(not_this(
            source,
            format!("joint '{name}' is not where it was read"),
        ));
    };
    let at = element.start + close;
    let pad = indent_before(source.text, element.start);
    Ok((at..at, format!("  {xml}\n{pad}")))
}

/// A comment after `<robot …>` with what the URDF cannot hold: rotors and
/// every friction term.
fn summary_comment(
    source: &UrdfSource,
    model: &Model,
    friction: &Friction,
) -> Result<Edit, ExportError> {
    let at = source
        .text
        .find("<robot")
        .ok_or_else(|| not_this(source, "no <robot>".into()))?;
    let end = at + start_tag_len(&source.text[at..]);
    let mut lines = vec![
        "identified by momentlmi: each moving body's <inertial> (the links fixed to it merged in),"
            .to_string(),
        "and <dynamics> damping (viscous) and friction (Coulomb) when friction was identified."
            .into(),
        "What a URDF cannot hold is in the sidecar written beside it and here:".into(),
    ];
    for r in &model.rotors {
        let p = r.inertia.0.map(|x| format!("{x:e}")).join(", ");
        lines.push(format!(
            "  rotor '{}' (joint '{}', gear ratio {}): params [{p}]",
            r.name, model.joints[r.joint].name, r.gear_ratio
        ));
    }
    for t in crate::dynamics::FrictionTerm::ALL {
        let c = friction.coefficients(t);
        if c.iter().any(|&x| x != 0.0) {
            let v: Vec<String> = c.iter().map(|x| format!("{x:e}")).collect();
            lines.push(format!(
                "  friction {} ({}): [{}]",
                t.name(),
                t.unit(),
                v.join(", ")
            ));
        }
    }
    let body = lines.join("\n     ");
    Ok((end..end, format!("\n  <!-- {body} -->")))
}
