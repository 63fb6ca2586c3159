//! Reading URDF text into a [`Robot`] with `roxmltree`: one parse, the
//! elements a robot description uses read strictly (a bad number is an
//! error naming the link or joint, the element and the attribute), every
//! other element (materials, textures, Gazebo and ROS 2 control blocks, …)
//! ignored.

use super::error::UrdfError;
use super::limits::{self, Limits};
use super::robot::{
    Geometry, Inertial, Joint, JointDynamics, JointType, Limit, Link, Mimic, Pose, Reduction,
    Robot, Shape, Transmission,
};
use roxmltree::Node;
use std::collections::HashSet;
use std::path::Path;

/// Where an element sits, for messages: a link or a joint.
#[derive(Clone, Copy)]
enum Owner<'a> {
    Link(&'a str),
    Joint(&'a str),
}

struct Ctx<'a> {
    path: &'a str,
    owner: Owner<'a>,
}

impl Ctx<'_> {
    fn err(&self, message: String) -> UrdfError {
        match self.owner {
            Owner::Link(l) => UrdfError::Link {
                path: self.path.into(),
                link: l.into(),
                message,
            },
            Owner::Joint(j) => UrdfError::Joint {
                path: self.path.into(),
                joint: j.into(),
                message,
            },
        }
    }

    /// A message made an error naming the file and the owner.
    fn ok<T>(&self, r: Result<T, String>) -> Result<T, UrdfError> {
        r.map_err(|m| self.err(m))
    }
}

/// A required finite number attribute of `node`.
fn number(node: Node, name: &str) -> Result<f64, String> {
    let what = node.tag_name().name();
    let raw = node
        .attribute(name)
        .ok_or_else(|| format!("<{what}> has no '{name}' attribute"))?;
    parse_number(raw, what, name)
}

/// An optional finite number attribute (absent: `default`).
fn number_or(node: Node, name: &str, default: f64) -> Result<f64, String> {
    match node.attribute(name) {
        None => Ok(default),
        Some(raw) => parse_number(raw, node.tag_name().name(), name),
    }
}

fn parse_number(raw: &str, what: &str, name: &str) -> Result<f64, String> {
    let v: f64 = raw
        .trim()
        .parse()
        .map_err(|_| format!("<{what} {name}=\"{raw}\">: not a number"))?;
    if !v.is_finite() {
        return Err(format!("<{what} {name}=\"{raw}\">: not finite"));
    }
    Ok(v)
}

/// An optional attribute of three finite numbers (absent: `default`).
fn triple(node: Node, name: &str, default: [f64; 3]) -> Result<[f64; 3], String> {
    Ok(triple_opt(node, name)?.unwrap_or(default))
}

/// A required attribute of three finite numbers.
fn triple_req(node: Node, name: &str) -> Result<[f64; 3], String> {
    triple_opt(node, name)?
        .ok_or_else(|| format!("<{}> has no '{name}' attribute", node.tag_name().name()))
}

fn triple_opt(node: Node, name: &str) -> Result<Option<[f64; 3]>, String> {
    let Some(raw) = node.attribute(name) else {
        return Ok(None);
    };
    let what = node.tag_name().name();
    let v: Vec<f64> = raw
        .split_whitespace()
        .take(4)
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| format!("<{what} {name}=\"{raw}\">: not three numbers"))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(format!(
            "<{what} {name}=\"{raw}\">: expected three finite numbers"
        ));
    }
    Ok(Some([v[0], v[1], v[2]]))
}

/// The `<origin>` child of `node` (absent: identity).
fn origin(node: Node) -> Result<Pose, String> {
    match child(node, "origin") {
        None => Ok(Pose::default()),
        Some(o) => Ok(Pose {
            xyz: triple(o, "xyz", [0.0; 3])?,
            rpy: triple(o, "rpy", [0.0; 3])?,
        }),
    }
}

fn child<'a, 'i>(node: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    node.children().find(|c| c.has_tag_name(tag))
}

fn children<'a, 'i>(node: Node<'a, 'i>, tag: &'static str) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children().filter(move |c| c.has_tag_name(tag))
}

fn read_inertial(cx: &Ctx, node: Node) -> Result<Inertial, UrdfError> {
    let mass = child(node, "mass").ok_or_else(|| cx.err("<inertial> has no <mass>".into()))?;
    let inertia = child(node, "inertia")
        .ok_or_else(|| cx.err("<inertial> has no <inertia> (missing inertia)".into()))?;
    let mut i6 = [0.0; 6];
    for (k, name) in ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]
        .iter()
        .enumerate()
    {
        i6[k] = cx.ok(number(inertia, name))?;
    }
    Ok(Inertial {
        origin: cx.ok(origin(node))?,
        mass: cx.ok(number(mass, "value"))?,
        inertia: i6,
        range: node.range(),
    })
}

/// `value` of attribute `name` of `node` if it is positive.
fn positive(node: Node, name: &str, value: f64) -> Result<f64, String> {
    if value > 0.0 {
        return Ok(value);
    }
    Err(format!(
        "<{} {name}=\"{}\">: must be positive",
        node.tag_name().name(),
        node.attribute(name).unwrap_or("")
    ))
}

/// Three numbers that each pass `ok` (`must`: what `ok` asks, for the
/// message).
fn all3(
    node: Node,
    name: &str,
    v: [f64; 3],
    ok: fn(f64) -> bool,
    must: &str,
) -> Result<[f64; 3], String> {
    if v.iter().all(|&x| ok(x)) {
        return Ok(v);
    }
    Err(format!(
        "<{} {name}=\"{}\">: every value must be {must}",
        node.tag_name().name(),
        node.attribute(name).unwrap_or("")
    ))
}

/// Three positive numbers (box sides).
fn positive3(node: Node, name: &str, v: [f64; 3]) -> Result<[f64; 3], String> {
    all3(node, name, v, |x| x > 0.0, "positive")
}

/// Three non-zero numbers (mesh scales: a negative one mirrors the mesh,
/// as left/right parts of many robots do).
fn nonzero3(node: Node, name: &str, v: [f64; 3]) -> Result<[f64; 3], String> {
    all3(node, name, v, |x| x != 0.0, "non-zero")
}

/// The geometry of a `<collision>` or `<visual>`, with its ranges: box
/// sides, radii and cylinder lengths positive, mesh scales non-zero
/// (negative: mirrored), a capsule's length non-negative.
fn geometry(shape: Node) -> Result<Geometry, String> {
    let g = child(shape, "geometry").ok_or("no <geometry>")?;
    let e = g
        .children()
        .find(|c| c.is_element())
        .ok_or("an empty <geometry>")?;
    Ok(match e.tag_name().name() {
        "box" => Geometry::Box {
            size: positive3(e, "size", triple_req(e, "size")?)?,
        },
        "cylinder" => Geometry::Cylinder {
            radius: positive(e, "radius", number(e, "radius")?)?,
            length: positive(e, "length", number(e, "length")?)?,
        },
        "sphere" => Geometry::Sphere {
            radius: positive(e, "radius", number(e, "radius")?)?,
        },
        "capsule" => {
            let length = number(e, "length")?;
            if length < 0.0 {
                return Err(format!(
                    "<capsule length=\"{}\">: must not be negative",
                    e.attribute("length").unwrap_or("")
                ));
            }
            Geometry::Capsule {
                radius: positive(e, "radius", number(e, "radius")?)?,
                length,
            }
        }
        "mesh" => Geometry::Mesh {
            filename: e
                .attribute("filename")
                .ok_or("<mesh> has no 'filename' attribute")?
                .to_string(),
            scale: nonzero3(e, "scale", triple(e, "scale", [1.0; 3])?)?,
        },
        other => return Err(format!("unknown geometry <{other}>")),
    })
}

/// A `<collision>` or `<visual>`; one whose origin or geometry cannot be
/// read, or is out of range, is kept as [`Geometry::Invalid`] (identity
/// origin) with the reason.
fn read_shape(s: Node) -> Shape {
    match origin(s).and_then(|o| Ok((o, geometry(s)?))) {
        Ok((origin, geometry)) => Shape { origin, geometry },
        Err(message) => Shape {
            origin: Pose::default(),
            geometry: Geometry::Invalid { message },
        },
    }
}

fn read_shapes(link: Node, tag: &'static str) -> Vec<Shape> {
    children(link, tag).map(read_shape).collect()
}

fn read_link(path: &str, node: Node) -> Result<Link, UrdfError> {
    let name = node.attribute("name").ok_or_else(|| UrdfError::Robot {
        path: path.into(),
        message: format!("a <link> without a name (line {})", line_of(node)),
    })?;
    let cx = Ctx {
        path,
        owner: Owner::Link(name),
    };
    Ok(Link {
        name: name.to_string(),
        inertial: child(node, "inertial")
            .map(|i| read_inertial(&cx, i))
            .transpose()?,
        collisions: read_shapes(node, "collision"),
        visuals: read_shapes(node, "visual"),
        range: node.range(),
    })
}

fn joint_type(cx: &Ctx, node: Node) -> Result<JointType, UrdfError> {
    Ok(match node.attribute("type") {
        Some("revolute") => JointType::Revolute,
        Some("continuous") => JointType::Continuous,
        Some("prismatic") => JointType::Prismatic,
        Some("fixed") => JointType::Fixed,
        Some("floating") => JointType::Floating,
        Some("planar") => JointType::Planar,
        Some("spherical") => JointType::Spherical,
        Some(other) => {
            return Err(cx.err(format!(
                "type \"{other}\" is not a URDF joint type (revolute, continuous, prismatic, fixed, floating, planar, spherical)"
            )));
        }
        None => return Err(cx.err("no 'type' attribute".into())),
    })
}

fn link_ref(cx: &Ctx, node: Node, tag: &str) -> Result<String, UrdfError> {
    child(node, tag)
        .and_then(|c| c.attribute("link"))
        .map(str::to_string)
        .ok_or_else(|| cx.err(format!("no <{tag} link=\"…\">")))
}

fn read_joint(path: &str, node: Node) -> Result<Joint, UrdfError> {
    let name = node.attribute("name").ok_or_else(|| UrdfError::Robot {
        path: path.into(),
        message: format!("a <joint> without a name (line {})", line_of(node)),
    })?;
    let cx = Ctx {
        path,
        owner: Owner::Joint(name),
    };
    let limit = child(node, "limit")
        .map(|l| -> Result<Limit, UrdfError> {
            Ok(Limit {
                lower: cx.ok(number_or(l, "lower", 0.0))?,
                upper: cx.ok(number_or(l, "upper", 0.0))?,
                effort: cx.ok(number_or(l, "effort", 0.0))?,
                velocity: cx.ok(number_or(l, "velocity", 0.0))?,
            })
        })
        .transpose()?;
    let mimic = child(node, "mimic")
        .map(|m| -> Result<Mimic, UrdfError> {
            Ok(Mimic {
                joint: m
                    .attribute("joint")
                    .ok_or_else(|| cx.err("<mimic> has no 'joint' attribute".into()))?
                    .to_string(),
                multiplier: cx.ok(number_or(m, "multiplier", 1.0))?,
                offset: cx.ok(number_or(m, "offset", 0.0))?,
            })
        })
        .transpose()?;
    let dynamics = child(node, "dynamics")
        .map(|d| -> Result<JointDynamics, UrdfError> {
            let opt = |name: &str| -> Result<Option<f64>, UrdfError> {
                d.attribute(name)
                    .map(|raw| cx.ok(parse_number(raw, "dynamics", name)))
                    .transpose()
            };
            Ok(JointDynamics {
                damping: opt("damping")?,
                friction: opt("friction")?,
            })
        })
        .transpose()?;
    Ok(Joint {
        name: name.to_string(),
        kind: joint_type(&cx, node)?,
        parent: link_ref(&cx, node, "parent")?,
        child: link_ref(&cx, node, "child")?,
        origin: cx.ok(origin(node))?,
        axis: match child(node, "axis") {
            Some(a) => cx.ok(triple(a, "xyz", [1.0, 0.0, 0.0]))?,
            None => [1.0, 0.0, 0.0],
        },
        limit,
        mimic,
        dynamics,
        ranges: (node.range(), child(node, "dynamics").map(|d| d.range())),
    })
}

fn read_transmission(node: Node) -> Transmission {
    Transmission {
        name: node.attribute("name").unwrap_or("").to_string(),
        joint: child(node, "joint")
            .and_then(|j| j.attribute("name"))
            .map(str::to_string),
        reduction: node
            .descendants()
            .find(|c| c.has_tag_name("mechanicalReduction"))
            .map(|r| {
                let text = r.text().unwrap_or("").trim();
                match text.parse::<f64>() {
                    Ok(v) if v.is_finite() => Reduction::Ratio(v),
                    _ => Reduction::NotANumber(text.to_string()),
                }
            }),
    }
}

fn line_of(node: Node) -> u32 {
    node.document().text_pos_at(node.range().start).row
}

/// The `<transmission>` elements anywhere under `root`, outermost only (one
/// nested in another is part of it), each subtree visited once.
fn transmissions(root: Node) -> Vec<Transmission> {
    let mut inside = 0..0;
    let mut out = Vec::new();
    for n in root.descendants() {
        if n.has_tag_name("transmission") && !inside.contains(&n.range().start) {
            inside = n.range();
            out.push(read_transmission(n));
        }
    }
    out
}

/// Reads URDF text with the default [`Limits`]; `path` names the file in
/// errors.
pub fn read_str(text: &str, path: &str) -> Result<Robot, UrdfError> {
    read_str_with(text, path, &Limits::default())
}

/// Reads URDF text within `limits` (checked before parsing); `path` names
/// the file in errors. Time and memory are linear in the text's length.
pub fn read_str_with(text: &str, path: &str, limits: &Limits) -> Result<Robot, UrdfError> {
    limits::check(text, path, limits)?;
    let options = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..Default::default()
    };
    let doc =
        roxmltree::Document::parse_with_options(text, options).map_err(|e| UrdfError::Xml {
            path: path.into(),
            message: e.to_string(),
        })?;
    let root = doc.root_element();
    if !root.has_tag_name("robot") {
        return Err(UrdfError::Robot {
            path: path.into(),
            message: format!(
                "the root element is <{}>, not <robot>",
                root.tag_name().name()
            ),
        });
    }
    let robot = Robot {
        name: root.attribute("name").unwrap_or("").to_string(),
        links: children(root, "link")
            .map(|l| read_link(path, l))
            .collect::<Result<_, _>>()?,
        joints: children(root, "joint")
            .map(|j| read_joint(path, j))
            .collect::<Result<_, _>>()?,
        transmissions: transmissions(root),
    };
    unique_names(&robot, path)?;
    Ok(robot)
}

fn unique_names(robot: &Robot, path: &str) -> Result<(), UrdfError> {
    let mut seen = HashSet::with_capacity(robot.links.len());
    for l in &robot.links {
        if !seen.insert(l.name.as_str()) {
            return Err(UrdfError::DuplicateLink {
                path: path.into(),
                name: l.name.clone(),
            });
        }
    }
    let mut seen = HashSet::with_capacity(robot.joints.len());
    for j in &robot.joints {
        if !seen.insert(j.name.as_str()) {
            return Err(UrdfError::DuplicateJoint {
                path: path.into(),
                name: j.name.clone(),
            });
        }
    }
    Ok(())
}

/// Reads a URDF file with the default [`Limits`]; also returns its text (for
/// repairs that keep the rest of the file byte for byte).
pub fn read_file(path: &Path) -> Result<(String, Robot), UrdfError> {
    read_file_with(path, &Limits::default())
}

/// Reads a URDF file within `limits`: a file larger than
/// [`Limits::max_bytes`] is refused before it is read (and a stream that
/// does not say its size is read no further than that).
pub fn read_file_with(path: &Path, limits: &Limits) -> Result<(String, Robot), UrdfError> {
    let p = path.display().to_string();
    let text = read_text(path, &p, limits.max_bytes)?;
    let robot = read_str_with(&text, &p, limits)?;
    Ok((text, robot))
}

/// The file's text, refused beyond `max_bytes`.
fn read_text(path: &Path, p: &str, max_bytes: usize) -> Result<String, UrdfError> {
    let io = |source| UrdfError::Io {
        path: p.into(),
        source,
    };
    let bytes = crate::io::read_capped(path, max_bytes as u64).map_err(|e| match e {
        crate::io::Capped::Io(source) => io(source),
        crate::io::Capped::TooLarge(bytes) => UrdfError::TooLarge {
            path: p.into(),
            bytes,
            limit: max_bytes,
        },
    })?;
    String::from_utf8(bytes).map_err(|_| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "not UTF-8 text",
        ))
    })
}
