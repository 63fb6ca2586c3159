//! The record of which effects a true robot has and the magnitudes the
//! user set: written beside the data (`config.effects` of the JSON), read
//! back, and resolved against an effect library
//! ([`crate::effects::Library`]), which knows what the names mean.

use super::error::{OverrideProblem, SimError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Which effects are on (by name), and the parameter overrides.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Effects {
    /// Effects switched on, in the order given.
    pub on: Vec<String>,
    /// Overrides of the robot's default magnitudes, by parameter name.
    pub overrides: BTreeMap<String, f64>,
}

impl Effects {
    /// These effects (duplicates dropped), with the robot's default
    /// magnitudes.
    pub fn new<S: AsRef<str>>(on: impl IntoIterator<Item = S>) -> Self {
        let mut e = Self::default();
        for x in on {
            let x = x.as_ref().trim().to_string();
            if !e.on.contains(&x) {
                e.on.push(x);
            }
        }
        e
    }

    /// Parses `a,b,c` and `NAME=VALUE` overrides (the syntax only: the
    /// names are checked against an effect library when the true robot is
    /// built, [`crate::effects::Library::check`]).
    pub fn parse(list: &str, overrides: &[String]) -> Result<Self, SimError> {
        let mut e = Self::new(list.split(',').map(str::trim).filter(|s| !s.is_empty()));
        for o in overrides {
            let (name, value) = parse_override(o)?;
            e.overrides.insert(name, value);
        }
        Ok(e)
    }

    /// With one more override (checked when the true robot is built).
    pub fn with(mut self, name: &str, value: f64) -> Self {
        self.overrides.insert(name.to_string(), value);
        self
    }

    /// Whether an effect is on.
    pub fn has(&self, name: &str) -> bool {
        self.on.iter().any(|e| e == name)
    }
}

/// Parses `NAME=VALUE` into a parameter name and its value.
pub fn parse_override(s: &str) -> Result<(String, f64), SimError> {
    let bad = |problem| SimError::Override {
        text: s.to_string(),
        problem,
    };
    let (k, v) = s.split_once('=').ok_or(bad(OverrideProblem::NoEquals))?;
    let name = k.trim();
    if name.is_empty() {
        return Err(bad(OverrideProblem::NoName));
    }
    let value: f64 = v
        .trim()
        .parse()
        .map_err(|_| bad(OverrideProblem::NotANumber(v.trim().to_string())))?;
    Ok((name.to_string(), value))
}

#[cfg(test)]
mod tests {
    use super::{Effects, parse_override};

    #[test]
    fn the_syntax_of_effects_and_overrides() {
        let e = Effects::parse(" coulomb, viscous,,coulomb ", &["stiffness = 300".into()]).unwrap();
        assert_eq!(e.on, ["coulomb", "viscous"]);
        assert_eq!(e.overrides["stiffness"], 300.0);
        assert!(e.has("viscous") && !e.has("offset"));
        for (bad, needle) in [("k", "NAME=VALUE"), ("=1", "no parameter"), ("k=x", "'x'")] {
            let m = parse_override(bad).unwrap_err().to_string();
            assert!(m.contains(needle) && m.contains(bad), "{m}");
        }
    }
}
