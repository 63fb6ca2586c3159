//! The design itself: the search, the pool bound, the report and the
//! samples written.

use super::ExciteOptions;
use super::design::{Criterion, check_size, optimal_weights};
use super::error::ExciteError;
use super::fourier::Coefficients;
use super::information::{InfoBasis, condition_number, score};
use super::limits::{JointLimits, joint_limits};
use crate::data::Dataset;
use crate::dynamics::{RobotDescription, Samples};
use crate::sim::trajectory::Trajectory;
use faer::Mat;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;
use serde::Serialize;

/// Samples per period and harmonic the information is taken on.
const INFO_SAMPLES: usize = 40;

/// The convex pool's bound.
#[derive(Clone, Debug, Serialize)]
pub struct PoolReport {
    /// Candidates (random motions fitted to the limits, and the designed one).
    pub candidates: usize,
    /// The optimum over mixtures of the candidates (the criterion's value;
    /// λ_min for E and cond).
    pub bound: f64,
    /// The designed motion's value of the same quantity.
    pub designed: f64,
    /// D: `exp((log det F − bound) / k)`, the designed motion's
    /// D-efficiency against the best mixture; E/cond: designed / bound.
    pub efficiency: f64,
    /// The weight of each candidate (the designed one last).
    pub weights: Vec<f64>,
}

/// A designed excitation and what it gives.
#[derive(Clone, Debug, Serialize)]
pub struct Designed {
    /// The robot.
    pub robot: String,
    /// The settings.
    pub options: ExciteOptions,
    /// How it was designed.
    pub method: String,
    /// The motion (its Fourier coefficients).
    pub trajectory: Trajectory,
    /// Base parameters the information is taken on.
    pub base_parameters: usize,
    /// The criterion's value (larger is better).
    pub value: f64,
    /// `log det F` of the design.
    pub log_det: f64,
    /// The condition number of the scaled base regressor.
    pub condition_number: f64,
    /// The criterion's value of the best random seed before the search.
    pub best_seed_value: f64,
    /// The limits kept.
    pub limits: Vec<JointLimits>,
    /// Per joint, the smallest margin to each limit, as a fraction of it:
    /// `[position, velocity, acceleration]`.
    pub margins: Vec<[f64; 3]>,
    /// Per joint with an effort limit, `1 − peak |τ| / limit` of the
    /// description's model (rigid bodies, rotors, nominal friction) along the
    /// motion: negative where the motion needs more torque than the joint
    /// has (checked, not enforced).
    pub torque_margins: Vec<Option<f64>>,
    /// The convex pool's bound (with `pool > 0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pool: Option<PoolReport>,
    /// What the motion separates (a design by [`super::separate()`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation: Option<super::separation::Separation>,
}

/// `F` of a Fourier trajectory over one period.
fn info_of(
    basis: &InfoBasis,
    traj: &Trajectory,
    harmonics: usize,
) -> Result<Mat<f64>, ExciteError> {
    let (_, s) = period_samples(traj, harmonics)?;
    basis.information(&s[0], &s[1], &s[2])
}

/// A Fourier trajectory at `INFO_SAMPLES` points per harmonic over one
/// period: the times (s) and `[q, q̇, q̈]`, each sample-major (n per
/// sample).
pub(super) fn period_samples(
    traj: &Trajectory,
    harmonics: usize,
) -> Result<(Vec<f64>, [Vec<f64>; 3]), ExciteError> {
    let Trajectory::Fourier { omega, .. } = traj else {
        return Err(ExciteError::Pool {
            problem: "a Fourier trajectory is needed",
        });
    };
    let m = INFO_SAMPLES * harmonics.max(1);
    let period = 2.0 * std::f64::consts::PI / omega;
    let mut s = [vec![], vec![], vec![]];
    let t: Vec<f64> = (0..m).map(|i| period * i as f64 / m as f64).collect();
    for &ti in &t {
        let st = traj.exact_state(ti).unwrap_or_default();
        for (v, x) in s.iter_mut().zip(st) {
            v.extend(x);
        }
    }
    Ok((t, s))
}

/// Random coefficients (uniform in ±1/k for harmonic k).
fn random_coefficients(n: usize, h: usize, omega: f64, seed: u64) -> Coefficients {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let ab = (0..n)
        .map(|_| {
            (0..2 * h)
                .map(|i| rng.random_range(-1.0..1.0) / (i % h + 1) as f64)
                .collect()
        })
        .collect();
    Coefficients { omega, ab }
}

/// What a search maximises: a motion's value (larger is better).
pub(super) type Objective<'a> = dyn Fn(&Trajectory) -> Result<f64, ExciteError> + Sync + 'a;

/// The compass search from `start`: (value, coefficients, start's value).
fn search(
    limits: &[JointLimits],
    start: Coefficients,
    opts: &ExciteOptions,
    objective: &Objective,
) -> Result<(f64, Coefficients, f64), ExciteError> {
    let eval = |c: &Coefficients| -> Result<f64, ExciteError> { objective(&c.fitted(limits)?) };
    let (mut best, mut x) = (eval(&start)?, start);
    let first = best;
    let (mut step, mut evals) = (0.25, 1);
    while evals < opts.evaluations && step > 1e-3 {
        let mut improved = false;
        for j in 0..x.ab.len() {
            for i in 0..x.ab[j].len() {
                for sign in [1.0, -1.0] {
                    if evals >= opts.evaluations {
                        return Ok((best, x, first));
                    }
                    let mut y = x.clone();
                    y.ab[j][i] += sign * step;
                    let v = eval(&y)?;
                    evals += 1;
                    if v > best {
                        (best, x, improved) = (v, y, true);
                        break;
                    }
                }
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    Ok((best, x, first))
}

/// The best motion over `opts.seeds` searches in parallel: (value, the
/// motion fitted into `limits`, the best start's value).
pub(super) fn best_of_seeds(
    limits: &[JointLimits],
    omega: f64,
    opts: &ExciteOptions,
    objective: &Objective,
) -> Result<(f64, Trajectory, f64), ExciteError> {
    let n = limits.len();
    let runs: Vec<_> = (0..opts.seeds as u64)
        .into_par_iter()
        .map(|s| {
            let start = random_coefficients(n, opts.harmonics, omega, opts.seed + s);
            search(limits, start, opts, objective)
        })
        .collect::<Result<_, _>>()?;
    let best_seed_value = runs.iter().map(|r| r.2).fold(f64::NEG_INFINITY, f64::max);
    let (value, coef, _) = (runs.into_iter())
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .ok_or(ExciteError::Pool { problem: "no seed" })?;
    Ok((value, coef.fitted(limits)?, best_seed_value))
}

/// The base frequency: `base_hz` rounded so that `seconds` holds a whole
/// number (≥ 1) of periods.
pub(super) fn omega_for(opts: &ExciteOptions) -> Result<f64, ExciteError> {
    let checks = [
        ("seconds", opts.seconds, 1e6),
        ("base_hz", opts.base_hz, 100.0),
        ("harmonics", opts.harmonics as f64, 50.0),
        ("seeds", opts.seeds as f64, 1e4),
    ];
    for (setting, value, most) in checks {
        if !(value > 0.0 && value <= most) {
            return Err(ExciteError::Setting {
                setting,
                value,
                requirement: "must be positive and within its range (seconds ≤ 1e6, base_hz ≤ 100, harmonics ≤ 50, seeds ≤ 1e4)",
            });
        }
    }
    let periods = (opts.seconds * opts.base_hz).round().max(1.0);
    Ok(2.0 * std::f64::consts::PI * periods / opts.seconds)
}

/// The convex criterion a pool design uses for `c` (D, or E for E and cond).
fn convex_of(c: Criterion) -> Criterion {
    if c == Criterion::D {
        Criterion::D
    } else {
        Criterion::E
    }
}

/// Designs an excitation for `robot` with `opts`.
pub fn design(robot: &RobotDescription, opts: &ExciteOptions) -> Result<Designed, ExciteError> {
    let omega = omega_for(opts)?;
    let basis = InfoBasis::of(&robot.model)?;
    if opts.pool > 0 {
        // before the search: the pool (+ the designed motion) must fit
        let k = basis.len();
        check_size(k, opts.pool.saturating_add(1), convex_of(opts.criterion))?;
    }
    let limits = joint_limits(robot);
    let objective = |t: &Trajectory| -> Result<f64, ExciteError> {
        Ok(score(&info_of(&basis, t, opts.harmonics)?, opts.criterion))
    };
    let (value, trajectory, best_seed_value) = best_of_seeds(&limits, omega, opts, &objective)?;
    let f = info_of(&basis, &trajectory, opts.harmonics)?;
    if !(value.is_finite() && score(&f, Criterion::D).is_finite()) {
        return Err(ExciteError::Singular {
            parameters: basis.len(),
        });
    }
    let pool = (opts.pool > 0)
        .then(|| pool_bound(&basis, &limits, &f, opts, omega))
        .transpose()?;
    let method = format!(
        "compass search of {} Fourier coefficients per joint from {} random seeds, {} evaluations each at most; the criterion on the information of {} base parameters over one period",
        2 * opts.harmonics,
        opts.seeds,
        opts.evaluations,
        basis.len()
    );
    let mut d = designed(
        robot,
        opts,
        (limits, trajectory),
        (value, best_seed_value),
        method,
    )?;
    d.pool = pool;
    Ok(d)
}

/// The report of `trajectory` (fitted into `limits`), found with `value`
/// (the best start's: `best_seed_value`) by `method`: its margins and its
/// information on the base parameters.
pub(super) fn designed(
    robot: &RobotDescription,
    opts: &ExciteOptions,
    (limits, trajectory): (Vec<JointLimits>, Trajectory),
    (value, best_seed_value): (f64, f64),
    method: String,
) -> Result<Designed, ExciteError> {
    let basis = InfoBasis::of(&robot.model)?;
    let f = info_of(&basis, &trajectory, opts.harmonics)?;
    let omega = match &trajectory {
        Trajectory::Fourier { omega, .. } => *omega,
        _ => omega_for(opts)?,
    };
    Ok(Designed {
        robot: robot.source.clone(),
        options: opts.clone(),
        method,
        margins: margins(&trajectory, &limits, omega),
        torque_margins: torque_margins(robot, &trajectory, &limits, omega)?,
        base_parameters: basis.len(),
        value,
        log_det: score(&f, Criterion::D),
        condition_number: condition_number(&f),
        best_seed_value,
        limits,
        trajectory,
        pool: None,
        separation: None,
    })
}

/// The convex design over `opts.pool` random candidates and the designed
/// motion.
fn pool_bound(
    basis: &InfoBasis,
    limits: &[JointLimits],
    f: &Mat<f64>,
    opts: &ExciteOptions,
    omega: f64,
) -> Result<PoolReport, ExciteError> {
    let n = limits.len();
    let convex = convex_of(opts.criterion);
    let mut pool: Vec<Mat<f64>> = (0..opts.pool as u64)
        .into_par_iter()
        .map(|s| {
            let c = random_coefficients(n, opts.harmonics, omega, 1_000_003 + opts.seed + s);
            info_of(basis, &c.fitted(limits)?, opts.harmonics)
        })
        .collect::<Result<_, ExciteError>>()?;
    pool.push(f.clone());
    let d = optimal_weights(&pool, convex)?;
    let mine = score(f, convex);
    let k = f.nrows() as f64;
    Ok(PoolReport {
        candidates: pool.len(),
        bound: d.optimum,
        designed: mine,
        efficiency: if convex == Criterion::D {
            ((mine - d.optimum) / k).exp()
        } else {
            mine / d.optimum
        },
        weights: d.weights,
    })
}

/// Per joint, the smallest relative margin to its position, velocity and
/// acceleration limits over one period at 64 points per harmonic.
fn margins(traj: &Trajectory, limits: &[JointLimits], omega: f64) -> Vec<[f64; 3]> {
    let period = 2.0 * std::f64::consts::PI / omega;
    let steps = super::fourier::GRID
        * traj
            .top_hz()
            .map_or(1, |f| (f * period).round().max(1.0) as usize);
    let mut m = vec![[1.0f64; 3]; limits.len()];
    for i in 0..steps {
        let Some([q, qd, qdd]) = traj.exact_state(period * i as f64 / steps as f64) else {
            break;
        };
        for (j, l) in limits.iter().enumerate() {
            let half = 0.5 * (l.position.1 - l.position.0);
            let mid = 0.5 * (l.position.1 + l.position.0);
            m[j][0] = m[j][0].min(1.0 - (q[j] - mid).abs() / half);
            m[j][1] = m[j][1].min(1.0 - qd[j].abs() / l.velocity);
            m[j][2] = m[j][2].min(1.0 - qdd[j].abs() / l.acceleration);
        }
    }
    m
}

/// Per joint with an effort limit, its margin to the peak torque of the
/// description's model over one period (64 points per harmonic).
fn torque_margins(
    robot: &RobotDescription,
    traj: &Trajectory,
    limits: &[JointLimits],
    omega: f64,
) -> Result<Vec<Option<f64>>, ExciteError> {
    if limits.iter().all(|l| l.effort.is_none()) {
        return Ok(vec![None; limits.len()]);
    }
    let period = 2.0 * std::f64::consts::PI / omega;
    let steps = super::fourier::GRID
        * traj
            .top_hz()
            .map_or(1, |f| (f * period).round().max(1.0) as usize);
    let mut data = crate::dynamics::Data::new(&robot.model);
    let mut peak = vec![0.0f64; limits.len()];
    for i in 0..steps {
        let Some([q, qd, qdd]) = traj.exact_state(period * i as f64 / steps as f64) else {
            break;
        };
        let tau = crate::dynamics::rnea(&robot.model, &mut data, &q, &qd, &qdd)?;
        for (j, p) in peak.iter_mut().enumerate() {
            let f = robot.friction.torque(j, qd[j], tau[j]);
            *p = p.max((tau[j] + f).abs());
        }
    }
    Ok((limits.iter().zip(peak))
        .map(|(l, p)| l.effort.map(|e| 1.0 - p / e))
        .collect())
}

/// The designed motion sampled at `rate_hz` over its `seconds` (exact
/// derivatives), each sample checked against the limits.
pub fn samples(d: &Designed, rate_hz: f64) -> Result<Dataset, ExciteError> {
    if !(rate_hz > 0.0 && rate_hz <= 1e5) {
        return Err(ExciteError::Setting {
            setting: "rate_hz",
            value: rate_hz,
            requirement: "must be in (0, 1e5]",
        });
    }
    let names: Vec<&str> = d.limits.iter().map(|l| l.joint.as_str()).collect();
    let exact = d.options.seconds * rate_hz;
    let count = exact.round();
    if (exact - count).abs() > 1e-6 * exact.max(1.0) {
        return Err(ExciteError::Setting {
            setting: "rate_hz",
            value: rate_hz,
            requirement: "must give a whole number of samples over the motion (seconds × rate), so that the written period repeats",
        });
    }
    if count > crate::sim::simulate::MAX_SAMPLES as f64 {
        return Err(ExciteError::Setting {
            setting: "seconds × rate_hz (samples)",
            value: count,
            requirement: "must be at most 1e7 samples",
        });
    }
    let count = count as usize;
    let mut out = Dataset::empty(&names);
    for i in 0..count {
        let t = i as f64 / rate_hz;
        let [q, qd, qdd] = d.trajectory.exact_state(t).ok_or(ExciteError::Pool {
            problem: "a Fourier trajectory is needed",
        })?;
        check_sample(&d.limits, t, [&q, &qd, &qdd])?;
        out.t.push(t);
        out.q.push(&q);
        out.qd.push(&qd);
        out.qdd.push(&qdd);
    }
    out.tau = Samples::new(names.len());
    Ok(out)
}

/// A sample within every limit, else the first one it leaves.
fn check_sample(limits: &[JointLimits], t: f64, s: [&[f64]; 3]) -> Result<(), ExciteError> {
    for (j, l) in limits.iter().enumerate() {
        let bad = |what, value: f64, limit: f64| ExciteError::Limit {
            joint: l.joint.clone(),
            what,
            t,
            value,
            limit,
        };
        if s[0][j] < l.position.0 || s[0][j] > l.position.1 {
            let lim = if s[0][j] < l.position.0 {
                l.position.0
            } else {
                l.position.1
            };
            return Err(bad("position", s[0][j], lim));
        }
        if s[1][j].abs() > l.velocity {
            return Err(bad("velocity", s[1][j], l.velocity));
        }
        if s[2][j].abs() > l.acceleration {
            return Err(bad("acceleration", s[2][j], l.acceleration));
        }
    }
    Ok(())
}
