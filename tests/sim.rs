//! The simulator: inverse kinematics, the shell excitation, each effect
//! against its formula, and the processed data.

use momentlmi::data::Samples;
use momentlmi::dynamics::{Data, cheetah3, rnea};
use momentlmi::effects::Library;
use momentlmi::effects::simulate;
use momentlmi::sim::Effects;
use momentlmi::sim::SimConfig;
use momentlmi::sim::trajectory::{Shell, Trajectory, cheetah_ik};

#[test]
fn inverse_kinematics_round_trips() {
    for k in 0..50 {
        let f = k as f64;
        // the branch the IK returns: foot below the hip, knee bent positive
        let q = [
            0.5 * (0.7 * f).sin(),
            -0.15 + 0.65 * (1.3 * f).cos(),
            0.3 + 1.2 * (0.5 + 0.5 * (0.9 * f).sin()),
        ];
        let p = cheetah3::foot_position(q);
        let back = cheetah_ik(&p).unwrap();
        for i in 0..3 {
            assert!((back[i] - q[i]).abs() < 1e-9, "{q:?} → {back:?}");
        }
    }
    assert!(
        cheetah_ik(&nalgebra::Vector3::new(0.0, 0.0, -0.9)).is_none(),
        "beyond reach"
    );
}

#[test]
fn shell_motion_is_reproduced_and_stays_in_limits() {
    let shell = Shell::default();
    let tr = Trajectory::Shell(shell);
    let model = cheetah3::model();
    let mut k = 0.0;
    while k < 20.0 {
        let (q, qd, _) = tr.state(k).unwrap();
        let foot = cheetah3::foot_position([q[0], q[1], q[2]]);
        assert!((foot - shell.foot(k)).norm() < 1e-9, "t = {k}");
        for (i, j) in model.joints.iter().enumerate() {
            assert!(
                q[i] > j.limits.0 && q[i] < j.limits.1,
                "t = {k}: joint {i} at {}",
                q[i]
            );
        }
        assert!(qd.iter().all(|v| v.is_finite()));
        k += 0.01;
    }
    // the angles follow the paper's rates: φ̇ = 12 sin(1.63 t)
    let h = 1e-6;
    for t in [0.3, 2.0, 7.5] {
        let dphi = (shell.angles(t + h).0 - shell.angles(t - h).0) / (2.0 * h);
        assert!((dphi - 12.0 * (1.63 * t).sin()).abs() < 1e-5);
        let dth = (shell.angles(t + h).1 - shell.angles(t - h).1) / (2.0 * h);
        assert!((dth - 3.4 * (0.265 * t).sin()).abs() < 1e-5);
    }
}

fn states() -> (Samples, Samples, Samples) {
    let tr = Trajectory::Shell(Shell::default());
    let mut out = (Samples::new(3), Samples::new(3), Samples::new(3));
    for k in 0..200 {
        let (q, qd, qdd) = tr.state(k as f64 * 0.05).unwrap();
        out.0.push(&q);
        out.1.push(&qd);
        out.2.push(&qdd);
    }
    out
}

#[test]
fn each_effect_alone_adds_its_formula_and_off_is_absent() {
    let model = cheetah3::model();
    let leg = cheetah3::description();
    let (q, qd, qdd) = states();
    let none = Library::builtin()
        .true_robot(&leg, &Effects::default())
        .unwrap()
        .torques(&q, &qd, &qdd)
        .unwrap();
    // no effects = links only rigid-body dynamics, exactly
    let links = momentlmi::dynamics::Model::new(
        "cheetah3-leg",
        model.joints.clone(),
        vec![],
        model.gravity,
    )
    .unwrap();
    let mut d = Data::new(&links);
    for k in 0..q.len() {
        let t = rnea(&links, &mut d, &q[k], &qd[k], &qdd[k]).unwrap();
        assert!((0..3).all(|i| t[i] == none[k][i]));
    }
    let sgn = |v: f64| {
        if v > 0.0 {
            1.0
        } else if v < 0.0 {
            -1.0
        } else {
            0.0
        }
    };
    for e in Library::builtin().names() {
        if matches!(
            e,
            "time_delay"
                | "payload"
                | "rotor_inertia"
                | "link_inertia"
                | "elasticity"
                | "backlash"
                | "joint_offset"
        ) {
            continue; // checked below through the dynamics
        }
        // a drift scales the friction there is
        let list = if e == "friction_drift" {
            "coulomb,viscous,friction_drift"
        } else {
            e
        };
        let fx = Effects::parse(list, &[]).unwrap();
        let times: Vec<f64> = (0..q.len()).map(|k| 0.05 * k as f64).collect();
        let got = Library::builtin()
            .true_robot(&leg, &fx)
            .unwrap()
            .torques_at(&times, &q, &qd, &qdd)
            .unwrap();
        for k in 0..q.len() {
            for i in 0..3 {
                let v = qd[k][i];
                let base = none[k][i];
                let friction = cheetah3::COULOMB[i] * sgn(v) + 0.1 * v;
                let want = match e {
                    "coulomb" => base + cheetah3::COULOMB[i] * sgn(v),
                    "viscous" => base + 0.1 * v,
                    "stribeck" => base + 1.0 * (-(v / 0.2).powi(2)).exp() * sgn(v),
                    "asymmetric_friction" => base + 0.3 * cheetah3::COULOMB[i] * sgn(v).abs(),
                    "offset" => base + 0.5,
                    // no rotors here: the load is the links' torque, `base`
                    "load_friction" => base + 0.05 * base.abs() * sgn(v),
                    "cogging" => base + 0.2 * (6.0 * cheetah3::GEAR_RATIO * q[k][i]).sin(),
                    "torque_gain" => base * 1.1,
                    "friction_drift" => base + friction * (1.0 - 0.4 / 60.0 * times[k]),
                    // every joint of the leg has a rotor: its ripple is cogging
                    "ripple" => base,
                    other => panic!("untested effect {other}"),
                };
                assert!(
                    (got[k][i] - want).abs() < 1e-12,
                    "{e}: joint {i} sample {k}"
                );
            }
        }
    }
    // rotor inertia: the full model with rotors
    let with = Library::builtin()
        .true_robot(&leg, &Effects::parse("rotor_inertia", &[]).unwrap())
        .unwrap()
        .torques(&q, &qd, &qdd)
        .unwrap();
    let mut d = Data::new(&model);
    for k in 0..q.len() {
        let t = rnea(&model, &mut d, &q[k], &qd[k], &qdd[k]).unwrap();
        assert!((0..3).all(|i| (t[i] - with[k][i]).abs() < 1e-12));
    }
    // payload: 1 kg at the foot = knee link with a point mass added
    let pay = Library::builtin()
        .true_robot(
            &leg,
            &Effects::parse("payload", &["payload_mass=1.0".into()]).unwrap(),
        )
        .unwrap()
        .torques(&q, &qd, &qdd)
        .unwrap();
    let mut joints = links.joints.clone();
    let pm = momentlmi::moments::InertialParams::from_mass_com_inertia(
        1.0,
        nalgebra::Vector3::new(0.0, 0.0, -0.345),
        nalgebra::Matrix3::zeros(),
    );
    joints[2].inertia = joints[2].inertia.plus(&pm);
    let heavy = momentlmi::dynamics::Model::new("h", joints, vec![], model.gravity).unwrap();
    let mut d = Data::new(&heavy);
    for k in 0..q.len() {
        let t = rnea(&heavy, &mut d, &q[k], &qd[k], &qdd[k]).unwrap();
        assert!((0..3).all(|i| (t[i] - pay[k][i]).abs() < 1e-12));
    }
    // joint offset: the encoders read q − δ, so the torques are the rigid
    // ones at q + δ (δ = 0.02 here)
    let off = Library::builtin()
        .true_robot(
            &leg,
            &Effects::parse("joint_offset", &["joint_offset=0.02".into()]).unwrap(),
        )
        .unwrap()
        .torques(&q, &qd, &qdd)
        .unwrap();
    let mut d = Data::new(&links);
    for k in 0..q.len() {
        let qs: Vec<f64> = q[k].iter().map(|x| x + 0.02).collect();
        let t = rnea(&links, &mut d, &qs, &qd[k], &qdd[k]).unwrap();
        assert!((0..3).all(|i| (t[i] - off[k][i]).abs() < 1e-12));
        assert!((0..3).any(|i| (t[i] - none[k][i]).abs() > 1e-6));
    }
    // link inertia: every link's parameters scaled by 1 + s (s = 0.2 here)
    let heavier = Library::builtin()
        .true_robot(
            &leg,
            &Effects::parse("link_inertia", &["link_inertia_error=0.2".into()]).unwrap(),
        )
        .unwrap()
        .torques(&q, &qd, &qdd)
        .unwrap();
    for k in 0..q.len() {
        assert!((0..3).all(|i| (heavier[k][i] - 1.2 * none[k][i]).abs() < 1e-9));
    }
    let lib = Library::builtin();
    let checked = |list: &str, o: &[&str]| {
        let o: Vec<String> = o.iter().map(|s| s.to_string()).collect();
        lib.check(&Effects::parse(list, &o).unwrap())
    };
    assert!(checked("joint_offset", &["joint_offset=0.6"]).is_err());
    assert!(checked("coulomb,warp_drive", &[]).is_err());

    assert!(Effects::parse("offset", &["offset=abc".into()]).is_err());
}

#[test]
fn time_delay_uses_the_earlier_state() {
    let leg = cheetah3::description();
    let fx = Effects::parse("time_delay", &["delay=0.01".into()]).unwrap();
    let mut cfg = SimConfig::for_robot(&leg, 0.5, fx, 1);
    cfg.noise_sigma = 0.0;
    cfg.encoder_counts = 0.0;
    cfg.processed = false;
    let d = simulate(&leg, &cfg, |_, _| {}).unwrap();
    let tr = Trajectory::Shell(Shell::default());
    let robot = Library::builtin()
        .true_robot(&leg, &Effects::default())
        .unwrap();
    for k in [100usize, 250, 400] {
        let (q, qd, qdd) = tr.state(d.t[k] - 0.01).unwrap();
        let one = |v: Vec<f64>| Samples::from_rows(&[v]);
        let want = robot.torques(&one(q), &one(qd), &one(qdd)).unwrap();
        assert!((0..3).all(|i| (want[0][i] - d.tau[k][i]).abs() < 1e-12));
    }
}

#[test]
fn processed_data_track_the_true_states() {
    let leg = cheetah3::description();
    let fx = Effects::parse("rotor_inertia,coulomb,viscous", &[]).unwrap();
    let cfg = SimConfig::for_robot(&leg, 3.0, fx, 7);
    let d = simulate(&leg, &cfg, |_, _| {}).unwrap();
    let tr = Trajectory::Shell(Shell::default());
    let mut worst = [0.0f64; 3];
    for k in (200..2800).step_by(50) {
        let (q, qd, _) = tr.state(d.t[k]).unwrap();
        worst[0] = worst[0].max((0..3).map(|i| (q[i] - d.q[k][i]).abs()).fold(0.0, f64::max));
        worst[1] = worst[1].max(
            (0..3)
                .map(|i| (qd[i] - d.qd[k][i]).abs())
                .fold(0.0, f64::max),
        );
    }
    assert!(worst[0] < 2e-3, "q error {}", worst[0]);
    assert!(worst[1] < 0.2, "q̇ error {}", worst[1]);
    // torque noise has the requested σ
    let clean = {
        let mut c = cfg.clone();
        c.noise_sigma = 0.0;
        simulate(&leg, &c, |_, _| {}).unwrap()
    };
    let res: Vec<f64> = d
        .tau
        .iter()
        .zip(&clean.tau)
        .flat_map(|(a, b)| (0..3).map(move |i| a[i] - b[i]))
        .collect();
    let sd = (res.iter().map(|x| x * x).sum::<f64>() / res.len() as f64).sqrt();
    assert!((sd - 0.3).abs() < 0.02, "σ = {sd}");
}

#[test]
fn multisine_excitation_stays_in_limits_for_any_robot() {
    // the Panda-like limits of a URDF model: a 3-link chain written here
    let urdf = "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\
        <link name=\"c\"><inertial><mass value=\"1\"/><origin xyz=\"0.2 0 0\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\
        <joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/><limit lower=\"-0.5\" upper=\"2.0\" effort=\"1\" velocity=\"1\"/></joint>\
        <joint name=\"j2\" type=\"continuous\"><parent link=\"b\"/><child link=\"c\"/><origin xyz=\"0.3 0 0\"/><axis xyz=\"0 1 0\"/></joint></robot>";
    let model = momentlmi::dynamics::urdf::model_from_urdf_str(urdf, "r.urdf", None).unwrap();
    let robot = momentlmi::dynamics::RobotDescription::new(
        "r.urdf",
        model.clone(),
        &momentlmi::dynamics::sidecar::Sidecar::default(),
        None,
    )
    .unwrap();
    for seed in 0..5 {
        let tr = Trajectory::fourier_for(&model, seed);
        for k in 0..2000 {
            let (q, _, _) = tr.state(k as f64 * 0.01).unwrap();
            assert!(q[0] >= -0.5 && q[0] <= 2.0, "{}", q[0]);
            assert!(q[1].abs() <= 1.0 + 1e-12);
        }
    }
    let mut cfg = SimConfig::for_robot(
        &robot,
        2.0,
        Effects::parse("coulomb,viscous", &[]).unwrap(),
        3,
    );
    cfg.noise_sigma = 0.1;
    let d = simulate(&robot, &cfg, |_, _| {}).unwrap();
    assert_eq!(d.len(), 2000);
    assert_eq!(d.joints, vec!["j1", "j2"]);
}

/// Elasticity and backlash: the torque carries the spring torque computed
/// from the simulated link-side state instead of the rigid links' torque,
/// the link side obeys its own dynamics, and the dead band transmits nothing.
#[test]
fn elasticity_and_backlash_follow_their_formulas() {
    use momentlmi::dynamics::{Data, Model, rnea};
    use momentlmi::sim::compliance::{Compliance, simulate_link_side};
    let model = cheetah3::model();
    let leg = cheetah3::description();
    for (effects, b) in [("elasticity", 0.0), ("backlash", 0.005)] {
        let fx = Effects::parse(effects, &[]).unwrap();
        let mut cfg = SimConfig::for_robot(&leg, 1.0, fx, 1);
        cfg.noise_sigma = 0.0;
        cfg.encoder_counts = 0.0;
        cfg.processed = false;
        let d = simulate(&leg, &cfg, |_, _| {}).unwrap();
        let mut rigid_cfg = cfg.clone();
        rigid_cfg.effects = Effects::default();
        let r = simulate(&leg, &rigid_cfg, |_, _| {}).unwrap();
        let c = Compliance {
            stiffness: 2000.0,
            damping: 5.0,
            backlash: b,
        };
        let links = Model::new("l", model.joints.clone(), vec![], model.gravity).unwrap();
        let ls = simulate_link_side(&links, &cfg.trajectory, &d.t, &c).unwrap();
        let mut data = Data::new(&links);
        let mut dead = 0;
        for k in (5..d.len() - 5).step_by(7) {
            for i in 0..3 {
                // formula: τ = τ_rigid(θ) − τ_links(θ) + τ_s, here with no rotors and no friction: τ = τ_s
                let x = d.q[k][i] - ls[k].0[i];
                let xd = d.qd[k][i] - ls[k].1[i];
                let ts = c.torque(x, xd);
                assert!((d.tau[k][i] - ts).abs() < 1e-9, "{effects}: joint {i}");
                assert!(
                    (ls[k].2[i] - ts).abs() < 1e-9 * (1.0 + ts.abs()),
                    "{} vs {ts}",
                    ls[k].2[i]
                );
                if x.abs() <= b {
                    assert_eq!(ts, 0.0);
                    dead += 1;
                }
                // the deflection is small but real
                assert!(x.abs() < 0.05, "{effects}: deflection {x}");
            }
            // link side: M(q_L) q̈_L + h = τ_s, q̈_L by central differences
            let dt = d.t[k + 1] - d.t[k - 1];
            let qdd: Vec<f64> = (0..3)
                .map(|i| (ls[k + 1].1[i] - ls[k - 1].1[i]) / dt)
                .collect();
            let tau = rnea(&links, &mut data, &ls[k].0, &ls[k].1, &qdd).unwrap();
            for i in 0..3 {
                // (with backlash, skip samples near the dead band's edges, where
                // the transmitted torque jumps and a central difference of q̇_L
                // is no acceleration)
                let near_edge = b > 0.0
                    && (0..2).any(|s| {
                        ((d.q[k + 2 * s - 1][i] - ls[k + 2 * s - 1].0[i]).abs() - b).abs() < 2.0 * b
                    });
                if near_edge {
                    continue;
                }
                assert!(
                    (tau[i] - ls[k].2[i]).abs() < 0.05 * (1.0 + ls[k].2[i].abs()),
                    "{effects}: link dynamics joint {i}: {} vs {}",
                    tau[i],
                    ls[k].2[i]
                );
            }
        }
        if b > 0.0 {
            assert!(dead > 0, "the dead band is crossed during the motion");
        }
        // and it differs from the rigid robot
        let diff = d
            .tau
            .iter()
            .zip(&r.tau)
            .map(|(a, b)| (a[1] - b[1]).abs())
            .fold(0.0, f64::max);
        assert!(diff > 0.01, "{effects}: {diff}");
    }
}

/// The link side of a model with rotors: rotor housings welded to their
/// mounts, spin removed. With rotors symmetric about their spin axes, the
/// joint-space mass matrices differ on the diagonal exactly by the reflected
/// spin inertia `N² aᵀ Ī_rotor a`, at any configuration.
#[test]
fn link_side_differs_by_the_reflected_spin_inertia() {
    use momentlmi::dynamics::{Data, crba};
    use momentlmi::moments::InertialParams;
    let mut model = cheetah3::model();
    for r in model.rotors.iter_mut() {
        let a = r.axis;
        let h = a * a.dot(&r.inertia.h());
        let ia = a.dot(&(r.inertia.inertia() * a));
        let i = a * a.transpose() * ia
            + (nalgebra::Matrix3::identity() - a * a.transpose()) * (0.6 * ia + 1e-4);
        r.inertia = InertialParams::from_mass_h_inertia(r.inertia.mass(), h, i);
    }
    let links = model.link_side();
    assert!(links.rotors.is_empty());
    // mass is conserved except for rotors on the fixed base
    let total = |m: &momentlmi::dynamics::Model| -> f64 {
        m.joints.iter().map(|j| j.inertia.mass()).sum::<f64>()
            + m.rotors.iter().map(|r| r.inertia.mass()).sum::<f64>()
    };
    let on_base: f64 = model
        .rotors
        .iter()
        .filter(|r| model.joints[r.joint].parent.is_none())
        .map(|r| r.inertia.mass())
        .sum();
    assert!((total(&model) - on_base - total(&links)).abs() < 1e-12);
    let (mut df, mut dl) = (Data::new(&model), Data::new(&links));
    for q in [[0.0, -0.8, 1.6], [0.3, -1.1, 2.0], [-0.2, -0.5, 1.2]] {
        crba(&model, &mut df, &q).unwrap();
        crba(&links, &mut dl, &q).unwrap();
        for i in 0..3 {
            let r = model.rotor_of(i).unwrap();
            let spin = r.gear_ratio.powi(2) * r.axis.dot(&(r.inertia.inertia() * r.axis));
            let diff = df.mass_matrix[(i, i)] - dl.mass_matrix[(i, i)];
            assert!(
                (diff - spin).abs() < 1e-10 * (1.0 + spin),
                "joint {i}: {diff} vs {spin}"
            );
        }
    }
}

/// A record written before the link-side encoder settings existed reads
/// back with the old rule (counts per joint turn) and no dropped edges; a
/// new record says which encoder each joint has.
#[test]
fn older_records_keep_their_encoders() {
    let leg = cheetah3::description();
    let cfg = SimConfig::for_robot(&leg, 1.0, Effects::default(), 1);
    let links = leg.model.link_side();
    let no_rotors =
        momentlmi::dynamics::Model::new("links", links.joints.clone(), vec![], links.gravity)
            .unwrap();
    let (res, side) = cfg.encoder(&no_rotors, 0);
    assert_eq!(side, "link side");
    assert!((res - std::f64::consts::TAU / 2f64.powi(19)).abs() < 1e-18);
    let (res, side) = cfg.encoder(&leg.model, 0);
    assert_eq!(side, "motor side");
    assert!((res - std::f64::consts::TAU / (16384.0 * cheetah3::GEAR_RATIO)).abs() < 1e-15);
    let mut v = serde_json::to_value(&cfg).unwrap();
    for k in ["link_encoder_bits", "linear_resolution_m", "edge_seconds"] {
        v.as_object_mut().unwrap().remove(k);
    }
    let old: SimConfig = serde_json::from_value(v).unwrap();
    assert_eq!((old.link_encoder_bits, old.edge_seconds), (None, 0.0));
    let (res, _) = old.encoder(&no_rotors, 0);
    assert!((res - std::f64::consts::TAU / 16384.0).abs() < 1e-15);
}

/// On an arm without rotors, `ripple` adds `A sin(p qᵢ)` to every revolute
/// joint (defaults A = 0.5 N·m, p = 5 per joint turn).
#[test]
fn ripple_adds_its_formula_on_joints_without_a_rotor() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let urdf = dir.join("panda.urdf");
    let arm = momentlmi::dynamics::robots::load_robot(
        urdf.to_str().unwrap(),
        Some(&dir.join("panda.toml")),
    )
    .unwrap();
    let n = arm.model.dof();
    let row = |k: usize, s: f64| -> Vec<f64> {
        (0..n)
            .map(|i| s * (0.3 * k as f64 + i as f64).sin())
            .collect()
    };
    let (mut q, mut qd, mut qdd) = (Samples::new(n), Samples::new(n), Samples::new(n));
    for k in 0..50 {
        q.push(&row(k, 1.0));
        qd.push(&row(k + 3, 0.7));
        qdd.push(&row(k + 5, 2.0));
    }
    let torques = |e: &str| {
        Library::builtin()
            .true_robot(&arm, &Effects::parse(e, &[]).unwrap())
            .unwrap()
            .torques(&q, &qd, &qdd)
            .unwrap()
    };
    let (none, ripple) = (torques(""), torques("ripple"));
    for k in 0..q.len() {
        for i in 0..n {
            let want = none[k][i] + 0.5 * (5.0 * q[k][i]).sin();
            assert!((ripple[k][i] - want).abs() < 1e-12, "joint {i} sample {k}");
        }
    }
}
