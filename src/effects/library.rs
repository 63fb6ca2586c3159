//! [`Library`]: a list of effects — the built-in ones, plus a user's own —
//! that names resolve against, the simulator applies and the diagnosis
//! proposes.

use super::effect::Effect;
use super::error::EffectError;
use super::params::{ParamSpec, Values};
use crate::data::Dataset;
use crate::dynamics::RobotDescription;
use crate::sim::{Effects, SimConfig, TrueRobot, Truth, simulate_with};
use std::collections::BTreeMap;
use std::sync::Arc;

/// An ordered list of effects with unique names; a parameter name shared by
/// two effects has one spec.
#[derive(Clone)]
pub struct Library {
    effects: Vec<Arc<dyn Effect>>,
}

impl std::fmt::Debug for Library {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.names()).finish()
    }
}

impl PartialEq for Library {
    /// Libraries are equal when they list the same effect names in order.
    fn eq(&self, other: &Self) -> bool {
        self.names() == other.names()
    }
}

impl Default for Library {
    /// The built-in library.
    fn default() -> Self {
        Self::builtin()
    }
}

impl Library {
    /// The built-in effects ([`super::builtin`]), in the order the
    /// diagnosis tries them and the simulator applies them.
    pub fn builtin() -> Self {
        Self {
            effects: super::builtin::all(),
        }
    }

    /// No effect.
    pub fn empty() -> Self {
        Self { effects: vec![] }
    }

    /// Adds `effect` at the end (an error if its name is taken, or if it
    /// declares a shared parameter unlike an effect already in).
    pub fn add(&mut self, effect: impl Effect + 'static) -> Result<&mut Self, EffectError> {
        let effect: Arc<dyn Effect> = Arc::new(effect);
        if self.find(effect.name()).is_some() {
            return Err(EffectError::Duplicate(effect.name().to_string()));
        }
        for p in effect.params() {
            if let Some((spec, owners)) = self.spec(p.name)
                && spec != p
            {
                return Err(EffectError::Conflict {
                    effect: effect.name().into(),
                    param: p.name.into(),
                    other: owners[0].into(),
                });
            }
        }
        self.effects.push(effect);
        Ok(self)
    }

    /// `self` with `effect` added ([`Self::add`]).
    pub fn with(mut self, effect: impl Effect + 'static) -> Result<Self, EffectError> {
        self.add(effect)?;
        Ok(self)
    }

    /// The effects, in order.
    pub fn effects(&self) -> &[Arc<dyn Effect>] {
        &self.effects
    }

    /// The effects' names, in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.effects.iter().map(|e| e.name()).collect()
    }

    fn find(&self, name: &str) -> Option<&Arc<dyn Effect>> {
        self.effects.iter().find(|e| e.name() == name.trim())
    }

    /// The effect named `name`.
    pub fn get(&self, name: &str) -> Result<&Arc<dyn Effect>, EffectError> {
        self.find(name).ok_or_else(|| EffectError::UnknownEffect {
            name: name.trim().to_string(),
            valid: self.names().iter().map(|s| s.to_string()).collect(),
        })
    }

    /// Every parameter once (in the order first declared), with the
    /// effects that declare it.
    pub fn params(&self) -> Vec<(ParamSpec, Vec<&'static str>)> {
        let mut out: Vec<(ParamSpec, Vec<&'static str>)> = vec![];
        for e in &self.effects {
            for p in e.params() {
                match out.iter_mut().find(|(s, _)| s.name == p.name) {
                    Some((_, owners)) => owners.push(e.name()),
                    None => out.push((p, vec![e.name()])),
                }
            }
        }
        out
    }

    fn spec(&self, name: &str) -> Option<(ParamSpec, Vec<&'static str>)> {
        self.params().into_iter().find(|(s, _)| s.name == name)
    }

    fn param(&self, name: &str) -> Result<(ParamSpec, Vec<&'static str>), EffectError> {
        self.spec(name).ok_or_else(|| EffectError::UnknownParam {
            name: name.to_string(),
            valid: self.params().iter().map(|(s, _)| s.name.into()).collect(),
        })
    }

    /// Checks a record: every effect named is in the library, and every
    /// override names a parameter of an effect that is on, within its range.
    pub fn check(&self, fx: &Effects) -> Result<(), EffectError> {
        for name in &fx.on {
            self.get(name)?;
        }
        for (name, &value) in &fx.overrides {
            let (spec, owners) = self.param(name)?;
            if !owners.iter().any(|o| fx.has(o)) {
                return Err(EffectError::NotOn {
                    param: name.clone(),
                    effects: owners.iter().map(|s| s.to_string()).collect(),
                });
            }
            spec.check(value)?;
        }
        Ok(())
    }

    /// Checks a robot's default magnitudes (its sidecar's `[effects]`
    /// table): every name a parameter of the library, every value in range.
    pub fn check_defaults(&self, robot: &RobotDescription) -> Result<(), EffectError> {
        let wrap = |e: EffectError| EffectError::Defaults {
            robot: robot.origin(),
            source: Box::new(e),
        };
        for (name, &value) in &robot.effects {
            self.param(name)
                .and_then(|(s, _)| s.check(value))
                .map_err(wrap)?;
        }
        Ok(())
    }

    /// The value of every parameter of the library: its nominal value, the
    /// robot's default over it, the record's override over that.
    pub fn magnitudes(
        &self,
        robot: &RobotDescription,
        fx: &Effects,
    ) -> Result<BTreeMap<&'static str, f64>, EffectError> {
        self.check(fx)?;
        self.check_defaults(robot)?;
        Ok(self
            .params()
            .into_iter()
            .map(|(s, _)| {
                let v = fx
                    .overrides
                    .get(s.name)
                    .or_else(|| robot.effects.get(s.name))
                    .copied()
                    .unwrap_or(s.nominal);
                (s.name, v)
            })
            .collect())
    }

    /// The true robot of `robot` with the effects of `fx` (applied in the
    /// library's order, whatever the record's).
    pub fn true_robot(
        &self,
        robot: &RobotDescription,
        fx: &Effects,
    ) -> Result<TrueRobot, EffectError> {
        let all = self.magnitudes(robot, fx)?;
        let mut truth = Truth::new(robot);
        for e in self.effects.iter().filter(|e| fx.has(e.name())) {
            let values = Values::new(e.name(), e.params().iter().map(|p| (p.name, all[p.name])));
            e.apply(&values, &mut truth)?;
        }
        Ok(truth.build(fx.clone())?)
    }

    /// Simulates `robot` with the effects `cfg.effects` records
    /// ([`crate::sim::simulate_with`] on [`Self::true_robot`]).
    pub fn simulate(
        &self,
        robot: &RobotDescription,
        cfg: &SimConfig,
        progress: impl FnMut(usize, usize),
    ) -> Result<Dataset, EffectError> {
        let truth = self.true_robot(robot, &cfg.effects)?;
        Ok(simulate_with(robot, &truth, cfg, progress)?)
    }

    /// One line per parameter: name, effects, meaning, unit, range and
    /// nominal value (for `simulate --help`).
    pub fn param_help(&self) -> String {
        self.params()
            .iter()
            .map(|(p, owners)| {
                format!(
                    "  {} ({}): {} ({}, {}). Default {}.",
                    p.name,
                    owners.join(", "),
                    p.doc,
                    p.unit,
                    p.range,
                    p.nominal
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }
}
