//! What describing a robot had to fill in or could not use, reported
//! without failing ([`super::RobotDescription::warnings`]).

use serde::Serialize;
use std::fmt;

/// A warning about a robot's description.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum DescriptionWarning {
    /// Joints whose nominal friction neither the sidecar nor the URDF
    /// gives: placeholders are used.
    PlaceholderFriction {
        /// The joints.
        joints: Vec<String>,
        /// The placeholder Coulomb coefficient (N·m or N).
        coulomb: f64,
        /// The placeholder viscous coefficient (N·m·s/rad or N·s/m).
        viscous: f64,
    },
    /// A URDF shape that could not be read (kept as invalid geometry).
    Geometry(crate::urdf::GeometryWarning),
    /// A moving joint the URDF couples to another (`<mimic>`), which the
    /// model moves on its own.
    Mimic {
        /// The joint.
        joint: String,
        /// The joint it mimics.
        leader: String,
    },
    /// A link's mesh that could not be used for its bounding ellipsoid.
    Mesh {
        /// The link.
        link: String,
        /// Why.
        note: String,
    },
    /// A body whose shapes give no bounding ellipsoid.
    NoBoundingEllipsoid {
        /// The body.
        body: String,
        /// Why.
        reason: String,
    },
    /// Solved bounding ellipsoids could not be stored in the cache (they
    /// are right; the next run solves them again).
    Cache {
        /// The cache's folder and the reason.
        reason: String,
    },
}

impl fmt::Display for DescriptionWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DescriptionWarning::PlaceholderFriction {
                joints,
                coulomb,
                viscous,
            } => write!(
                f,
                "no nominal friction for joint(s) {} in the sidecar ([[joint]] coulomb/viscous) or the URDF (<dynamics>, positive values): placeholders {coulomb} N·m Coulomb, {viscous} N·m·s/rad viscous where missing",
                joints.join(", ")
            ),
            DescriptionWarning::Geometry(g) => g.fmt(f),
            DescriptionWarning::Mimic { joint, leader } => write!(
                f,
                "joint '{joint}' mimics '{leader}' in the URDF (<mimic>), but is simulated and identified as an independent joint: lock it in a sidecar (lock = [\"{joint}\"], docs/robots.md) if it follows '{leader}'"
            ),
            DescriptionWarning::Mesh { link, note } => write!(f, "link '{link}': {note}"),
            DescriptionWarning::NoBoundingEllipsoid { body, reason } => {
                write!(
                    f,
                    "body '{body}': no bounding ellipsoid from its geometry: {reason}"
                )
            }
            DescriptionWarning::Cache { reason } => write!(
                f,
                "bounding ellipsoids not cached ({reason}): they are solved again on every run"
            ),
        }
    }
}
