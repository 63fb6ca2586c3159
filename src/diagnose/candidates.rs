//! The library of candidate effects, each a group of extra regressor columns
//! built from the data and the nominal model's prediction τ̂.

use crate::data::Dataset;
use crate::dynamics::params_file::Friction;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Data, Model, regressor, sign};

/// Candidate names, in the order they are tried.
pub const CANDIDATES: [&str; 13] = [
    "coulomb",
    "viscous",
    "stribeck",
    "asymmetric_friction",
    "offset",
    "rotor_inertia",
    "link_inertia",
    "payload",
    "time_delay",
    "cogging",
    "torque_gain",
    "elasticity",
    "backlash",
];

/// Columns of one candidate: `cols[c][k·n + i]` for sample k, joint i.
pub struct Columns {
    /// Candidate name.
    pub name: &'static str,
    /// Description of the chosen nonlinear parameter, if any.
    pub detail: String,
    /// Column-major: one Vec per column, rows = samples × joints.
    pub cols: Vec<Vec<f64>>,
    /// Inertial correction: the nominal parameters of the corrected bodies
    /// (10 columns each, in order); the fit keeps `J(π + β) ⪰ 0` for each.
    pub bodies: Vec<[f64; 10]>,
    /// The coefficients must be ≥ 0 (a payload mass).
    pub nonneg: bool,
    /// Nonlinear parameters chosen by search before the linear fit (a delay,
    /// a Stribeck velocity, a stiffness per joint, …); they count in ΔBIC.
    pub nonlinear: usize,
}

fn zeros(rows: usize) -> Vec<f64> {
    vec![0.0; rows]
}

/// Per-joint columns from a per-sample scalar function of joint i.
fn per_joint(d: &Dataset, f: impl Fn(usize, usize) -> f64) -> Vec<Vec<f64>> {
    let n = d.joints.len();
    (0..n)
        .map(|i| {
            let mut c = zeros(d.len() * n);
            for k in 0..d.len() {
                c[k * n + i] = f(k, i);
            }
            c
        })
        .collect()
}

/// The nominal prediction τ̂ flattened (sample-major).
pub fn flat(v: &[Vec<f64>]) -> Vec<f64> {
    v.iter().flatten().copied().collect()
}

/// Builds the columns of candidate `name` (nonlinear parameters on a grid
/// are returned as separate variants; the caller picks the best on training data).
pub fn build(name: &'static str, model: &Model, friction: &Friction, d: &Dataset) -> Vec<Columns> {
    let n = d.joints.len();
    let rows = d.len() * n;
    let gear: Vec<f64> = (0..n)
        .map(|i| model.rotor_of(i).map_or(1.0, |r| r.gear_ratio))
        .collect();
    let tau_hat = || predict_torques(model, friction, &d.q, &d.qd, &d.qdd).unwrap_or_default();
    let one = |cols: Vec<Vec<f64>>| {
        vec![Columns {
            name,
            detail: String::new(),
            cols,
            bodies: vec![],
            nonneg: false,
            nonlinear: 0,
        }]
    };
    match name {
        "coulomb" => one(per_joint(d, |k, i| sign(d.qd[k][i]))),
        "viscous" => one(per_joint(d, |k, i| d.qd[k][i])),
        "offset" => one(per_joint(d, |_, _| 1.0)),
        "asymmetric_friction" => one(per_joint(d, |k, i| sign(d.qd[k][i]).abs())),
        "stribeck" => [0.05, 0.1, 0.2, 0.5]
            .iter()
            .map(|&vs| Columns {
                name,
                detail: format!("Stribeck velocity {vs} rad/s"),
                cols: per_joint(d, |k, i| {
                    (-(d.qd[k][i] / vs).powi(2)).exp() * sign(d.qd[k][i])
                }),
                bodies: vec![],
                nonneg: false,
                nonlinear: 1,
            })
            .collect(),
        "cogging" => (1..=12)
            .map(|p| {
                let p = p as f64;
                let mut cols = per_joint(d, |k, i| (p * gear[i] * d.q[k][i]).sin());
                cols.extend(per_joint(d, |k, i| (p * gear[i] * d.q[k][i]).cos()));
                Columns {
                    name,
                    detail: format!("period {p} per motor turn"),
                    cols,
                    bodies: vec![],
                    nonneg: false,
                    nonlinear: 1,
                }
            })
            .collect(),
        "torque_gain" => one(vec![flat(&tau_hat())]),
        "time_delay" => {
            let th = tau_hat();
            let dt = if d.len() > 1 {
                (d.t[d.len() - 1] - d.t[0]) / (d.len() - 1) as f64
            } else {
                1e-3
            };
            [1usize, 2, 3, 5, 8, 12, 20, 30]
                .iter()
                .map(|&s| {
                    let mut c = zeros(rows);
                    for k in 0..d.len() {
                        let j = k.saturating_sub(s);
                        for i in 0..n {
                            c[k * n + i] = th[j][i] - th[k][i];
                        }
                    }
                    Columns {
                        name,
                        detail: format!("delay {:.0} ms", 1e3 * s as f64 * dt),
                        cols: vec![c],
                        bodies: vec![],
                        nonneg: false,
                        nonlinear: 1,
                    }
                })
                .collect()
        }
        "link_inertia" | "rotor_inertia" | "payload" => {
            let nl = 10 * model.dof();
            let nb = model.num_bodies();
            let (lo, hi) = match name {
                "link_inertia" => (0, nl),
                "rotor_inertia" => (nl, 10 * nb),
                _ => (0, 0),
            };
            let mut data = Data::new(model);
            let mut cols: Vec<Vec<f64>> =
                vec![zeros(rows); if name == "payload" { 1 } else { hi - lo }];
            // payload: a point mass at the last body's tool point (cheetah3-leg: the foot)
            let last = model.dof() - 1;
            let at = if model.name == "cheetah3-leg" {
                nalgebra::Vector3::from(crate::dynamics::cheetah3::FOOT)
            } else {
                nalgebra::Vector3::zeros()
            };
            let unit = crate::moments::InertialParams::from_mass_com_inertia(
                1.0,
                at,
                nalgebra::Matrix3::zeros(),
            );
            for k in 0..d.len() {
                let Ok(y) = regressor(model, &mut data, &d.q[k], &d.qd[k], &d.qdd[k]) else {
                    continue;
                };
                for i in 0..n {
                    if name == "payload" {
                        cols[0][k * n + i] =
                            (0..10).map(|c| y[(i, 10 * last + c)] * unit.0[c]).sum();
                    } else {
                        for (c, col) in cols.iter_mut().enumerate() {
                            col[k * n + i] = y[(i, lo + c)];
                        }
                    }
                }
            }
            if cols.is_empty() {
                return vec![];
            }
            let p = model.params();
            let bodies: Vec<[f64; 10]> = (lo / 10..hi / 10)
                .map(|b| std::array::from_fn(|k| p[10 * b + k]))
                .collect();
            vec![Columns {
                name,
                detail: String::new(),
                cols,
                bodies,
                nonneg: name == "payload",
                nonlinear: 0,
            }]
        }
        // fitted to the residual by `super::compliance` (see `diagnose`)
        "elasticity" | "backlash" => vec![],
        _ => vec![],
    }
}
