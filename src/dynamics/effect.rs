//! The effects a real robot has and a nominal rigid-body model may lack:
//! one vocabulary for the simulator ([`crate::sim`], which adds them to a
//! "true robot") and the diagnoser ([`crate::diagnose`], which looks for
//! them in a residual).
//!
//! [`Effect`] names an effect; [`EffectParams`] holds every effect's typed
//! magnitudes, with defaults that a robot description (sidecar `[effects]`)
//! can change; [`Param`] names one magnitude (for `NAME=VALUE` overrides).
//! Friction magnitudes are per joint and come from the robot description's
//! nominal friction; the parameters here scale them. Terms, per joint i
//! (q̇ᵢ in rad/s, N the gear ratio, sign(0) = 0):
//!
//! | effect | term | parameters |
//! |---|---|---|
//! | `rotor_inertia` | the rotors are part of the robot (else links only) | — |
//! | `coulomb` | `s_c B_c,i sign(q̇ᵢ)` | `coulomb_scale` s_c |
//! | `viscous` | `s_v B_i q̇ᵢ` | `viscous_scale` s_v |
//! | `stribeck` | `F_s e^{−(q̇ᵢ/v_s)²} sign(q̇ᵢ)` | `stribeck_force`, `stribeck_velocity` |
//! | `asymmetric_friction` | `a s_c B_c,i \|sign(q̇ᵢ)\|` | `asymmetry` a |
//! | `offset` | `cᵢ` | `offset` |
//! | `payload` | a point mass at the tool point, in the dynamics | `payload_mass` |
//! | `time_delay` | the torque is that of the state at `t − δ` | `delay` δ |
//! | `cogging` | `A sin(p N qᵢ)` | `cogging_amplitude` A, `cogging_period` p |
//! | `torque_gain` | measured `(1 + ε) τ` | `gain_error` ε |
//! | `elasticity` | the links are driven through a spring–damper | `stiffness`, `damping` |
//! | `backlash` | as elasticity, with a dead band of half-width b | `backlash_width` b, `stiffness`, `damping` |

use super::error::DynamicsError;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// An effect of a real robot that a rigid-body model may lack.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[cfg_attr(
    feature = "clap",
    derive(clap::ValueEnum),
    value(rename_all = "snake_case")
)]
#[serde(rename_all = "snake_case")]
pub enum Effect {
    /// The rotors' reflected inertia and gyroscopic terms.
    RotorInertia,
    /// Coulomb friction.
    Coulomb,
    /// Viscous friction.
    Viscous,
    /// Stribeck friction (extra friction near zero velocity).
    Stribeck,
    /// Coulomb friction that differs by direction.
    AsymmetricFriction,
    /// A constant torque offset (sensor bias, an unmodelled spring preload).
    Offset,
    /// An unmodelled point mass at the tool point.
    Payload,
    /// A delay between the measured state and the measured torque.
    TimeDelay,
    /// Motor cogging, periodic in the motor angle.
    Cogging,
    /// A torque-constant (gain) error.
    TorqueGain,
    /// Series elasticity of the transmission.
    Elasticity,
    /// Backlash (a dead band) in a compliant transmission.
    Backlash,
    /// An encoder zero offset: the measured position is the true one minus
    /// a constant (a calibration error).
    JointOffset,
}

impl Effect {
    /// Every effect, in the order reports list them.
    pub const ALL: [Effect; 13] = [
        Effect::RotorInertia,
        Effect::Coulomb,
        Effect::Viscous,
        Effect::Stribeck,
        Effect::AsymmetricFriction,
        Effect::Offset,
        Effect::Payload,
        Effect::TimeDelay,
        Effect::Cogging,
        Effect::TorqueGain,
        Effect::Elasticity,
        Effect::Backlash,
        Effect::JointOffset,
    ];

    /// The name used on the command line and in files (`rotor_inertia`, …).
    pub fn name(self) -> &'static str {
        match self {
            Effect::RotorInertia => "rotor_inertia",
            Effect::Coulomb => "coulomb",
            Effect::Viscous => "viscous",
            Effect::Stribeck => "stribeck",
            Effect::AsymmetricFriction => "asymmetric_friction",
            Effect::Offset => "offset",
            Effect::Payload => "payload",
            Effect::TimeDelay => "time_delay",
            Effect::Cogging => "cogging",
            Effect::TorqueGain => "torque_gain",
            Effect::Elasticity => "elasticity",
            Effect::Backlash => "backlash",
            Effect::JointOffset => "joint_offset",
        }
    }

    /// Its parameters.
    pub fn params(self) -> Vec<Param> {
        Param::ALL
            .iter()
            .copied()
            .filter(|p| p.effects().contains(&self))
            .collect()
    }

    /// `a, b, c` of every effect's name.
    pub fn names() -> String {
        Self::ALL.map(Effect::name).join(", ")
    }

    /// Whether it makes the transmission compliant (a link-side simulation).
    pub fn is_compliance(self) -> bool {
        matches!(self, Effect::Elasticity | Effect::Backlash)
    }
}

impl fmt::Display for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Effect {
    type Err = DynamicsError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        by_name(&Self::ALL, Effect::name, s, "effect", Self::names)
    }
}

/// The item of `all` named `s` (trimmed), or an error listing the valid names.
fn by_name<T: Copy>(
    all: &[T],
    name: fn(T) -> &'static str,
    s: &str,
    what: &'static str,
    valid: fn() -> String,
) -> Result<T, DynamicsError> {
    all.iter()
        .copied()
        .find(|x| name(*x) == s.trim())
        .ok_or_else(|| DynamicsError::UnknownName {
            what,
            name: s.trim().to_string(),
            valid: valid(),
        })
}

/// Defines [`Param`] and [`EffectParams`] from one table: field, variant,
/// the effects it belongs to, default, unit, doc.
macro_rules! effect_params {
    ($( $(#[doc = $doc:literal])+ $field:ident, $variant:ident, [$($effect:ident),+], $default:expr; )+) => {
        /// The name of one effect parameter.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        pub enum Param {
            $( $(#[doc = $doc])+ $variant, )+
        }

        impl Param {
            /// Every parameter.
            pub const ALL: &'static [Param] = &[$(Param::$variant),+];

            /// The name used in `NAME=VALUE` overrides and in files.
            pub fn name(self) -> &'static str {
                match self { $(Param::$variant => stringify!($field),)+ }
            }

            /// Its documentation (meaning, unit, range).
            pub fn doc(self) -> &'static str {
                match self { $(Param::$variant => concat!($($doc),+).trim_ascii(),)+ }
            }

            /// Its built-in default (before a robot's `[effects]` table).
            pub fn default_value(self) -> f64 {
                match self { $(Param::$variant => $default,)+ }
            }

            /// The effects it belongs to.
            pub fn effects(self) -> &'static [Effect] {
                match self { $(Param::$variant => &[$(Effect::$effect),+],)+ }
            }
        }

        /// Every effect's magnitudes (per robot: the description's
        /// `[effects]` table over these defaults; per run: overrides).
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct EffectParams {
            $( $(#[doc = $doc])+ pub $field: f64, )+
        }

        impl Default for EffectParams {
            fn default() -> Self {
                Self { $($field: $default,)+ }
            }
        }

        impl EffectParams {
            /// The value of one parameter.
            pub fn get(&self, p: Param) -> f64 {
                match p { $(Param::$variant => self.$field,)+ }
            }

            fn slot(&mut self, p: Param) -> &mut f64 {
                match p { $(Param::$variant => &mut self.$field,)+ }
            }
        }
    };
}

effect_params! {
    /// Scale of the robot's nominal Coulomb friction (1: as described).
    coulomb_scale, CoulombScale, [Coulomb, AsymmetricFriction], 1.0;
    /// Scale of the robot's nominal viscous friction (1: as described).
    viscous_scale, ViscousScale, [Viscous], 1.0;
    /// Stribeck peak F_s (N·m).
    stribeck_force, StribeckForce, [Stribeck], 1.0;
    /// Stribeck velocity v_s (rad/s), > 0.
    stribeck_velocity, StribeckVelocity, [Stribeck], 0.2;
    /// Asymmetry a: Coulomb (1 + a)·B_c forward, (1 − a)·B_c backward.
    asymmetry, Asymmetry, [AsymmetricFriction], 0.3;
    /// Torque offset (N·m), every joint.
    offset, Offset, [Offset], 0.5;
    /// Payload mass (kg) at the tool point, ≥ 0.
    payload_mass, PayloadMass, [Payload], 0.5;
    /// Delay δ (s) between state and torque, ≥ 0.
    delay, Delay, [TimeDelay], 0.005;
    /// Cogging amplitude A (N·m).
    cogging_amplitude, CoggingAmplitude, [Cogging], 0.2;
    /// Cogging periods p per motor turn.
    cogging_period, CoggingPeriod, [Cogging], 6.0;
    /// Torque gain error ε (measured (1 + ε) τ), > −1.
    gain_error, GainError, [TorqueGain], 0.1;
    /// Transmission stiffness K (N·m/rad), > 0.
    stiffness, Stiffness, [Elasticity, Backlash], 2000.0;
    /// Transmission damping D (N·m·s/rad), ≥ 0.
    damping, Damping, [Elasticity, Backlash], 5.0;
    /// Dead-band half-width b (rad), ≥ 0.
    backlash_width, BacklashWidth, [Backlash], 0.005;
    /// Encoder zero offset δ (rad or m), every joint: true q = measured q + δ; |δ| ≤ 0.5.
    joint_offset, JointOffsetValue, [JointOffset], 0.05;
}

/// The largest magnitude of any effect parameter: beyond it the simulated
/// torques leave the range the data readers accept.
pub const MAX_ABS_EFFECT: f64 = 1e6;
/// The longest time delay (s) an effect may have.
pub const MAX_DELAY_S: f64 = 1.0;

impl Param {
    /// One line per parameter: name, effects, meaning and unit, built-in
    /// default (for `simulate --help`).
    pub fn help_table() -> String {
        Self::ALL
            .iter()
            .map(|p| {
                let effects: Vec<&str> = p.effects().iter().map(|e| e.name()).collect();
                format!(
                    "  {} ({}): {} Default {}.",
                    p.name(),
                    effects.join(", "),
                    p.doc(),
                    p.default_value()
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// `a, b, c` of every parameter's name.
    pub fn names() -> String {
        Self::ALL
            .iter()
            .map(|p| p.name())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Whether `v` is an admissible value (finite, and within the physical
    /// range its doc states).
    fn admits(self, v: f64) -> bool {
        v.is_finite()
            && v.abs() <= MAX_ABS_EFFECT
            && match self {
                Param::StribeckVelocity | Param::Stiffness | Param::CoggingPeriod => v > 0.0,
                Param::Delay => (0.0..=MAX_DELAY_S).contains(&v),
                Param::PayloadMass | Param::Damping | Param::BacklashWidth => v >= 0.0,
                Param::GainError => v > -1.0,
                Param::Asymmetry => (-1.0..=1.0).contains(&v),
                Param::JointOffsetValue => v.abs() <= 0.5,
                _ => true,
            }
    }
}

impl fmt::Display for Param {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Param {
    type Err = DynamicsError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        by_name(Self::ALL, Param::name, s, "effect parameter", Self::names)
    }
}

impl EffectParams {
    /// Sets one parameter, checking its range.
    pub fn set(&mut self, p: Param, v: f64) -> Result<(), DynamicsError> {
        if !p.admits(v) {
            return Err(DynamicsError::EffectParameter {
                name: p.name(),
                value: v,
            });
        }
        *self.slot(p) = v;
        Ok(())
    }

    /// Checks every parameter's range (e.g. after reading a sidecar).
    pub fn validate(&self) -> Result<(), DynamicsError> {
        for &p in Param::ALL {
            if !p.admits(self.get(p)) {
                return Err(DynamicsError::EffectParameter {
                    name: p.name(),
                    value: self.get(p),
                });
            }
        }
        Ok(())
    }
}

/// Parses `NAME=VALUE` into a parameter and its value.
pub fn parse_override(s: &str) -> Result<(Param, f64), DynamicsError> {
    let (k, v) = s.split_once('=').ok_or_else(|| DynamicsError::Override {
        text: s.to_string(),
        message: "expected NAME=VALUE".into(),
    })?;
    let p: Param = k.parse()?;
    let value: f64 = v.trim().parse().map_err(|_| DynamicsError::Override {
        text: s.to_string(),
        message: format!("'{}' is not a number", v.trim()),
    })?;
    Ok((p, value))
}
