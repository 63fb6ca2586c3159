//! A compliance hypothesis' per-joint parameters: stiffness, damping, dead
//! band and the axial inertia moved from the rotor to the link.

use crate::sim::compliance::Compliance;

/// Per-joint transmission parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Transmission {
    /// Stiffness K_i (N·m/rad).
    pub stiffness: Vec<f64>,
    /// Damping D_i (N·m·s/rad).
    pub damping: Vec<f64>,
    /// Dead-band half-width b_i (rad).
    pub backlash: Vec<f64>,
    /// Axial inertia moved from the rotor to link i (kg·m²).
    pub axial_shift: Vec<f64>,
}

impl Transmission {
    /// Joint i's spring–damper and dead band.
    pub fn spring(&self, i: usize) -> Compliance {
        Compliance {
            stiffness: self.stiffness[i],
            damping: self.damping[i],
            backlash: self.backlash[i],
        }
    }

    /// The transmitted torque of joint i at deflection x and rate xd.
    #[inline]
    pub fn torque(&self, i: usize, x: f64, xd: f64) -> f64 {
        self.spring(i).torque(x, xd)
    }
}
