//! A motion that tells two effects apart: the diagnosis reports two
//! hypotheses as tied when they explain a motion equally; this designs
//! one, within the robot's limits, on which each one's predicted torques
//! are as far as possible from anything the other can fit.
//!
//! For a motion (one period at `INFO_SAMPLES` points per harmonic, the
//! torques those of the robot's own model), each effect's hypothesis is
//! built as the diagnosis builds it ([`crate::effects::Effect::hypothesis`],
//! the middle variant of a grid); its columns are scaled to unit norm. The
//! share of A that B cannot fit is the mean over A's columns of
//! `‖(I − P_B) a‖²` (`P_B` the projection onto B's columns); the motion's
//! value is the smaller of the two shares (A not fitted by B, B not fitted
//! by A), so that whichever is true, the other cannot mimic it. 0: the two
//! are the same hypothesis on this motion; 1: orthogonal.

use super::ExciteOptions;
use super::error::ExciteError;
use super::limits::joint_limits;
use super::report::{Designed, Objective, best_of_seeds, designed, omega_for, period_samples};
pub use super::separation::{INSEPARABLE, Separation};
use crate::data::Dataset;
use crate::dynamics::RobotDescription;
use crate::dynamics::predict::predict_torques;
use crate::effects::{Context, Effect, Library};
use crate::sim::trajectory::Trajectory;

/// Designs a motion that separates the effects `pair` of `library` on
/// `robot` (the search of [`super::design`] with the separation as its
/// criterion). Unknown names, an effect that does not apply to the robot
/// or proposes nothing on it, are named errors.
pub fn separate(
    robot: &RobotDescription,
    library: &Library,
    pair: [&str; 2],
    opts: &ExciteOptions,
) -> Result<Designed, ExciteError> {
    if pair[0].trim() == pair[1].trim() {
        return Err(ExciteError::Separate {
            why: format!(
                "'{}' is named twice: two different effects are needed",
                pair[0]
            ),
        });
    }
    let effects = [library.get(pair[0])?, library.get(pair[1])?];
    for e in &effects {
        if let Some(why) = e.inapplicable(&robot.model) {
            return Err(ExciteError::Separate {
                why: format!("'{}' does not apply to this robot: {why}", e.name()),
            });
        }
    }
    let omega = omega_for(opts)?;
    let limits = joint_limits(robot);
    let shares = |t: &Trajectory| shares(robot, [&**effects[0], &**effects[1]], t, opts.harmonics);
    let objective = |t: &Trajectory| -> Result<f64, ExciteError> {
        let [a, b] = shares(t)?;
        Ok(a.min(b))
    };
    let objective: &Objective = &objective;
    let (value, trajectory, best_start) = best_of_seeds(&limits, omega, opts, objective)?;
    let [a, b] = shares(&trajectory)?;
    let method = format!(
        "compass search of {} Fourier coefficients per joint from {} random seeds, {} evaluations each at most; the smaller share of one effect's predicted torques the other cannot fit, over one period",
        2 * opts.harmonics,
        opts.seeds,
        opts.evaluations,
    );
    let mut d = designed(
        robot,
        opts,
        (limits, trajectory),
        (value, best_start),
        method,
    )?;
    d.separation = Some(Separation {
        effects: [effects[0].name().into(), effects[1].name().into()],
        first_not_fitted_by_second: a,
        second_not_fitted_by_first: b,
        best_start,
        separable: value >= INSEPARABLE,
    });
    Ok(d)
}

/// The two shares on the motion `t`: `[A not fitted by B, B not fitted by A]`.
fn shares(
    robot: &RobotDescription,
    effects: [&dyn Effect; 2],
    t: &Trajectory,
    harmonics: usize,
) -> Result<[f64; 2], ExciteError> {
    let data = motion_data(robot, t, harmonics)?;
    let zeros = vec![0.0; data.len() * data.joints.len()];
    let cx = Context::new(&robot.model, &robot.friction, &data, &zeros, data.len());
    let cols = |e: &dyn Effect| -> Result<Vec<Vec<f64>>, ExciteError> {
        let h = e.hypothesis(&cx)?;
        let Some(v) = h.variants.get(h.variants.len() / 2) else {
            return Err(ExciteError::Separate {
                why: format!("'{}' proposes nothing on this robot", e.name()),
            });
        };
        Ok(v.cols.clone())
    };
    let (a, b) = (cols(effects[0])?, cols(effects[1])?);
    Ok([unfitted(&a, &b), unfitted(&b, &a)])
}

/// One period of `t` as a dataset whose torques are the robot's model's.
fn motion_data(
    robot: &RobotDescription,
    t: &Trajectory,
    harmonics: usize,
) -> Result<Dataset, ExciteError> {
    let (times, [q, qd, qdd]) = period_samples(t, harmonics)?;
    let names = robot.model.joint_names();
    let mut d = Dataset::empty(&names);
    let n = names.len();
    for (k, &tk) in times.iter().enumerate() {
        d.t.push(tk);
        d.q.push(&q[k * n..(k + 1) * n]);
        d.qd.push(&qd[k * n..(k + 1) * n]);
        d.qdd.push(&qdd[k * n..(k + 1) * n]);
    }
    d.tau = predict_torques(&robot.model, &robot.friction, &d.q, &d.qd, &d.qdd)?;
    Ok(d)
}

/// The mean over `a`'s nonzero columns (each scaled to unit norm) of the
/// share of its square norm outside the span of `b`'s columns; 0 when `a`
/// has no nonzero column (it does not show on the motion).
fn unfitted(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let basis = orthonormal(b);
    let shares: Vec<f64> = (a.iter())
        .filter_map(|c| {
            let norm2: f64 = c.iter().map(|x| x * x).sum();
            (norm2 > 0.0 && norm2.is_finite()).then(|| {
                let r = residual(c, &basis);
                r.iter().map(|x| x * x).sum::<f64>() / norm2
            })
        })
        .collect();
    if shares.is_empty() {
        return 0.0;
    }
    shares.iter().sum::<f64>() / shares.len() as f64
}

/// An orthonormal basis of the columns' span (modified Gram–Schmidt,
/// twice; a column within the span of those before it, to 1e-10 of its
/// norm, adds nothing).
fn orthonormal(cols: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mut basis: Vec<Vec<f64>> = vec![];
    for c in cols {
        let norm: f64 = c.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            continue;
        }
        let r = residual(&residual(c, &basis), &basis);
        let rn: f64 = r.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rn > 1e-10 * norm {
            basis.push(r.iter().map(|x| x / rn).collect());
        }
    }
    basis
}

/// `c` minus its projections on the orthonormal `basis`, one at a time.
fn residual(c: &[f64], basis: &[Vec<f64>]) -> Vec<f64> {
    let mut r = c.to_vec();
    for u in basis {
        let dot: f64 = r.iter().zip(u).map(|(x, y)| x * y).sum();
        r.iter_mut().zip(u).for_each(|(x, y)| *x -= dot * y);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_column_within_the_others_span_is_fitted_and_an_orthogonal_one_is_not() {
        let e1 = vec![1.0, 0.0, 0.0];
        let e2 = vec![0.0, 1.0, 0.0];
        let mix = vec![2.0, -3.0, 0.0];
        let e3 = vec![0.0, 0.0, 5.0];
        assert!(unfitted(&[mix.clone()], &[e1.clone(), e2.clone()]) < 1e-12);
        assert!((unfitted(&[e3.clone()], &[e1.clone(), e2.clone()]) - 1.0).abs() < 1e-12);
        // half in, half out: (1, 0, 1)/√2 against e1 leaves a share 1/2
        let half = vec![1.0, 0.0, 1.0];
        assert!((unfitted(&[half], &[e1.clone()]) - 0.5).abs() < 1e-12);
        // mean over columns; a zero column does not count
        let zero = vec![0.0; 3];
        assert!((unfitted(&[mix, e3, zero], &[e1, e2]) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn dependent_columns_add_nothing_to_the_basis() {
        let b = orthonormal(&[
            vec![1.0, 1.0, 0.0],
            vec![2.0, 2.0, 0.0],
            vec![0.0, 1.0, 0.0],
        ]);
        assert_eq!(b.len(), 2);
    }
}
