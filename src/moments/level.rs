//! [`Level`]: how physically consistent a body's identified parameters must
//! be — the paper's hierarchy of conditions, from none to density
//! realizability in a bounding ellipsoid.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// A body's constraint level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Level {
    /// No constraint (ordinary least squares).
    None,
    /// Physical semi-consistency `I(π) ⪰ εI` (Theorem 1).
    Semi,
    /// Full consistency `J(π) ⪰ εI` (Theorem 3).
    Consistent,
    /// Consistency and density realizability in the body's ellipsoid
    /// (Theorem 4).
    Ellipsoid,
}

impl Level {
    /// Every level, from the weakest.
    pub const ALL: [Level; 4] = [
        Level::None,
        Level::Semi,
        Level::Consistent,
        Level::Ellipsoid,
    ];

    /// From its name (`none`, `semi`, `consistent`, `ellipsoid`).
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|l| l.as_str() == s)
    }

    /// Its name.
    pub fn as_str(self) -> &'static str {
        match self {
            Level::None => "none",
            Level::Semi => "semi",
            Level::Consistent => "consistent",
            Level::Ellipsoid => "ellipsoid",
        }
    }

    /// `none, semi, consistent, ellipsoid`.
    pub fn names() -> String {
        Self::ALL.map(Level::as_str).join(", ")
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A name that is not a level.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("'{0}' is not a constraint level (one of none, semi, consistent, ellipsoid)")]
pub struct UnknownLevel(pub String);

impl FromStr for Level {
    type Err = UnknownLevel;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::parse(s).ok_or_else(|| UnknownLevel(s.to_string()))
    }
}
