//! Reading URDF text into a [`Robot`] with `roxmltree`: one parse, the
//! elements a robot description uses read strictly (a bad number is an
//! error naming the link or joint, the element and the attribute), every
//! other element (materials, textures, Gazebo and ROS 2 control blocks, …)
//! ignored.

use super::error::UrdfError;
use super::robot::{
    Geometry, Inertial, Joint, JointDynamics, JointType, Limit, Link, Mimic, Pose, Robot, Shape,
    Transmission,
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

    /// A required finite number attribute of `<what>`.
    fn number(&self, node: Node, name: &str) -> Result<f64, UrdfError> {
        let what = node.tag_name().name();
        let raw = node
            .attribute(name)
            .ok_or_else(|| self.err(format!("<{what}> has no '{name}' attribute")))?;
        self.parse_number(raw, what, name)
    }

    /// An optional finite number attribute (absent: `default`).
    fn number_or(&self, node: Node, name: &str, default: f64) -> Result<f64, UrdfError> {
        match node.attribute(name) {
            None => Ok(default),
            Some(raw) => self.parse_number(raw, node.tag_name().name(), name),
        }
    }

    fn parse_number(&self, raw: &str, what: &str, name: &str) -> Result<f64, UrdfError> {
        let v: f64 = raw
            .trim()
            .parse()
            .map_err(|_| self.err(format!("<{what} {name}=\"{raw}\">: not a number")))?;
        if !v.is_finite() {
            return Err(self.err(format!("<{what} {name}=\"{raw}\">: not finite")));
        }
        Ok(v)
    }

    /// An optional attribute of three finite numbers (absent: `default`).
    fn triple(&self, node: Node, name: &str, default: [f64; 3]) -> Result<[f64; 3], UrdfError> {
        Ok(self.triple_opt(node, name)?.unwrap_or(default))
    }

    /// A required attribute of three finite numbers.
    fn triple_req(&self, node: Node, name: &str) -> Result<[f64; 3], UrdfError> {
        self.triple_opt(node, name)?.ok_or_else(|| {
            self.err(format!(
                "<{}> has no '{name}' attribute",
                node.tag_name().name()
            ))
        })
    }

    fn triple_opt(&self, node: Node, name: &str) -> Result<Option<[f64; 3]>, UrdfError> {
        let Some(raw) = node.attribute(name) else {
            return Ok(None);
        };
        let what = node.tag_name().name();
        let v: Vec<f64> = raw
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .map_err(|_| self.err(format!("<{what} {name}=\"{raw}\">: not three numbers")))?;
        if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
            return Err(self.err(format!(
                "<{what} {name}=\"{raw}\">: expected three finite numbers"
            )));
        }
        Ok(Some([v[0], v[1], v[2]]))
    }

    /// The `<origin>` child of `node` (absent: identity).
    fn origin(&self, node: Node) -> Result<Pose, UrdfError> {
        match child(node, "origin") {
            None => Ok(Pose::default()),
            Some(o) => Ok(Pose {
                xyz: self.triple(o, "xyz", [0.0; 3])?,
                rpy: self.triple(o, "rpy", [0.0; 3])?,
            }),
        }
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
        i6[k] = cx.number(inertia, name)?;
    }
    Ok(Inertial {
        origin: cx.origin(node)?,
        mass: cx.number(mass, "value")?,
        inertia: i6,
        range: node.range(),
    })
}

/// A `<geometry>`; a problem with it is kept as [`Geometry::Invalid`].
fn read_geometry(cx: &Ctx, shape: Node) -> Geometry {
    let parsed = (|| -> Result<Geometry, UrdfError> {
        let g = child(shape, "geometry").ok_or_else(|| cx.err("no <geometry>".into()))?;
        let Some(e) = g.children().find(|c| c.is_element()) else {
            return Err(cx.err("an empty <geometry>".into()));
        };
        Ok(match e.tag_name().name() {
            "box" => Geometry::Box {
                size: cx.triple_req(e, "size")?,
            },
            "cylinder" => Geometry::Cylinder {
                radius: cx.number(e, "radius")?,
                length: cx.number(e, "length")?,
            },
            "sphere" => Geometry::Sphere {
                radius: cx.number(e, "radius")?,
            },
            "capsule" => Geometry::Capsule {
                radius: cx.number(e, "radius")?,
                length: cx.number(e, "length")?,
            },
            "mesh" => Geometry::Mesh {
                filename: e
                    .attribute("filename")
                    .ok_or_else(|| cx.err("<mesh> has no 'filename' attribute".into()))?
                    .to_string(),
                scale: cx.triple(e, "scale", [1.0; 3])?,
            },
            other => return Err(cx.err(format!("unknown geometry <{other}>"))),
        })
    })();
    parsed.unwrap_or_else(|e| Geometry::Invalid {
        message: e.to_string(),
    })
}

fn read_shapes(cx: &Ctx, link: Node, tag: &'static str) -> Result<Vec<Shape>, UrdfError> {
    children(link, tag)
        .map(|s| {
            Ok(Shape {
                origin: cx.origin(s)?,
                geometry: read_geometry(cx, s),
            })
        })
        .collect()
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
        collisions: read_shapes(&cx, node, "collision")?,
        visuals: read_shapes(&cx, node, "visual")?,
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
                lower: cx.number_or(l, "lower", 0.0)?,
                upper: cx.number_or(l, "upper", 0.0)?,
                effort: cx.number_or(l, "effort", 0.0)?,
                velocity: cx.number_or(l, "velocity", 0.0)?,
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
                multiplier: cx.number_or(m, "multiplier", 1.0)?,
                offset: cx.number_or(m, "offset", 0.0)?,
            })
        })
        .transpose()?;
    let dynamics = child(node, "dynamics")
        .map(|d| -> Result<JointDynamics, UrdfError> {
            let opt = |name: &str| -> Result<Option<f64>, UrdfError> {
                d.attribute(name)
                    .map(|raw| cx.parse_number(raw, "dynamics", name))
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
        origin: cx.origin(node)?,
        axis: match child(node, "axis") {
            Some(a) => cx.triple(a, "xyz", [1.0, 0.0, 0.0])?,
            None => [1.0, 0.0, 0.0],
        },
        limit,
        mimic,
        dynamics,
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
                text.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| text.to_string())
            }),
    }
}

fn line_of(node: Node) -> u32 {
    node.document().text_pos_at(node.range().start).row
}

/// Reads URDF text; `path` names the file in errors.
pub fn read_str(text: &str, path: &str) -> Result<Robot, UrdfError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| UrdfError::Xml {
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
        transmissions: root
            .descendants()
            .filter(|n| n.has_tag_name("transmission"))
            .map(read_transmission)
            .collect(),
    };
    unique_names(&robot, path)?;
    Ok(robot)
}

fn unique_names(robot: &Robot, path: &str) -> Result<(), UrdfError> {
    let mut seen = HashSet::new();
    for l in &robot.links {
        if !seen.insert(l.name.as_str()) {
            return Err(UrdfError::Robot {
                path: path.into(),
                message: format!("two links are named '{}'", l.name),
            });
        }
    }
    let mut seen = HashSet::new();
    for j in &robot.joints {
        if !seen.insert(j.name.as_str()) {
            return Err(UrdfError::Robot {
                path: path.into(),
                message: format!("two joints are named '{}'", j.name),
            });
        }
    }
    Ok(())
}

/// Reads a URDF file; also returns its text (for repairs that keep the rest
/// of the file byte for byte).
pub fn read_file(path: &Path) -> Result<(String, Robot), UrdfError> {
    let p = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| UrdfError::Io {
        path: p.clone(),
        source,
    })?;
    let robot = read_str(&text, &p)?;
    Ok((text, robot))
}
