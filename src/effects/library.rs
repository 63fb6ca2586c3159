//! [`Library`]: a list of effects — the built-in ones, plus a user's own —
//! that names resolve against, the simulator applies and the diagnosis
//! proposes.

use super::effect::Effect;
use super::error::EffectError;
use super::params::ParamSpec;
use super::values::{Values, checked};
use crate::data::Dataset;
use crate::dynamics::RobotDescription;
use crate::sim::{Effects, SimConfig, TrueRobot, Truth, simulate_with};
use std::collections::BTreeMap;
use std::sync::Arc;

/// An ordered list of effects with unique names; a parameter name shared by
/// two effects has one unit, nominal value and range.
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
        self.push(Arc::new(effect))
    }

    /// [`Self::add`] of an effect already shared.
    pub fn push(&mut self, effect: Arc<dyn Effect>) -> Result<&mut Self, EffectError> {
        if self.find(effect.name()).is_some() {
            return Err(EffectError::Duplicate(effect.name().to_string()));
        }
        for p in effect.params() {
            if let Some((spec, owners)) = self.spec(p.name)
                && (spec.unit, spec.nominal, spec.range) != (p.unit, p.nominal, p.range)
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
            checked(&spec, value)?;
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
                .and_then(|(s, _)| checked(&s, value))
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

#[cfg(test)]
mod tests {
    use super::Library;
    use crate::dynamics::cheetah3;
    use crate::effects::{Context, Effect, EffectError, Hypothesis, ParamSpec, Range, Values};
    use crate::sim::{Effects, Truth};

    /// An effect that declares the built-in `stiffness` differently.
    struct Stiff(f64);
    impl Effect for Stiff {
        fn name(&self) -> &'static str {
            "stiff"
        }
        fn summary(&self) -> &'static str {
            "a test effect"
        }
        fn params(&self) -> Vec<ParamSpec> {
            vec![ParamSpec::new(
                "stiffness",
                "N·m/rad",
                self.0,
                Range::Positive,
                "K",
            )]
        }
        fn apply(&self, _: &Values, _: &mut Truth) -> Result<(), EffectError> {
            Ok(())
        }
        fn hypothesis(&self, _: &Context) -> Result<Hypothesis, EffectError> {
            Ok(Hypothesis::none())
        }
    }

    /// The built-in names are unique and every built-in effect's shared
    /// parameters agree (the library could be built one by one).
    #[test]
    fn the_builtin_library_is_consistent() {
        let lib = Library::builtin();
        // added one by one, as a user's effects are, every built-in fits
        let mut again = Library::empty();
        for e in super::super::builtin::all() {
            let name = e.name();
            assert!(lib.names().iter().filter(|n| **n == name).count() == 1);
            again.push(e).unwrap();
        }
        assert_eq!(again, lib);
        assert_eq!(lib.names().len(), 17);
        assert_eq!(lib.names()[8], "link_inertia");
        let shared: Vec<_> = lib
            .params()
            .into_iter()
            .filter(|(_, o)| o.len() > 1)
            .collect();
        let names: Vec<&str> = shared.iter().map(|(s, _)| s.name).collect();
        assert_eq!(names, ["coulomb_scale", "stiffness", "damping"]);
        // a foreign effect declaring `stiffness` unlike elasticity is refused
        // (unit, nominal value and range must agree; the wording may not)
        let e = lib.clone().with(Stiff(1.0)).unwrap_err().to_string();
        assert!(e.contains("stiffness") && e.contains("elasticity"), "{e}");
        assert!(lib.with(Stiff(2000.0)).is_ok());
    }

    /// A magnitude is its nominal value, under the robot's `[effects]`
    /// default, under the record's override; unknown names and values out
    /// of range are named errors.
    #[test]
    fn magnitudes_follow_nominal_then_robot_then_override() {
        let lib = Library::builtin();
        let mut leg = cheetah3::description();
        leg.effects.insert("stiffness".into(), 800.0);
        leg.effects.insert("offset".into(), 0.25);
        let fx = Effects::parse("elasticity", &["stiffness=300".into()]).unwrap();
        let m = lib.magnitudes(&leg, &fx).unwrap();
        assert_eq!(m["stiffness"], 300.0);
        assert_eq!(m["offset"], 0.25);
        assert_eq!(m["damping"], 5.0);
        leg.effects.insert("stifness".into(), 1.0);
        let e = lib.magnitudes(&leg, &fx).unwrap_err().to_string();
        assert!(e.contains("cheetah3-leg") && e.contains("stifness"), "{e}");
        leg.effects.remove("stifness");
        leg.effects.insert("delay".into(), 2.0);
        let e = lib.check_defaults(&leg).unwrap_err().to_string();
        assert!(e.contains("delay") && e.contains("[0, 1]"), "{e}");
        let help = lib.param_help();
        assert!(help.contains("stiffness (elasticity, backlash)") && help.contains("N·m/rad"));
    }
}
