//! The compliance hypotheses (`elasticity`, `backlash`): the links driven
//! from the measured motor side θ(t) through a spring–damper per joint
//! (stiffness `K_i` N·m/rad, damping `D_i` N·m·s/rad, dead-band half-width
//! `b_i` rad; `b = 0` for elasticity), fitted on the training part.
//!
//! The link side is the current model's [`Model::link_side`] (rotor housings
//! welded to their mounts, rotor spin on the motor side). Its deflection
//! `x = θ − q_L` is small, so the link dynamics are linearised along the
//! measured motion (precomputed once per data set, [`Linearisation`]):
//!
//! ```text
//! M(θ) ẍ = τ_L(θ, θ̇, θ̈) − G x − C ẋ − τ_s(x, ẋ)
//! τ_s,i = K_i dz(x_i, b_i) + D_i ẋ_i [|x_i| > b_i]
//! G = ∂τ_L/∂q,  C = ∂τ_L/∂q̇  (at the measured state)
//! ```
//!
//! which is ~100× cheaper to integrate than the full link dynamics. The
//! coefficients are solved for the acceleration once per data set and axial
//! shift, at every sample (the nodes: `ẍ = b − P x − Q ẋ − A τ_s`, `A = M⁻¹`;
//! the shifts of recent simulations are cached), so a step is four
//! matrix–vector products: RK4, one step per sample, its middle node the
//! mean of its ends; a step in which a joint enters or leaves its dead band
//! is redone in 16 substeps on interpolated nodes, since the spring force
//! has a kink there. The loops are compiled for each joint count up to 7.
//! The hypothesis is searched in three stages:
//!
//! 1. a grid shared by every joint over K (150 … 8,000 N·m/rad: 15 values
//!    for elasticity; 8 for backlash, with 7 dead bands 0.001 … 0.023 rad,
//!    each joint's pick then refined on a 3 × 3 (K, b) grid), damping ratio
//!    ζ (0.05, 0.15, 0.4), on the first 3 s of the training part; each
//!    joint takes the grid point that explains its own residual best
//!    (scaled by its best coefficient, so the grid judges timing, not
//!    amplitude);
//! 2. coordinate descent over the whole training part (one sweep for
//!    elasticity, two for backlash): per joint a local (K_i, D_i, b_i) grid
//!    (3 × 3 for elasticity, 5 × 5 × 3 for backlash), then the axial split
//!    s_i at a fixed ringing frequency K_i / (M_ii + s_i);
//! 3. Levenberg–Marquardt on (ln K_i, ln D_i, b_i, s_i).
//!
//! The damping matters as much as K: the spring–damper's torque jumps by
//! D ẋ at each impact. The candidate's columns are, per joint, the torque
//! the hypothesis changes: `τ_s − τ_L(θ)`. A rigid model cannot tell how the
//! inertia about a joint axis is shared between the link and the rotor (the
//! rotor's `N² I_zz` and the link's axial inertia enter rigid torques as one
//! sum), but the link's ringing depends on it, hence the fitted shift s_i.
//!
//! Files: `transmission` (the parameters), `nodes` (the dynamics solved per
//! sample), `sinks` (what a simulation feeds), `integrate` (the lock-step
//! RK4), `linearisation` (the precomputation, its node cache and the
//! simulations), `search` (the three stages); this file turns a fit into
//! the hypothesis' columns.

mod integrate;
mod linearisation;
mod nodes;
mod search;
mod sinks;
mod transmission;

pub use linearisation::Linearisation;
pub use search::{ComplianceFit, WARM_UP, fit};
pub use transmission::Transmission;

use super::hypothesis::Columns;
use crate::dynamics::Model;

/// Bytes a compliance search over `samples` samples of `n` joints holds:
/// per sample M, ∂τ/∂q, ∂τ/∂q̇ and one ∂M/∂sᵢ per joint (n³ in all), τ_L
/// and its shifts, and the node sets its simulations are solved on
/// ([`linearisation::NODE_SETS`]).
pub(crate) fn memory_bytes(n: usize, samples: usize) -> u64 {
    let n6 = n as u64;
    8 * samples as u64
        * (3 * n6 * n6
            + n6 * n6 * n6
            + n6 * n6
            + 4 * n6
            + linearisation::NODE_SETS * nodes::node_values(n))
}

/// Whether `model` has a motor side the data could show a compliance of:
/// a rotor on some joint.
pub(crate) fn has_motor_side(model: &Model) -> bool {
    (0..model.dof()).any(|j| model.rotor_of(j).is_some())
}

/// Stiffness range (N·m/rad) a robot joint's transmission is taken to have:
/// below it the joint would sag visibly under its own weight, above it the
/// spring is too stiff to ring within the data's bandwidth.
const PLAUSIBLE_STIFFNESS: (f64, f64) = (50.0, 1e5);

/// Why a fitted transmission is physically doubtful, if it is.
fn doubtful(p: &Transmission) -> Option<String> {
    let (lo, hi) = PLAUSIBLE_STIFFNESS;
    let (i, k) = p
        .stiffness
        .iter()
        .enumerate()
        .find(|(_, k)| !(lo..=hi).contains(*k))?;
    Some(format!(
        "joint {}'s fitted stiffness {k:.0} N·m/rad is outside {lo}–{hi:.0} N·m/rad",
        i + 1
    ))
}

/// The transmission recorded as a variant's key (`stiffness_i`,
/// `damping_i`, `backlash_i`, `axial_shift_i` per joint i), if it is one
/// of `n` joints.
pub fn from_key(key: &[(String, f64)], n: usize) -> Option<Transmission> {
    let get = |name: &str, i: usize| {
        let k = format!("{name}_{i}");
        key.iter()
            .find(|(x, _)| *x == k)
            .map(|(_, v)| *v)
            .filter(|v| v.is_finite())
    };
    let all = |name: &str| (0..n).map(|i| get(name, i)).collect::<Option<Vec<f64>>>();
    Some(Transmission {
        stiffness: all("stiffness")?,
        damping: all("damping")?,
        backlash: all("backlash")?,
        axial_shift: all("axial_shift")?,
    })
}

/// The key recording `p`.
fn key_of(p: &Transmission) -> Vec<(String, f64)> {
    let fields = [
        ("stiffness", &p.stiffness),
        ("damping", &p.damping),
        ("backlash", &p.backlash),
        ("axial_shift", &p.axial_shift),
    ];
    (fields.iter())
        .flat_map(|(name, v)| {
            v.iter()
                .enumerate()
                .map(move |(i, x)| (format!("{name}_{i}"), *x))
        })
        .collect()
}

/// The candidate's columns on all samples (one per joint) for a fitted
/// hypothesis (zero during the warm-up).
pub fn columns(lin: &Linearisation, fit: &ComplianceFit, backlash: bool) -> Option<Columns> {
    columns_of(lin, &fit.transmission, backlash)
}

/// The columns of the transmission `p` on the data `lin` is for.
pub fn columns_of(lin: &Linearisation, p: &Transmission, backlash: bool) -> Option<Columns> {
    let n = lin.n;
    let ns = lin.t.len();
    let h = lin.simulate(p, ns)?;
    let mut cols = vec![vec![0.0; ns * n]; n];
    for s in search::warm_up(&lin.t)..ns {
        for i in 0..n {
            cols[i][s * n + i] = h[s * n + i];
        }
    }
    let list = |v: &[f64], digits: usize| {
        v.iter()
            .map(|x| format!("{x:.digits$}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut detail = format!(
        "K = ({}) N·m/rad, D = ({}) N·m·s/rad",
        list(&p.stiffness, 0),
        list(&p.damping, 2)
    );
    if p.backlash.iter().any(|&b| b > 0.0) {
        detail = format!("dead band ±({}) rad, {detail}", list(&p.backlash, 4));
    }
    Some(Columns {
        detail,
        doubt: doubtful(p),
        cols,
        bodies: vec![],
        nonneg: false,
        // K, D and the axial split per joint, and the dead band for backlash
        nonlinear: if backlash { 4 * n } else { 3 * n },
        // the search's result, built again on other data by simulating it
        key: key_of(p),
        into_bodies: vec![],
        joints: (0..n).map(Some).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::{Transmission, doubtful};

    #[test]
    fn a_fitted_stiffness_outside_a_joints_range_is_doubtful() {
        let t = |k: f64| Transmission {
            stiffness: vec![2000.0, k],
            damping: vec![5.0; 2],
            backlash: vec![0.0; 2],
            axial_shift: vec![0.0; 2],
        };
        assert!(doubtful(&t(800.0)).is_none());
        let why = doubtful(&t(4.0)).unwrap();
        assert!(
            why.contains("joint 2") && why.contains("4 N·m/rad"),
            "{why}"
        );
        assert!(doubtful(&t(3e6)).is_some());
    }
}
