//! The diagnosis' noise floor (issue 35): from two runs of one trajectory
//! (`diagnose::floor::repeat_floor`), and the floor a diagnosis is given.

use momentlmi::data::Dataset;
use momentlmi::diagnose::floor::repeat_floor;
use momentlmi::diagnose::{DiagnoseError, DiagnoseOptions, FloorSource, NoiseFloor, diagnose};
use momentlmi::dynamics::{Friction, cheetah3};
use momentlmi::effects::simulate;
use momentlmi::sim::{Effects, SimConfig};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

/// `seconds` of the leg's noise-free data of trajectory `seed`.
fn clean(seconds: f64, seed: u64) -> Dataset {
    let leg = cheetah3::description();
    let fx = Effects::parse("rotor_inertia,coulomb,viscous", &[]).unwrap();
    let mut cfg = SimConfig::for_robot(&leg, seconds, fx, seed);
    (cfg.noise_sigma, cfg.encoder_counts, cfg.processed) = (0.0, 0.0, false);
    simulate(&leg, &cfg, |_, _| {}).unwrap()
}

/// `d` with Gaussian noise of `sigma` per joint (N·m) on its torques.
fn noisy(mut d: Dataset, sigma: [f64; 3], seed: u64) -> Dataset {
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let unit = Normal::new(0.0, 1.0).unwrap();
    for row in d.tau.as_flat_mut().chunks_mut(3) {
        for (x, s) in row.iter_mut().zip(sigma) {
            *x += s * unit.sample(&mut rng);
        }
    }
    d
}

/// Two runs of one trajectory, the second starting 37 samples later, with
/// independent noise of known σ: aligned at that lag, the floor is σ
/// within 5 % per joint; a run of another trajectory is refused by name.
#[test]
fn two_runs_of_one_trajectory_give_their_noise() {
    let d = clean(6.0, 1);
    let sigma = [0.1, 0.3, 0.05];
    let a = noisy(d.slice(0..5000), sigma, 11);
    let b = noisy(d.slice(37..6000), sigma, 12);
    let f = repeat_floor(&a, &b, ["a", "b"]).unwrap();
    let FloorSource::Repeats { lag, samples, .. } = &f.source else {
        panic!("{:?}", f.source)
    };
    assert_eq!((*lag, *samples), (-37, 5000 - 37));
    for (got, want) in f.per_joint.iter().zip(sigma) {
        assert!(
            (got / want - 1.0).abs() < 0.05,
            "{:?} vs {sigma:?}",
            f.per_joint
        );
    }
    // another trajectory: the same moves 0.3 rad further on every joint
    let mut other = b.clone();
    other.q.as_flat_mut().iter_mut().for_each(|q| *q += 0.3);
    let e = repeat_floor(&a, &other, ["a", "other"]).unwrap_err();
    assert!(matches!(e, DiagnoseError::NotRepeats { .. }), "{e}");
    assert!(e.to_string().contains("positions differ"), "{e}");
}

/// A diagnosis given a floor reports it, says where it came from, and
/// keeps every joint's gap closed within [0, 1]; a floor of the wrong
/// length is an error. Without one, the floor comes from first differences
/// (here unfiltered white noise: no joint low-passed, and each at least
/// 0.9 σ — the torque's own change between samples adds to it).
#[test]
fn a_diagnosis_measures_the_gap_against_the_floor_it_is_given() {
    let d = noisy(clean(10.0, 3), [0.2; 3], 21);
    let model = cheetah3::model();
    let none = Friction::zeros(3);
    let dg = diagnose(&model, &none, &d, &DiagnoseOptions::default()).unwrap();
    let FloorSource::FirstDifferences { low_passed } = &dg.noise_floor_source else {
        panic!("{:?}", dg.noise_floor_source)
    };
    assert!(low_passed.is_empty(), "{low_passed:?}");
    assert!(
        dg.noise_floor.iter().all(|f| *f > 0.18),
        "{:?}",
        dg.noise_floor
    );
    let given = NoiseFloor {
        per_joint: vec![0.5, 0.25, 0.125],
        source: FloorSource::Repeats {
            runs: vec!["x".into(), "y".into()],
            lag: 0,
            position_rms: 0.0,
            samples: 1,
        },
    };
    let opts = DiagnoseOptions::default().with_noise_floor(given.clone());
    let dg = diagnose(&model, &none, &d, &opts).unwrap();
    assert_eq!(dg.noise_floor, given.per_joint);
    assert_eq!(dg.noise_floor_source, given.source);
    assert!(
        dg.gap_closed.iter().all(|g| (0.0..=1.0).contains(g)),
        "{:?}",
        dg.gap_closed
    );
    let short = NoiseFloor {
        per_joint: vec![0.1; 2],
        ..given
    };
    let e = diagnose(
        &model,
        &none,
        &d,
        &DiagnoseOptions::default().with_noise_floor(short),
    );
    assert!(matches!(e, Err(DiagnoseError::NotRepeats { .. })));
}
