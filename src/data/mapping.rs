//! Which array, column or message field of a log is q, q̇, q̈ and τ of
//! which joint, and in which units: one mapping for every file format
//! (docs/inputs.md, "Column mappings"), read from TOML.
//!
//! ```toml
//! joints = ["lwr_0_joint", "lwr_1_joint"]  # the arrays' column order (default: the robot's)
//! time = "times"                            # the time stamps' array or column
//! time_unit = "s"                           # s (default), ms, us or ns
//! [q]
//! source = "positions"   # an n × joints array, a "pos_{joint}" pattern, or `columns = [...]`
//! unit = "rad"           # rad (default) or deg
//! [qd]
//! source = "velocities"
//! [tau]
//! source = "torques"
//! ```

use super::error::DataError;
use serde::Deserialize;
use std::path::Path;

/// The largest mapping file read (bytes).
pub const MAX_MAPPING_BYTES: u64 = 1 << 20;

/// A column mapping.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Mapping {
    /// The order of the joints in the arrays' columns (and the values of
    /// `{joint}` in patterns); default: the robot's joint order.
    #[serde(default)]
    pub joints: Option<Vec<String>>,
    /// The array or column of time stamps (default `t`).
    #[serde(default)]
    pub time: Option<String>,
    /// The unit of the time stamps: `s` (default), `ms`, `us` or `ns`.
    #[serde(default)]
    pub time_unit: Option<String>,
    /// ROS 2 bags: the `sensor_msgs/msg/JointState` topic (default: the
    /// bag's only one).
    #[serde(default)]
    pub topic: Option<String>,
    /// Positions (rad or m).
    pub q: Option<Quantity>,
    /// Velocities (rad/s or m/s); absent: differentiated from q.
    pub qd: Option<Quantity>,
    /// Accelerations (rad/s² or m/s²); present: the file is taken as
    /// prepared.
    pub qdd: Option<Quantity>,
    /// Torques (N·m or N).
    pub tau: Option<Quantity>,
}

/// Where one quantity is.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Quantity {
    /// An array (`positions`: n × joints), or a name with `{joint}` (one
    /// column or 1-D array per joint).
    pub source: Option<String>,
    /// The columns or arrays, one per joint in `joints` order.
    pub columns: Option<Vec<String>>,
    /// `rad` (default) or `deg` for positions, velocities and
    /// accelerations (every joint's values converted: a robot with
    /// prismatic joints gives its angles in rad); torques are N·m (or N).
    pub unit: Option<String>,
}

/// Which quantity (for names in errors and the default names).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Positions.
    Q,
    /// Velocities.
    Qd,
    /// Accelerations.
    Qdd,
    /// Torques.
    Tau,
}

impl Kind {
    /// Every quantity.
    pub const ALL: [Kind; 4] = [Kind::Q, Kind::Qd, Kind::Qdd, Kind::Tau];

    /// The CSV format's column prefix (`q`, `qd`, `qdd`, `tau`).
    pub fn prefix(self) -> &'static str {
        match self {
            Kind::Q => "q",
            Kind::Qd => "qd",
            Kind::Qdd => "qdd",
            Kind::Tau => "tau",
        }
    }
}

impl Mapping {
    /// The CSV format's own names: `t`, `q_<joint>`, `qd_<joint>`,
    /// `qdd_<joint>`, `tau_<joint>`.
    pub fn csv_default() -> Self {
        let q = |p: &str| {
            Some(Quantity {
                source: Some(format!("{p}_{{joint}}")),
                ..Quantity::default()
            })
        };
        Self {
            time: Some("t".into()),
            q: q("q"),
            qd: q("qd"),
            qdd: q("qdd"),
            tau: q("tau"),
            ..Self::default()
        }
    }

    /// Reads and checks a mapping file.
    pub fn read(path: &Path) -> Result<Self, DataError> {
        let p = path.display().to_string();
        let io = |source| DataError::Io {
            path: p.clone(),
            source,
        };
        let bytes = crate::io::read_capped(path, MAX_MAPPING_BYTES).map_err(|e| match e {
            crate::io::Capped::Io(source) => io(source),
            crate::io::Capped::TooLarge(len) => DataError::Mapping {
                path: p.clone(),
                message: format!("{len} bytes or more; a mapping is at most {MAX_MAPPING_BYTES}"),
            },
        })?;
        let text = String::from_utf8(bytes).map_err(|_| DataError::Mapping {
            path: p.clone(),
            message: "not UTF-8 text".into(),
        })?;
        Self::parse(&text, &p)
    }

    /// Parses mapping TOML; `path` names it in errors.
    pub fn parse(text: &str, path: &str) -> Result<Self, DataError> {
        let m: Self = toml::from_str(text).map_err(|e| DataError::Mapping {
            path: path.into(),
            message: e.to_string(),
        })?;
        m.check(path)?;
        Ok(m)
    }

    fn check(&self, path: &str) -> Result<(), DataError> {
        let bad = |message: String| DataError::Mapping {
            path: path.into(),
            message,
        };
        self.time_scale().map_err(bad)?;
        if let Some(j) = twice(self.joints.iter().flatten().filter(|j| !j.is_empty())) {
            return Err(bad(format!(
                "joints: '{j}' is named twice (each joint is one column; \"\" skips a column)"
            )));
        }
        for k in Kind::ALL {
            let Some(q) = self.quantity(k) else { continue };
            if q.source.is_some() == q.columns.is_some() {
                return Err(bad(format!(
                    "[{}]: give exactly one of source and columns",
                    k.prefix()
                )));
            }
            if let (Some(c), Some(j)) = (&q.columns, &self.joints)
                && c.len() != j.len()
            {
                return Err(bad(format!(
                    "[{}]: {} columns for {} joints",
                    k.prefix(),
                    c.len(),
                    j.len()
                )));
            }
            if let Some(c) = twice(q.columns.iter().flatten()) {
                return Err(bad(format!(
                    "[{}]: column '{c}' is given for two joints",
                    k.prefix()
                )));
            }
            if k == Kind::Tau && q.unit.is_some() {
                return Err(bad("[tau]: torques are N·m (or N): no unit to give".into()));
            }
            q.scale()
                .map_err(|m| bad(format!("[{}]: {m}", k.prefix())))?;
        }
        if self.q.is_none() && self.topic.is_none() {
            return Err(bad(
                "[q]: the positions are needed (a ROS 2 bag's mapping may give only its topic)"
                    .into(),
            ));
        }
        Ok(())
    }

    /// The entry of quantity `k`.
    pub fn quantity(&self, k: Kind) -> Option<&Quantity> {
        match k {
            Kind::Q => self.q.as_ref(),
            Kind::Qd => self.qd.as_ref(),
            Kind::Qdd => self.qdd.as_ref(),
            Kind::Tau => self.tau.as_ref(),
        }
    }

    /// The time stamps' name (default `t`).
    pub fn time_name(&self) -> &str {
        self.time.as_deref().unwrap_or("t")
    }

    /// Seconds per unit of the time stamps.
    pub(crate) fn time_scale(&self) -> Result<f64, String> {
        match self.time_unit.as_deref().unwrap_or("s") {
            "s" => Ok(1.0),
            "ms" => Ok(1e-3),
            "us" => Ok(1e-6),
            "ns" => Ok(1e-9),
            u => Err(format!("time_unit '{u}': use s, ms, us or ns")),
        }
    }

    /// The joints of the arrays' columns: the mapping's, else `robot`'s.
    pub fn joint_order<'a>(&'a self, robot: &'a [&'a str]) -> Vec<&'a str> {
        match &self.joints {
            Some(j) => j.iter().map(String::as_str).collect(),
            None => robot.to_vec(),
        }
    }
}

impl Quantity {
    /// The factor to SI of this quantity's angles (1, or π/180 for `deg`).
    pub(crate) fn scale(&self) -> Result<f64, String> {
        match self.unit.as_deref().unwrap_or("rad") {
            "rad" => Ok(1.0),
            "deg" => Ok(std::f64::consts::PI / 180.0),
            u => Err(format!("unit '{u}': use rad or deg")),
        }
    }

    /// The per-joint names for `joints` (from `columns`, or `source` with
    /// `{joint}` replaced), or `None` when `source` names one 2-D array.
    pub fn per_joint(&self, joints: &[&str]) -> Option<Vec<String>> {
        if let Some(c) = &self.columns {
            return Some(c.clone());
        }
        let s = self.source.as_deref()?;
        s.contains("{joint}")
            .then(|| joints.iter().map(|j| s.replace("{joint}", j)).collect())
    }
}

/// The first name that comes twice among `names`.
fn twice<'a>(names: impl Iterator<Item = &'a String>) -> Option<&'a String> {
    let mut seen = std::collections::HashSet::new();
    names.into_iter().find(|n| !seen.insert(*n))
}
