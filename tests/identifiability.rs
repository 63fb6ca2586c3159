//! The identifiability report and the parameter ranges: the rank against
//! one computed another way, parameters that provably enter no torque, and
//! ranges on a problem whose null space the test builds.

#[path = "support/rank.rs"]
mod rank;

use faer::Mat;
use momentlmi::data::Dataset;
use momentlmi::dynamics::robots::load_robot;
use momentlmi::dynamics::{Data, FrictionTerm, Model, RobotDescription, regressor_batch, rnea};
use momentlmi::identify::{Identification, Level, PinnedBy, Reduced};
use rand::{RngExt, SeedableRng};
use std::path::Path;

fn panda() -> RobotDescription {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let urdf = dir.join("panda.urdf");
    load_robot(urdf.to_str().unwrap(), Some(&dir.join("panda.toml"))).unwrap()
}

/// `k` random states (positions within the limits, ±1 rad otherwise;
/// velocities and accelerations ±2), flat: the test's own, apart from
/// `dynamics::random_states` that the report uses, so that a fault there
/// cannot agree with itself.
fn random_states(model: &Model, k: usize, seed: u64) -> [Vec<f64>; 3] {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let mut s = [vec![], vec![], vec![]];
    for _ in 0..k {
        for j in &model.joints {
            let (lo, hi) = j.limits;
            let (lo, hi) = if lo.is_finite() && hi.is_finite() {
                (lo, hi)
            } else {
                (-1.0, 1.0)
            };
            s[0].push(rng.random_range(lo..hi));
            s[1].push(rng.random_range(-2.0..2.0));
            s[2].push(rng.random_range(-2.0..2.0));
        }
    }
    s
}

/// Random states with the model's exact torques, as a data set.
fn random_data(model: &Model, k: usize, seed: u64) -> Dataset {
    let [q, qd, qdd] = random_states(model, k, seed);
    let n = model.dof();
    let names = model.joint_names();
    let mut d = Dataset::empty(&names.iter().map(|s| s.as_ref()).collect::<Vec<&str>>());
    let mut data = Data::new(model);
    for i in 0..k {
        let at = i * n..(i + 1) * n;
        let tau = rnea(
            model,
            &mut data,
            &q[at.clone()],
            &qd[at.clone()],
            &qdd[at.clone()],
        )
        .unwrap();
        d.t.push(i as f64 * 1e-3);
        d.q.push(&q[at.clone()]);
        d.qd.push(&qd[at.clone()]);
        d.qdd.push(&qdd[at.clone()]);
        d.tau.push(tau.as_slice());
    }
    d
}

/// The numerical rank of the stacked regressor on random states, directly
/// (columns scaled to unit norm; the gap below it is many decades).
fn rank_on_random_states(model: &Model, seed: u64) -> usize {
    let [q, qd, qdd] = random_states(model, 400, seed);
    let y = regressor_batch(model, &q, &qd, &qdd).unwrap();
    // a column at rounding level (the Panda's link2.hz: 6e-15) is zero
    let s = rank::scaled_singular_values(&y, model.regressor_columns());
    let rank = s.iter().filter(|&&v| v > 1e-6 * s[0]).count();
    // a clear gap: the next value is round-off
    assert!(
        s.get(rank).is_none_or(|&v| v < 1e-12 * s[0]),
        "no gap: {s:?}"
    );
    rank
}

fn reported(
    robot: &RobotDescription,
    model: &Model,
    seed: u64,
) -> momentlmi::identify::Identifiability {
    let mut r = robot.clone();
    r.model = model.clone();
    let d = random_data(model, 300, seed);
    Identification::for_robot(&r, Level::Consistent, 1e-6)
        .unwrap()
        .fit(&d)
        .unwrap()
        .identifiability
}

#[test]
fn the_panda_and_the_legs_base_parameter_counts_match_a_rank_on_random_states() {
    let arm = panda();
    let links_only = arm.model.clone().with_friction_terms(&[]);
    let direct = rank_on_random_states(&links_only, 7);
    let id = reported(&arm, &links_only, 8);
    assert_eq!(id.rank, direct);
    assert_eq!(id.base_parameters.len(), direct);
    assert_eq!(id.structural_rank, Some(direct));
    // the Panda's 7 links: 70 columns, 43 base parameters (Pinocchio 4.1.0's
    // joint torque regressor on 400 random states of the same URDF, fingers
    // locked by buildReducedModel, columns at rounding level dropped, counts
    // 43 too: checked 2026-12-05; as Gaz et al., RA-L 2019)
    assert_eq!((id.columns, id.rank), (70, 43));
    assert!(
        id.unidentifiable.iter().any(|n| n == "panda_link2.hz"),
        "{:?}",
        id.unidentifiable
    );

    let leg = load_robot("cheetah3-leg", None).unwrap();
    let with_friction = leg.model.clone();
    let direct = rank_on_random_states(&with_friction, 9);
    let id = reported(&leg, &with_friction, 10);
    assert_eq!((id.columns, id.rank), (66, direct));
    assert!(id.condition_number.is_finite() && id.condition_number >= 1.0);
}

/// The base parameters' names (each a combination) in the report's order.
fn combinations(id: &momentlmi::identify::Identifiability) -> Vec<String> {
    (id.base_parameters.iter())
        .map(|b| b.combination.clone())
        .collect()
}

/// Issue 58: the command line's streamed reduction and the Python binding's
/// in-memory one named 5 of the leg's 38 base parameters otherwise, in
/// another order (a pivoted QR broke ties by rounding). The sums of one data
/// set added in other orders (chunks of 1, 7, 64, 4096 samples, and a
/// stream) now give the same base parameters and unseen directions, in θ's
/// order.
#[test]
fn every_reduction_of_the_same_data_names_the_same_base_parameters() {
    use momentlmi::identify::identifiability::Identifiability;
    use momentlmi::identify::{StreamReducer, parameter_names, reduce_samples};
    for robot in [load_robot("cheetah3-leg", None).unwrap(), panda()] {
        let model = &robot.model;
        let d = random_data(model, 600, 12);
        let names = parameter_names(model);
        let of = |red: Reduced| Identifiability::of(&red.r_d().unwrap().0, &names).unwrap();
        let mut reports: Vec<_> = [1, 7, 64, 4096]
            .map(|chunk| of(reduce_samples(model, &d.q, &d.qd, &d.qdd, &d.tau, chunk).unwrap()))
            .into();
        let mut stream = StreamReducer::new(model, 100);
        for i in 0..d.len() {
            stream
                .push(&d.q[i], &d.qd[i], &d.qdd[i], &d.tau[i])
                .unwrap();
        }
        reports.push(of(stream.finish().unwrap()));
        let first = &reports[0];
        assert!(first.rank > 0 && first.rank < first.columns);
        for (k, other) in reports.iter().enumerate().skip(1) {
            assert_eq!(combinations(other), combinations(first), "reduction {k}");
            assert_eq!(other.directions, first.directions, "reduction {k}");
        }
        assert!(first.base_columns.windows(2).all(|w| w[0] < w[1]));
    }
}

#[test]
fn parameters_that_enter_no_torque_are_named() {
    let leg = load_robot("cheetah3-leg", None).unwrap();
    let id = reported(&leg, &leg.model, 11);
    // the first link turns about its own fixed axis (x): only its Ixx and
    // its first moments across the axis enter a torque
    for p in ["m", "hx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"] {
        let name = format!("abad.{p}");
        assert!(
            id.unidentifiable.contains(&name),
            "{name}: {:?}",
            id.unidentifiable
        );
    }
    for p in ["hy", "hz", "Ixx"] {
        let name = format!("abad.{p}");
        assert!(!id.unidentifiable.contains(&name), "{name}");
    }
    // a friction term of a moving joint enters
    assert!(!id.unidentifiable.iter().any(|n| n.starts_with("viscous.")));
    assert!(id.summary().contains("enter no torque"));
}

/// The leg's model with only viscous friction, its regressor on random
/// states with two columns made equal and two zeroed (a null space the
/// test knows), torques from the truth plus white noise of σ = 1e-3 N·m.
/// Returns the reduced data, the truth and the changed columns.
fn known_null_space() -> (RobotDescription, Reduced, Vec<f64>, [usize; 4]) {
    let mut leg = load_robot("cheetah3-leg", None).unwrap();
    leg.model = leg
        .model
        .clone()
        .with_friction_terms(&[FrictionTerm::Viscous]);
    let model = &leg.model;
    let p = model.regressor_columns();
    let [q, qd, qdd] = random_states(model, 300, 12);
    let mut y = regressor_batch(model, &q, &qd, &qdd).unwrap();
    let rows = y.len() / p;
    // column 10 + 1 (hip.hx) copies column 10 + 2 (hip.hy); the knee's Ixy
    // and Ixz (20 + 5, 20 + 6) enter nothing
    let (a, b, z1, z2) = (11, 12, 25, 26);
    for i in 0..rows {
        y[i * p + a] = y[i * p + b];
        y[i * p + z1] = 0.0;
        y[i * p + z2] = 0.0;
    }
    let mut truth = model.params();
    truth.extend(std::iter::repeat_n(0.05, model.dof()));
    let mut g = Mat::<f64>::zeros(p + 1, p + 1);
    let mut rng = rand::rngs::StdRng::seed_from_u64(13);
    let noise = rand_distr::Normal::new(0.0, 1e-3).unwrap();
    for i in 0..rows {
        let row = &y[i * p..(i + 1) * p];
        let tau: f64 = row.iter().zip(&truth).map(|(x, t)| x * t).sum::<f64>() + rng.sample(noise);
        let ext = |j: usize| if j < p { row[j] } else { tau };
        for r in 0..=p {
            for c in 0..=p {
                g[(r, c)] += ext(r) * ext(c);
            }
        }
    }
    let red = Reduced::from_gram(g, rows / model.dof()).unwrap();
    (leg, red, truth, [a, b, z1, z2])
}

/// Parameter k's scale in the truth: a body's mass, its largest first
/// moment, or its largest diagonal inertia (by k's kind); a friction
/// coefficient itself.
fn kind_scale(truth: &[f64], k: usize) -> f64 {
    let (b, i) = (k / 10, k % 10);
    let of = |idx: &[usize]| {
        idx.iter()
            .map(|&j| truth[10 * b + j].abs())
            .fold(0.0, f64::max)
    };
    if 10 * (b + 1) > 60 {
        return truth[k].abs();
    }
    match i {
        0 => truth[k].abs(),
        1..=3 => of(&[1, 2, 3]),
        _ => of(&[4, 7, 9]),
    }
}

#[test]
fn every_range_holds_the_truth_and_data_determined_ones_are_tight() {
    let (leg, red, truth, [a, b, z1, z2]) = known_null_space();
    let id = Identification::for_robot(&leg, Level::Consistent, 1e-8).unwrap();
    let solved = id.solve(&red).unwrap();
    let ident = &solved.identifiability;
    for k in [a, b, z1, z2] {
        assert!(!ident.determined_alone(k), "column {k}");
    }
    for name in ["knee.Ixy", "knee.Ixz"] {
        assert!(ident.unidentifiable.iter().any(|n| n == name), "{name}");
    }
    // the 99.9 % confidence region: the truth is inside unless the noise
    // is one draw in a thousand
    let rows = red.samples * leg.model.dof();
    let delta = momentlmi::identify::confidence_delta(ident.rank, rows, 0.999).unwrap();
    let bounds = id
        .parameter_bounds(&red, &solved.theta, ident, delta)
        .unwrap();
    let mut tight = 0;
    for (k, r) in bounds.ranges.iter().enumerate() {
        let scale = kind_scale(&truth, k);
        let tol = 1e-6 * scale;
        let (lo, hi) = (
            r.min.unwrap_or(f64::NEG_INFINITY),
            r.max.unwrap_or(f64::INFINITY),
        );
        assert!(
            r.note
                .as_ref()
                .is_none_or(|n| n.starts_with("unbounded") || n.starts_with("solved at")),
            "{}: {:?}",
            r.name,
            r.note
        );
        assert!(
            lo - tol <= truth[k] && truth[k] <= hi + tol,
            "{}: truth {} not in [{lo}, {hi}]",
            r.name,
            truth[k]
        );
        if ident.determined_alone(k) {
            // σ = 1e-3 N·m leaves ranges of ~2 % of the parameter
            assert!(
                hi - lo <= 5e-2 * scale,
                "{}: [{lo}, {hi}] not tight",
                r.name
            );
            assert!(lo <= r.estimate && r.estimate <= hi, "{}", r.name);
            assert_eq!(r.pinned_by, PinnedBy::Data, "{}", r.name);
            tight += 1;
        }
    }
    assert!(tight >= 10, "only {tight} parameters determined alone");
    // the copied pair: only their sum is known, each alone is not
    for k in [a, b] {
        let r = &bounds.ranges[k];
        let width = r.max.unwrap_or(f64::INFINITY) - r.min.unwrap_or(f64::NEG_INFINITY);
        assert!(width > 1e-3, "{}: width {width}", r.name);
    }
}
