//! A quadruped (Solo12) standing on four force plates while its base sways
//! and tilts: the simulated log obeys the physics (feet fixed, states
//! consistent with their derivatives, forces and torques balancing the
//! dynamics), and identification from it reaches the noise floor.

use momentlmi::data::Dataset;
use momentlmi::dynamics::urdf::free_flyer_from_urdf_file;
use momentlmi::dynamics::{Data, Model};
use momentlmi::identify::floating::measured;
use momentlmi::identify::{Identification, Rows, reduce_floating};
use momentlmi::sim::floating::FloatingNoise;
use momentlmi::sim::standing::{StandingConfig, simulate_standing};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use std::path::Path;

#[path = "support/floating.rs"]
mod floating_support;
use floating_support::{generalized, held_out_rms};

fn solo() -> Model {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    free_flyer_from_urdf_file(&root.join("robots/solo12/solo12.urdf"), None).unwrap()
}

const FEET: [&str; 4] = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"];

fn config(ff: &Model) -> StandingConfig {
    // knees bent forward at the front, backward at the back (joints in
    // depth-first order: FL, FR, HL, HR; HAA, HFE, KFE each)
    assert_eq!(ff.joint_names()[..3], ["FL_HAA", "FL_HFE", "FL_KFE"]);
    let leg = |s: f64| [0.0, 0.8 * s, -1.6 * s];
    let posture = [leg(1.0), leg(1.0), leg(-1.0), leg(-1.0)].concat();
    StandingConfig::new(FEET.map(String::from).to_vec(), posture)
}

fn exact(ff: &Model, seconds: f64, rate: f64) -> Dataset {
    let cfg = StandingConfig {
        seconds,
        rate,
        noise: FloatingNoise::none(),
        ..config(ff)
    };
    simulate_standing(ff, &cfg).unwrap()
}

fn pose(log: &Dataset, k: usize) -> (Vector3<f64>, UnitQuaternion<f64>) {
    let q = &log.state(k).0;
    let rot = UnitQuaternion::from_quaternion(Quaternion::new(q[6], q[3], q[4], q[5]));
    (Vector3::new(q[0], q[1], q[2]), rot)
}

#[test]
fn the_feet_stay_put_and_the_states_are_consistent() {
    let ff = solo();
    let (rate, nq, nv) = (1000.0, ff.nq(), ff.nv());
    let log = exact(&ff, 2.0, rate);
    let [lq, lv, la] = generalized(&log);
    let frames: Vec<usize> = FEET.iter().map(|f| ff.frame_index(f).unwrap()).collect();
    let mut data = Data::new(&ff);
    let world = |data: &mut Data, k: usize| -> Vec<Vector3<f64>> {
        let (p, rot) = pose(&log, k);
        let feet = ff.frames_in_base(data, &lq[k * nq + 7..(k + 1) * nq], &frames);
        feet.unwrap().iter().map(|f| p + rot * f).collect()
    };
    let first = world(&mut data, 0);
    let dt = 1.0 / rate;
    let mut worst = [0.0f64; 5];
    for k in 1..log.len() - 1 {
        for (a, b) in world(&mut data, k).iter().zip(&first) {
            worst[0] = worst[0].max((a - b).norm());
        }
        // the base's twist is the pose's rate, in base axes
        let ((p0, r0), (p1, r1), (_, r)) = (pose(&log, k - 1), pose(&log, k + 1), pose(&log, k));
        let v = &lv[k * nv..(k + 1) * nv];
        let lin = r.inverse() * (p1 - p0) / (2.0 * dt);
        let ang = (r0.inverse() * r1).scaled_axis() / (2.0 * dt);
        worst[1] = worst[1].max((lin - Vector3::new(v[0], v[1], v[2])).norm());
        worst[2] = worst[2].max((ang - Vector3::new(v[3], v[4], v[5])).norm());
        // joint velocities and every acceleration are the rates of the rest
        for j in 0..ff.dof() {
            let d = (lq[(k + 1) * nq + 7 + j] - lq[(k - 1) * nq + 7 + j]) / (2.0 * dt);
            worst[3] = worst[3].max((d - v[6 + j]).abs());
        }
        for i in 0..nv {
            let d = (lv[(k + 1) * nv + i] - lv[(k - 1) * nv + i]) / (2.0 * dt);
            worst[4] = worst[4].max((d - la[k * nv + i]).abs());
        }
    }
    println!(
        "feet moved {:.1e} m; twist off {:.1e}, {:.1e}; q̇ {:.1e}; a {:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4]
    );
    assert!(worst[0] < 1e-10, "a foot moved {} m", worst[0]);
    // central differences are exact to O(dt²) ≈ 1e-6 of the motion's scale
    assert!(worst[1] < 1e-6 && worst[2] < 1e-6, "{worst:?}");
    assert!(worst[3] < 1e-5 && worst[4] < 1e-5, "{worst:?}");
    // forces and torques balance the dynamics: [0; τ] + Σ Jᵀ f = M a + h
    let mut biggest = 0.0f64;
    for k in (0..log.len()).step_by(97) {
        let b = measured(&ff, &mut data, &log, k).unwrap();
        let (q, v, a) = (
            &lq[k * nq..(k + 1) * nq],
            &lv[k * nv..(k + 1) * nv],
            &la[k * nv..(k + 1) * nv],
        );
        let g = momentlmi::dynamics::rnea(&ff, &mut data, q, v, a).unwrap();
        biggest = biggest.max((&b - g).amax());
        // the robot stands on its feet: they carry its weight
        let fz: f64 = log.contacts.iter().map(|c| c.wrench[6 * k + 2]).sum();
        assert!(
            (fz - 2.5 * 9.81).abs() < 0.1 * 2.5 * 9.81,
            "the feet carry {fz} N"
        );
    }
    assert!(biggest < 1e-9, "generalized force off by {biggest:e}");
}

#[test]
fn standing_data_identify_at_the_noise_floor() {
    let ff = solo();
    let log = |seconds, seed| {
        simulate_standing(
            &ff,
            &StandingConfig {
                seconds,
                seed,
                ..config(&ff)
            },
        )
        .unwrap()
    };
    let (train, test) = (log(60.0, 1), log(20.0, 2));
    let mut truth = ff.params();
    truth.resize(ff.regressor_columns(), 0.0);
    for rows in [Rows::Base, Rows::Joints] {
        let red = reduce_floating(&ff, &train, rows).unwrap();
        let solved = Identification::for_free_flyer(&ff, rows)
            .solve(&red)
            .unwrap();
        let fit = held_out_rms(&ff, &test, &solved.theta, rows);
        let floor = held_out_rms(&ff, &test, &truth, rows);
        let mut fitted = ff.clone();
        fitted
            .set_params(&solved.theta[..10 * ff.num_bodies()])
            .unwrap();
        let mut data = Data::new(&ff);
        let q = &test.state(0).0;
        let ((m0, c0, _), (m1, c1, _)) = (
            ff.centroidal(&mut data, q).unwrap(),
            fitted.centroidal(&mut data, q).unwrap(),
        );
        println!(
            "{rows:?}: held-out {fit:.5} (floor {floor:.5}); mass {m1:.4}/{m0:.4}; CoM {:.4?}/{:.4?}; {}",
            c1.as_slice(),
            c0.as_slice(),
            solved.identifiability.summary()
        );
        assert!(fit <= 1.10 * floor, "{rows:?}: {fit} vs floor {floor}");
        if rows == Rows::Base {
            // the plates weigh the robot and see its CoM over the feet; a
            // sway barely shows its height (measured: 5 mm off) or inertia
            assert!((m1 - m0).abs() <= 0.01 * m0, "mass {m1} vs {m0}");
            assert!((c1 - c0).xy().norm() <= 1e-3, "CoM {c1:?} vs {c0:?}");
            let friction = &solved.theta[10 * ff.num_bodies()..];
            assert!(
                friction.iter().all(|x| x.abs() < 1e-9),
                "base rows fit friction {friction:?}"
            );
        }
    }
}

#[test]
fn a_stance_that_cannot_stand_is_named() {
    let ff = solo();
    let run = |cfg: StandingConfig| simulate_standing(&ff, &cfg).unwrap_err().to_string();
    let base = config(&ff);
    let feet = |f: &[&str]| StandingConfig {
        feet: f.iter().map(|s| s.to_string()).collect(),
        ..base.clone()
    };
    let e = run(feet(&["FL_FOOT"]));
    assert!(e.contains("1 feet") && e.contains("three or more"), "{e}");
    let e = run(feet(&["FL_FOOT", "FR_FOOT", "FL_FOOT"]));
    assert!(e.contains("'FL_FOOT' is named twice"), "{e}");
    let e = run(feet(&["FL_FOOT", "FR_FOOT", "base_link"]));
    assert!(e.contains("'base_link' is on the base"), "{e}");
    let e = run(feet(&["FL_FOOT", "FR_FOOT", "FR_TOE"]));
    assert!(e.contains("FR_TOE"), "{e}");
    let e = run(StandingConfig {
        posture: vec![0.0; 3],
        ..base.clone()
    });
    assert!(e.contains("3 joint positions, not 12"), "{e}");
    // straight legs: the knees cannot bend the feet toward the base
    let e = run(StandingConfig {
        posture: vec![0.0; 12],
        ..base.clone()
    });
    assert!(e.contains("singular"), "{e}");
    // a slippery floor: the sway needs more sticking than μ = 0.01
    let e = run(StandingConfig {
        friction: 0.01,
        ..base
    });
    assert!(e.contains("friction cone"), "{e}");
}
