//! `excite`: a designed motion stays inside every limit in the samples it
//! writes, improves on its random start, and never beats the convex bound
//! of a pool that contains it.

use momentlmi::dynamics::robots::load_robot;
use momentlmi::excite::{Criterion, ExciteOptions, design, samples};

fn quick(seconds: f64, pool: usize) -> ExciteOptions {
    ExciteOptions {
        seconds,
        seeds: 2,
        evaluations: 120,
        pool,
        ..ExciteOptions::default()
    }
}

#[test]
fn the_written_samples_keep_every_limit() {
    let leg = load_robot("cheetah3-leg", None).unwrap();
    let d = design(&leg, &quick(4.0, 0)).unwrap();
    let data = samples(&d, 1000.0).unwrap();
    assert_eq!(data.len(), 4000);
    for (k, ((q, qd), qdd)) in data.q.iter().zip(&data.qd).zip(&data.qdd).enumerate() {
        for (j, joint) in leg.model.joints.iter().enumerate() {
            let l = &d.limits[j];
            let (lo, hi) = joint.limits;
            assert!(
                q[j] >= lo && q[j] <= hi,
                "row {k} joint {j}: q {} outside the model's [{lo}, {hi}]",
                q[j]
            );
            assert!(
                q[j] >= l.position.0 && q[j] <= l.position.1,
                "row {k} joint {j}"
            );
            assert!(qd[j].abs() <= l.velocity, "row {k} joint {j}: q̇ {}", qd[j]);
            assert!(
                qdd[j].abs() <= l.acceleration,
                "row {k} joint {j}: q̈ {}",
                qdd[j]
            );
        }
    }
    // the exact derivatives: q̇ is the difference quotient of q
    let (q, qd) = (&data.q, &data.qd);
    let fd = (q[101][1] - q[99][1]) / 0.002;
    assert!(
        (fd - qd[100][1]).abs() < 1e-3 * (1.0 + qd[100][1].abs()),
        "{fd} vs {}",
        qd[100][1]
    );
    assert!(
        d.value > d.best_seed_value,
        "the search did not improve on its start"
    );
    assert!(
        d.margins
            .iter()
            .all(|m| m.iter().all(|&x| (0.0..=1.0).contains(&x)))
    );
}

#[test]
fn the_design_is_never_above_the_convex_bound_of_its_pool() {
    let arm_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let arm = load_robot(
        arm_dir.join("panda.urdf").to_str().unwrap(),
        Some(&arm_dir.join("panda.toml")),
    )
    .unwrap();
    for criterion in [Criterion::D, Criterion::E] {
        let opts = ExciteOptions {
            criterion,
            ..quick(5.0, 12)
        };
        let d = design(&arm, &opts).unwrap();
        let p = d.pool.as_ref().unwrap();
        assert_eq!(p.candidates, 13);
        assert!(
            p.designed <= p.bound + 1e-6 * p.bound.abs().max(1.0),
            "{criterion:?}: {p:?}"
        );
        assert!(p.efficiency > 0.0 && p.efficiency <= 1.0 + 1e-6, "{p:?}");
        assert!((p.weights.iter().sum::<f64>() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn bad_settings_are_named() {
    let leg = load_robot("cheetah3-leg", None).unwrap();
    let e = design(&leg, &quick(-1.0, 0)).unwrap_err().to_string();
    assert!(e.contains("seconds"), "{e}");
    // a pool of 10⁸ candidates (≈ 1 TB of information matrices) is refused
    // before any is made, not grown until the memory runs out
    let e = design(&leg, &quick(1.0, 100_000_000))
        .unwrap_err()
        .to_string();
    assert!(e.contains("100000001 candidates"), "{e}");
    let d = design(&leg, &quick(1.0, 0)).unwrap();
    assert!(
        samples(&d, 0.0)
            .unwrap_err()
            .to_string()
            .contains("rate_hz")
    );
}

#[test]
fn the_sidecars_rate_limits_are_kept_and_bad_ones_named() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/panda");
    let text = std::fs::read_to_string(dir.join("panda.toml")).unwrap();
    let tmp = std::env::temp_dir().join(format!("momentlmi-excite-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let with = |extra: &str| {
        let side = tmp.join("panda.toml");
        let t = text.replacen(
            "name = \"panda_joint2\"\n",
            &format!("name = \"panda_joint2\"\n{extra}\n"),
            1,
        );
        assert_ne!(t, text, "the sidecar has no panda_joint2 entry");
        std::fs::write(&side, t).unwrap();
        // the sidecar's mapping and meshes are found beside the URDF
        load_robot(dir.join("panda.urdf").to_str().unwrap(), Some(&side))
    };
    let arm = with("max_velocity = 0.5\nmax_acceleration = 1.5\nmax_effort = 1.0").unwrap();
    let d = design(&arm, &quick(5.0, 0)).unwrap();
    let l = &d.limits[1];
    assert_eq!((l.velocity, l.acceleration), (0.5, 1.5));
    assert_eq!(
        (l.velocity_from, l.acceleration_from),
        ("description", "description")
    );
    // gravity alone needs more than 1 N·m at the shoulder
    assert!(d.torque_margins[1].unwrap() < 0.0, "{:?}", d.torque_margins);
    let data = samples(&d, 500.0).unwrap();
    assert!(
        data.qd.iter().all(|r| r[1].abs() <= 0.5) && data.qdd.iter().all(|r| r[1].abs() <= 1.5)
    );
    let e = with("max_velocity = -1").unwrap_err().to_string();
    assert!(
        e.contains("panda_joint2") && e.contains("max_velocity"),
        "{e}"
    );
}

/// A one-joint arm whose position range binds (its velocity limit is
/// generous): the peak between grid points must not pass the limit.
#[test]
fn a_binding_position_limit_is_kept_between_grid_points() {
    let tmp = std::env::temp_dir().join(format!("momentlmi-excite-one-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let urdf = tmp.join("one.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="one"><link name="base"/>
<link name="arm"><inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="20" effort="10"/></joint></robot>"#,
    )
    .unwrap();
    let arm = load_robot(urdf.to_str().unwrap(), None).unwrap();
    for seed in 1..4 {
        // a slow motion: neither its speed nor its acceleration binds
        let slow = ExciteOptions {
            seed,
            base_hz: 0.05,
            harmonics: 3,
            ..quick(20.0, 0)
        };
        let d = design(&arm, &slow).unwrap();
        assert!(
            d.margins[0][0] < 0.1,
            "the position does not bind: {:?}",
            d.margins
        );
        samples(&d, 1000.0).unwrap();
    }
    let e = design(
        &arm,
        &ExciteOptions {
            base_hz: 1e9,
            ..quick(10.0, 0)
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("base_hz"), "{e}");
}
