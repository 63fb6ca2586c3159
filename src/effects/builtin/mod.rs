//! The built-in effects, one file each. The registry below is the one list:
//! its order is the order the diagnosis tries them (and reports ties in)
//! and the simulator applies them. A new built-in effect is a new file
//! here implementing [`super::Effect`] and one line in `registry!`
//! (`friction.rs` is not an effect: what the friction effects share).

use super::effect::Effect;
use std::sync::Arc;

mod friction;

/// Declares each effect's module and lists the effects in order.
macro_rules! registry {
    ($($module:ident :: $effect:ident),+ $(,)?) => {
        $(pub mod $module;)+

        /// Every built-in effect, in the registry's order.
        pub fn all() -> Vec<Arc<dyn Effect>> {
            vec![$(Arc::new($module::$effect)),+]
        }
    };
}

registry! {
    coulomb::Coulomb,
    viscous::Viscous,
    stribeck::Stribeck,
    offset::Offset,
    asymmetric_friction::AsymmetricFriction,
    load_friction::LoadFriction,
    friction_drift::FrictionDrift,
    rotor_inertia::RotorInertia,
    link_inertia::LinkInertia,
    payload::Payload,
    time_delay::TimeDelay,
    cogging::Cogging,
    ripple::Ripple,
    torque_gain::TorqueGain,
    elasticity::Elasticity,
    backlash::Backlash,
    joint_offset::JointOffset,
}
