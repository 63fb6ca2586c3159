//! Failures that used to pass silently (a skipped sample counted, a zero
//! factor, zeros for a failed fit, a panic on an option) are named errors now.

use momentlmi::data::Dataset;
use momentlmi::diagnose::{DiagnoseError, DiagnoseOptions, diagnose};
use momentlmi::dynamics::Friction;
use momentlmi::dynamics::cheetah3;
use momentlmi::effects::{EffectError, Library, simulate};
use momentlmi::identify::{
    IdentifyError, IdentifyOptions, Level, StreamReducer, identify, reduce_samples,
    solve_identification,
};
use momentlmi::sim::{Effects, SimConfig, SimError};

fn leg_data(seconds: f64) -> Dataset {
    let leg = cheetah3::description();
    let fx = Effects::new(["rotor_inertia", "coulomb", "viscous"]);
    simulate(&leg, &SimConfig::for_robot(&leg, seconds, fx, 3), |_, _| {}).unwrap()
}

#[test]
fn a_sample_the_regressor_cannot_evaluate_is_named() {
    let model = cheetah3::model();
    let mut d = leg_data(1.0);
    // q with two values per sample for a three-joint robot
    d.q = momentlmi::data::Samples::from_rows(
        &d.q.iter().map(|r| r[..2].to_vec()).collect::<Vec<_>>(),
    );
    let e = reduce_samples(&model, &d.q, &d.qd, &d.qdd, &d.tau, 64).unwrap_err();
    assert!(
        matches!(
            e,
            IdentifyError::SampleLength {
                what: "q",
                expected: 3,
                found: 2,
                ..
            }
        ),
        "{e}"
    );
    let opts = IdentifyOptions::new(Level::None);
    assert!(identify(&model, &d, None, &opts).is_err());
    // the streaming reducer checks the torque too
    let mut s = StreamReducer::new(&model, 16);
    let e = s
        .push(&d.q[0], &d.qd[0], &d.qdd[0], &[1.0, 2.0])
        .unwrap_err();
    assert!(
        matches!(
            e,
            IdentifyError::SampleLength {
                sample: 0,
                what: "tau",
                ..
            }
        ),
        "{e}"
    );
    // the diagnosis reports the sample instead of a zero row or a panic
    let e = diagnose(&model, &Friction::zeros(3), &d, &DiagnoseOptions::default()).unwrap_err();
    assert!(matches!(e, DiagnoseError::Predict(_)), "{e}");
}

#[test]
fn a_failed_factorisation_is_an_error() {
    let model = cheetah3::model();
    let d = leg_data(1.0);
    let mut red = reduce_samples(&model, &d.q, &d.qd, &d.qdd, &d.tau, 256).unwrap();
    assert!(red.factor().is_ok());
    red.gram[(3, 5)] = f64::NAN;
    red.gram[(5, 3)] = f64::NAN;
    assert!(matches!(
        red.factor(),
        Err(IdentifyError::Factorisation { .. })
    ));
    let e =
        solve_identification(&model, &red, &IdentifyOptions::new(Level::Consistent)).unwrap_err();
    assert!(matches!(e, IdentifyError::Factorisation { .. }), "{e}");
    assert!(
        e.to_string().contains("failed (a value that is not finite"),
        "{e}"
    );
}

#[test]
fn a_solver_that_stops_early_is_its_status() {
    let leg = cheetah3::description();
    let d = leg_data(2.0);
    let opts = IdentifyOptions::for_robot(&leg, Level::Ellipsoid, 1e-6)
        .unwrap()
        .with_settings(momentlmi::conic::Settings::default().max_iter(2))
        .unwrap();
    let e = identify(&leg.model, &d, None, &opts).unwrap_err();
    assert!(
        matches!(e, IdentifyError::Solver(s) if !s.is_solved()),
        "{e}"
    );
    // the same problem with the default settings is solved
    let opts = IdentifyOptions::for_robot(&leg, Level::Ellipsoid, 1e-6).unwrap();
    assert!(
        identify(&leg.model, &d, None, &opts)
            .unwrap()
            .constraints_satisfied
    );
}

#[test]
fn options_out_of_range_are_refused_at_construction() {
    for (f, m, b, opt) in [
        (1.5, 4, 20, "train_fraction"),
        (-0.2, 4, 20, "train_fraction"),
        (f64::NAN, 4, 20, "train_fraction"),
        (0.6, 0, 20, "max_effects"),
        (0.6, 4, 1, "blocks"),
    ] {
        match DiagnoseOptions::new(f, m, b) {
            Err(DiagnoseError::Option { option, .. }) => assert_eq!(option, opt),
            other => panic!("{f} {m} {b}: {other:?}"),
        }
    }
    assert_eq!(
        DiagnoseOptions::new(0.6, 8, 20).unwrap(),
        DiagnoseOptions::default()
    );
    let base = IdentifyOptions::new(Level::Consistent);
    assert!(base.clone().with_prior(-1.0, vec![0.0; 60]).is_err());
    assert!(
        base.clone()
            .with_prior(f64::INFINITY, vec![0.0; 60])
            .is_err()
    );
    assert!(base.clone().with_prior(1e-6, vec![f64::NAN; 60]).is_err());
    assert!(base.clone().with_eps(-1e-3).is_err());
    // a prior of the wrong length is refused when solving, naming the counts
    let model = cheetah3::model();
    let d = leg_data(0.5);
    let short = base.with_prior(1e-6, vec![0.1; 10]).unwrap();
    let e = identify(&model, &d, None, &short).unwrap_err().to_string();
    assert!(e.contains("10 numbers for 6 bodies"), "{e}");
    // the simulator's settings
    let leg = cheetah3::description();
    for (seconds, what) in [(-1.0, "seconds"), (1e9, "seconds"), (f64::NAN, "seconds")] {
        let cfg = SimConfig::for_robot(&leg, seconds, Effects::default(), 1);
        match simulate(&leg, &cfg, |_, _| {}) {
            Err(EffectError::Sim(SimError::Setting { setting, .. })) => assert_eq!(setting, what),
            Err(EffectError::Sim(e @ SimError::Samples { .. })) => {
                assert!(e.to_string().contains("'seconds'"), "{e}")
            }
            other => panic!("{seconds}: {other:?}"),
        }
    }
    let mut cfg = SimConfig::for_robot(&leg, 1.0, Effects::default(), 1);
    cfg.cutoff_hz = 600.0;
    assert!(matches!(
        simulate(&leg, &cfg, |_, _| {}),
        Err(EffectError::Sim(SimError::Setting {
            setting: "cutoff_hz",
            ..
        }))
    ));
}

#[test]
fn unknown_effects_and_parameters_list_the_valid_names() {
    let lib = Library::builtin();
    let check = |list: &str, overrides: &[String]| {
        Effects::parse(list, overrides)
            .map_err(EffectError::from)
            .and_then(|fx| lib.check(&fx).map(|()| fx))
    };
    let e = check("coulomb,warp_drive", &[]).unwrap_err().to_string();
    assert!(
        e.contains("warp_drive") && e.contains("rotor_inertia") && e.contains("backlash"),
        "{e}"
    );
    let e = check("stribeck", &["stribek_force=2".into()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("stribek_force") && e.contains("stribeck_force") && e.contains("backlash_width"),
        "{e}"
    );
    // a parameter of an effect that is not on is not silently ignored
    let e = check("offset", &["stiffness=300".into()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("elasticity") && e.contains("not switched on"),
        "{e}"
    );
    // out of its range
    let e = check("elasticity", &["stiffness=-3".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("stiffness"), "{e}");
    assert!(check("offset", &["offset".into()]).is_err());
    let ok = check("elasticity, backlash", &["stiffness=300".into()]).unwrap();
    assert_eq!(ok.on, vec!["elasticity", "backlash"]);
    let leg = momentlmi::dynamics::cheetah3::description();
    assert_eq!(lib.magnitudes(&leg, &ok).unwrap()["stiffness"], 300.0);
}

#[test]
fn inputs_that_would_index_out_of_range_or_go_unnoticed_are_errors() {
    use momentlmi::data::{DataError, ReadOptions};
    use momentlmi::dynamics::sidecar::{MultiSine, Sidecar};
    use momentlmi::dynamics::urdf::model_from_urdf_str;
    use momentlmi::dynamics::{RobotDescription, cheetah3};
    use momentlmi::sim::trajectory::Trajectory;
    // ellipsoids of the wrong length at a level that does not need them
    let model = cheetah3::model();
    let d = leg_data(0.5);
    let e2 = cheetah3::ellipsoids()[..2].to_vec();
    let opts = IdentifyOptions::new(Level::Consistent).with_ellipsoids(e2);
    let e = identify(&model, &d, None, &opts).unwrap_err().to_string();
    assert!(e.contains("2 bounding ellipsoids for 6 bodies"), "{e}");
    // a partial set of qdd_* columns is not silently replaced by estimates
    let csv = "t,q_abad,qd_abad,qdd_abad,q_hip,qd_hip,q_knee,qd_knee,tau_abad,tau_hip,tau_knee\n0,0,0,0,0,0,0,0,0,0,0\n";
    let e =
        Dataset::parse_csv(csv, "p.csv", &cheetah3::JOINTS, ReadOptions::default()).unwrap_err();
    assert!(
        matches!(&e, DataError::MissingColumn { column, .. } if column == "qdd_hip"),
        "{e}"
    );
    // a mechanicalReduction that is not a number is named when it is needed
    let urdf = r#"<robot name="r"><link name="a"/><link name="b"/>
        <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
        <transmission name="t"><joint name="j"/><actuator name="m"><mechanicalReduction>fifty</mechanicalReduction></actuator></transmission></robot>"#;
    let sc = Sidecar::parse(
        "[[rotor]]\njoint = \"j\"\nmass = 0.1\ninertia = [1e-4, 0, 0, 1e-4, 0, 1e-4]\n",
        "s.toml",
    )
    .unwrap();
    let e = model_from_urdf_str(urdf, "r.urdf", Some(&sc))
        .unwrap_err()
        .to_string();
    assert!(e.contains("'fifty'") && e.contains("not a number"), "{e}");
    // <dynamics damping> alone: the missing friction is a placeholder, not a zero
    let urdf = r#"<robot name="r"><link name="a"/><link name="b"><inertial><mass value="1"/>
        <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
        <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/><dynamics damping="0.7"/></joint></robot>"#;
    let robot = momentlmi::urdf::read_str(urdf, "r.urdf").unwrap();
    let m = model_from_urdf_str(urdf, "r.urdf", None).unwrap();
    let r = RobotDescription::new("r.urdf", m.clone(), &Sidecar::default(), Some(&robot)).unwrap();
    assert_eq!(r.friction.viscous, vec![0.7]);
    assert_eq!(r.friction.coulomb, vec![0.5]);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.to_string().contains("placeholder"))
    );
    // an excitation with a non-finite coefficient: an error, not NaN data
    let mut cfg = SimConfig::for_robot(&r, 1.0, Effects::default(), 1);
    cfg.trajectory = Trajectory::multi_sine(&m, &MultiSine::default(), 1);
    if let Trajectory::Fourier { a, .. } = &mut cfg.trajectory {
        a[0][2] = f64::NAN;
    }
    let res = simulate(&r, &cfg, |_, _| {});
    assert!(
        matches!(res, Err(EffectError::Sim(SimError::NonFinite { .. }))),
        "{res:?}"
    );
    // the leg's shell on another 3-joint robot is refused
    let mut cfg = SimConfig::for_robot(&cheetah3::description(), 1.0, Effects::default(), 1);
    cfg.robot = "r.urdf".into();
    let three = r#"<robot name="r3"><link name="a"/><link name="b"/><link name="c"/><link name="d"/>
        <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>
        <joint name="j2" type="continuous"><parent link="b"/><child link="c"/></joint>
        <joint name="j3" type="continuous"><parent link="c"/><child link="d"/></joint></robot>"#;
    let m3 = model_from_urdf_str(three, "r3.urdf", None).unwrap();
    let r3 = RobotDescription::new("r3.urdf", m3, &Sidecar::default(), None).unwrap();
    assert!(matches!(
        simulate(&r3, &cfg, |_, _| {}),
        Err(EffectError::Sim(SimError::Setting {
            setting: "trajectory",
            ..
        }))
    ));
}

#[test]
fn a_repair_refuses_a_report_of_another_text() {
    use momentlmi::moments::urdf_check::{RepairOptions, check_urdf_str, repair_urdf};
    let link = |name: &str, ixx: &str| {
        format!(
            "<link name=\"{name}\"><inertial><mass value=\"1\"/><inertia ixx=\"{ixx}\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>"
        )
    };
    let bad = format!("<robot name=\"r\">{}</robot>", link("arm", "0.1"));
    let report = check_urdf_str(&bad, "a.urdf").unwrap();
    assert!(!report.consistent);
    let (fixed, names) = repair_urdf(&bad, &report, "a.urdf", &RepairOptions::default()).unwrap();
    assert_eq!(names, vec!["arm".to_string()]);
    assert!(check_urdf_str(&fixed, "b.urdf").unwrap().consistent);
    // the same report against another text: refused, not a garbled file
    let other = format!(
        "<robot name=\"somewhat longer\">   {}</robot>",
        link("arm", "0.1")
    );
    assert!(repair_urdf(&other, &report, "c.urdf", &RepairOptions::default()).is_err());
}

/// Numbers that span ~200 orders of magnitude: Clarabel 0.11 panicked
/// inside its PSD cone's SVD on them (faer's SVD did not converge), which
/// the conic layer turns into a solver error; with the one-sided Jacobi SVD
/// of small blocks (`faer_lapack::small`) the solve runs and ends with a
/// numerical error. Either way the caller gets an error naming the solver,
/// never a crash.
#[test]
fn a_hopeless_solve_is_an_error_not_a_crash() {
    use momentlmi::moments::{InertialParams, NearestOptions, nearest_consistent};
    let pi = InertialParams([1.0, 1e200, 0.0, 0.0, 0.02, 0.0, 0.0, 0.02, 0.0, 0.02]);
    let r = std::panic::catch_unwind(|| nearest_consistent(&pi, &NearestOptions::default()));
    let e = r
        .expect("the solver's panic escaped the conic layer")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("Clarabel failed") || e.contains("solver ended with status numerical_error"),
        "{e}"
    );
}
