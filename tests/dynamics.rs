//! Dynamics checked against an independent library (reference values copied
//! from Pinocchio 4.1.0 output for the 3-link leg, links only) and against
//! itself: Y π = τ, CRBA vs unit-acceleration RNEA, forward dynamics inverts
//! RNEA, and energy balance along a simulated trajectory (which checks the
//! rotor terms independently).

use momentlmi::dynamics::{Data, Model, cheetah3, crba, energy, forward_dynamics, regressor, rnea};
use std::path::Path;

struct Case {
    q: [f64; 3],
    qd: [f64; 3],
    qdd: [f64; 3],
    tau: [f64; 3],
    y: [[f64; 30]; 3],
    m: [[f64; 3]; 3],
}

/// Two cases of `rnea_leg3.json` (Pinocchio): links only, no rotors.
const CASES: [Case; 2] = [
    Case {
        q: [-3.115448073325186, 0.7238422476106363, 3.041022673471651],
        qd: [0.22661438807668688, -2.440843235045091, 0.6099530587992144],
        qdd: [9.515858308442478, 1.424486465081948, -10.944395973420917],
        tau: [-1.382699843801487, -2.436465266973584, -0.1435750904097498],
        y: [
            [
                0.0,
                0.0,
                -9.806647431800414,
                0.2564491145672814,
                9.515858308442478,
                0.0,
                0.0,
                -0.0,
                0.0,
                0.0,
                -0.4220295213564227,
                -0.04031524675220416,
                8.950220184040594,
                -0.05118018506792654,
                5.891151696156279,
                2.8782867451119127,
                9.307985715691082,
                0.0,
                -5.407310185396198,
                3.6247066122861997,
                0.2845267689260315,
                -3.1064036614063704,
                7.100920100635091,
                3.9516476294971388,
                6.6670887896129765,
                -9.686546848925135,
                8.755603088137986,
                8.326672684688674e-17,
                -2.8348643816228645,
                2.8487695188295024,
            ],
            [
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                7.026947839038113,
                0.0,
                6.2110405534808635,
                0.02548269876187227,
                -7.1299154364804735,
                -0.006306336386724825,
                1.424486465081948,
                -6.302052460507705,
                -0.02548269876187227,
                -1.9545816760106265,
                -7.0025118855915265,
                -2.155301941493635,
                -8.301133937496445,
                0.024338993702793566,
                7.726618116959884,
                -0.016361392529896,
                -9.51990950833897,
                5.5543615133533635,
                -0.024338993702793566,
            ],
            [
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                -5.528192194555467,
                0.0,
                -5.186323628230449,
                0.024338993702793566,
                7.726618116959884,
                -0.016361392529896,
                -9.51990950833897,
                5.5543615133533635,
                -0.024338993702793566,
            ],
        ],
        m: [
            [
                0.07633960396902416,
                0.012238907489530283,
                0.0004967816485271748,
            ],
            [
                0.012238907489530283,
                0.12270197701366112,
                0.012890830725461502,
            ],
            [
                0.0004967816485271748,
                0.012890830725461502,
                0.02714252268535285,
            ],
        ],
    },
    Case {
        q: [2.24782585338193, -1.6997812437389428, 1.2889646519373201],
        qd: [2.620876704681253, -1.8974563988843989, -2.7902913876977733],
        qdd: [-16.206159127523154, 10.731324427812812, 17.907088910101997],
        tau: [-2.3439173578678, 5.432057501254076, 1.205553970514614],
        y: [
            [
                0.0,
                0.0,
                -6.145773647956959,
                -7.6462779355760935,
                -16.206159127523154,
                0.0,
                0.0,
                -0.0,
                0.0,
                0.0,
                -0.3093772863912976,
                -7.681314079516502,
                7.604327969434044,
                1.4832597539673018,
                1.0005703896511067,
                -2.1900885961255487,
                5.482400102666757,
                -1.1102230246251565e-16,
                11.105282062560708,
                -17.20672951717426,
                -0.6996214071929628,
                -2.8612943093986516,
                11.402334434829807,
                -6.048281321743721,
                -22.61803028464331,
                -35.031440781767294,
                -4.867081437271603,
                -6.661338147750939e-16,
                -8.709568931259014,
                6.411871157120155,
            ],
            [
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                -0.8843209989049337,
                0.0,
                -6.817939570943736,
                0.8762024085398975,
                -2.0845586784518453,
                6.641698996595433,
                10.731324427812812,
                -16.071534114162628,
                -0.8762024085398975,
                3.689398102149917,
                22.191377641816384,
                -5.496464667043619,
                1.561088422340677,
                -2.5149417555916864,
                14.857725916053234,
                -4.677965376980343,
                28.63841333791481,
                -6.472061052712817,
                2.5149417555916864,
            ],
            [
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                9.762911583189705,
                0.0,
                -5.069735459662931,
                -2.5149417555916864,
                14.857725916053234,
                -4.677965376980343,
                28.63841333791481,
                -6.472061052712817,
                2.5149417555916864,
            ],
        ],
        m: [
            [
                0.03764869210942226,
                -0.02014511167982613,
                -0.0030049578541480396,
            ],
            [
                -0.02014511167982613,
                0.1741572036775938,
                0.03861844405742782,
            ],
            [
                -0.0030049578541480396,
                0.03861844405742782,
                0.02714252268535285,
            ],
        ],
    },
];

fn links_only() -> Model {
    let m = cheetah3::model();
    Model::new("leg3", m.joints.clone(), vec![], m.gravity).unwrap()
}

fn max_abs_diff(a: impl IntoIterator<Item = f64>, b: impl IntoIterator<Item = f64>) -> f64 {
    a.into_iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn leg3_matches_reference_values() {
    let model = links_only();
    let mut data = Data::new(&model);
    for (k, c) in CASES.iter().enumerate() {
        let tau = rnea(&model, &mut data, &c.q, &c.qd, &c.qdd)
            .unwrap()
            .clone();
        assert!(
            max_abs_diff(tau.iter().copied(), c.tau) < 1e-9,
            "case {k} tau {tau:?}"
        );
        let y = regressor(&model, &mut data, &c.q, &c.qd, &c.qdd)
            .unwrap()
            .clone();
        for i in 0..3 {
            assert!(
                max_abs_diff((0..30).map(|j| y[(i, j)]), c.y[i]) < 1e-9,
                "case {k} regressor row {i}"
            );
        }
        let m = crba(&model, &mut data, &c.q).unwrap().clone();
        for i in 0..3 {
            assert!(
                max_abs_diff((0..3).map(|j| m[(i, j)]), c.m[i]) < 1e-9,
                "case {k} mass row {i}"
            );
        }
    }
}

/// All cases of the reference files in ../shared, when present.
#[test]
fn all_reference_cases_in_shared() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/reference/rnea_leg3.json");
    let Ok(text) = std::fs::read_to_string(&p) else {
        println!("skipping: {} not found", p.display());
        return;
    };
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let model = links_only();
    // the file's body parameters are our true link parameters
    let params: Vec<f64> = v["body_parameters"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|b| b.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect();
    assert!(max_abs_diff(model.params(), params.iter().copied()) < 1e-15);
    check_cases(&model, &v, 30);
}

fn vec_of(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn check_cases(model: &Model, v: &serde_json::Value, ncols: usize) {
    let mut data = Data::new(model);
    let cases = v["cases"].as_array().unwrap();
    assert!(!cases.is_empty());
    for (k, c) in cases.iter().enumerate() {
        let (q, qd, qdd) = (vec_of(&c["q"]), vec_of(&c["qd"]), vec_of(&c["qdd"]));
        let tau = rnea(model, &mut data, &q, &qd, &qdd).unwrap().clone();
        assert!(
            max_abs_diff(tau.iter().copied(), vec_of(&c["tau"])) < 1e-9,
            "case {k}: tau"
        );
        let y = regressor(model, &mut data, &q, &qd, &qdd).unwrap().clone();
        for (i, row) in c["regressor_rows"].as_array().unwrap().iter().enumerate() {
            let want = vec_of(row);
            assert_eq!(want.len(), ncols);
            assert!(
                max_abs_diff((0..ncols).map(|j| y[(i, j)]), want) < 1e-9,
                "case {k}: regressor row {i}"
            );
        }
        let m = crba(model, &mut data, &q).unwrap().clone();
        for (i, row) in c["mass_matrix"].as_array().unwrap().iter().enumerate() {
            assert!(
                max_abs_diff((0..model.dof()).map(|j| m[(i, j)]), vec_of(row)) < 1e-9,
                "case {k}: mass row {i}"
            );
        }
    }
}

/// Deterministic test states.
#[path = "support/rng.rs"]
mod rng;
use rng::Rng;

#[test]
fn regressor_times_params_equals_rnea_with_rotors_and_friction() {
    let model = cheetah3::model();
    let mut data = Data::new(&model);
    let mut rng = Rng(11);
    let b = [0.1, 0.2, 0.3];
    let bc = cheetah3::COULOMB;
    let mut theta = model.params();
    theta.extend(b);
    theta.extend(bc);
    for _ in 0..50 {
        let (q, qd, qdd) = (rng.v(3.0), rng.v(10.0), rng.v(50.0));
        let tau = rnea(&model, &mut data, &q, &qd, &qdd).unwrap().clone();
        let y = regressor(&model, &mut data, &q, &qd, &qdd).unwrap().clone();
        assert_eq!(y.ncols(), 66);
        for i in 0..3 {
            let pred: f64 = (0..66).map(|j| y[(i, j)] * theta[j]).sum();
            let want = tau[i] + b[i] * qd[i] + bc[i] * qd[i].signum();
            assert!(
                (pred - want).abs() < 1e-10 * (1.0 + want.abs()),
                "{pred} vs {want}"
            );
        }
    }
}

#[test]
fn crba_matches_unit_acceleration_rnea_and_the_regressor() {
    let model = cheetah3::model();
    let mut data = Data::new(&model);
    let mut rng = Rng(5);
    let nog = Model::new(
        "nog",
        model.joints.clone(),
        model.rotors.clone(),
        nalgebra::Vector3::zeros(),
    )
    .unwrap();
    let mut dn = Data::new(&nog);
    let theta = model.params();
    for _ in 0..20 {
        let q = rng.v(3.0);
        let m = crba(&model, &mut data, &q).unwrap().clone();
        // symmetric positive definite, and larger than links-only by the rotors' N² I
        assert!((m.clone() - m.transpose()).abs().max() < 1e-14);
        assert!(m.clone().cholesky().is_some());
        for j in 0..3 {
            let mut e = vec![0.0; 3];
            e[j] = 1.0;
            let col = rnea(&nog, &mut dn, &q, &[0.0; 3], &e).unwrap().clone();
            let y = regressor(&nog, &mut dn, &q, &[0.0; 3], &e).unwrap().clone();
            for i in 0..3 {
                assert!((m[(i, j)] - col[i]).abs() < 1e-12, "M[{i},{j}]");
                let from_y: f64 = (0..60).map(|k| y[(i, k)] * theta[k]).sum();
                assert!((m[(i, j)] - from_y).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn forward_dynamics_inverts_rnea() {
    let model = cheetah3::model();
    let mut data = Data::new(&model);
    let mut rng = Rng(9);
    for _ in 0..20 {
        let (q, qd, qdd) = (rng.v(3.0), rng.v(10.0), rng.v(50.0));
        let tau = rnea(&model, &mut data, &q, &qd, &qdd).unwrap().clone();
        let back = forward_dynamics(&model, &mut data, &q, &qd, tau.as_slice()).unwrap();
        for i in 0..3 {
            assert!((back[i] - qdd[i]).abs() < 1e-9 * (1.0 + qdd[i].abs()));
        }
    }
}

/// d/dt (T + U) = q̇ᵀτ: integrate the forward dynamics with RK4 under a
/// known torque and compare the energy change with the work done. Both sides
/// use the rotors' inertia (T from the mass matrix, U from every body), so a
/// missing gyroscopic or reflected-inertia term in the dynamics breaks it.
#[test]
fn energy_balance_along_a_simulated_trajectory() {
    let model = cheetah3::model();
    let mut data = Data::new(&model);
    let tau_of = |t: f64| {
        [
            2.0 * (3.0 * t).sin(),
            -3.0 * (2.0 * t).cos(),
            1.5 * (5.0 * t).sin(),
        ]
    };
    let f = |data: &mut Data, t: f64, x: &[f64; 6]| -> [f64; 6] {
        let qdd = forward_dynamics(&model, data, &x[..3], &x[3..], &tau_of(t)).unwrap();
        [x[3], x[4], x[5], qdd[0], qdd[1], qdd[2]]
    };
    let dt = 1e-4;
    let mut x = [0.3, -0.8, 1.4, 2.0, -1.0, 3.0];
    let e0 = {
        let (t, u) = energy(&model, &mut data, &x[..3], &x[3..]).unwrap();
        t + u
    };
    let mut work = 0.0;
    let power = |t: f64, x: &[f64; 6]| (0..3).map(|i| x[3 + i] * tau_of(t)[i]).sum::<f64>();
    for step in 0..10_000 {
        let t = step as f64 * dt;
        let k1 = f(&mut data, t, &x);
        let add = |a: &[f64; 6], b: &[f64; 6], s: f64| {
            std::array::from_fn::<f64, 6, _>(|i| a[i] + s * b[i])
        };
        let k2 = f(&mut data, t + dt / 2.0, &add(&x, &k1, dt / 2.0));
        let k3 = f(&mut data, t + dt / 2.0, &add(&x, &k2, dt / 2.0));
        let k4 = f(&mut data, t + dt, &add(&x, &k3, dt));
        let xn: [f64; 6] =
            std::array::from_fn(|i| x[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        // Simpson's rule for the work over the step
        let xm = add(&x, &k2, dt / 2.0);
        work += dt / 6.0 * (power(t, &x) + 4.0 * power(t + dt / 2.0, &xm) + power(t + dt, &xn));
        x = xn;
    }
    let (t1, u1) = energy(&model, &mut data, &x[..3], &x[3..]).unwrap();
    let de = t1 + u1 - e0;
    assert!(
        de.abs() > 0.1,
        "the test must move energy around: ΔE = {de}"
    );
    println!("ΔE = {de}, work = {work}");
    assert!(
        (de - work).abs() < 1e-6 * (1.0 + work.abs()),
        "ΔE = {de}, work = {work}"
    );
    // and the rotors matter: dropping them changes the energy noticeably
    let links = Model::new("links", model.joints.clone(), vec![], model.gravity).unwrap();
    let mut dl = Data::new(&links);
    let (tl, _) = energy(&links, &mut dl, &x[..3], &x[3..]).unwrap();
    assert!((t1 - tl).abs() > 0.01 * t1.abs());
}

#[test]
fn bad_lengths_are_errors() {
    let model = cheetah3::model();
    let mut data = Data::new(&model);
    assert!(rnea(&model, &mut data, &[0.0; 2], &[0.0; 3], &[0.0; 3]).is_err());
    assert!(crba(&model, &mut data, &[0.0; 4]).is_err());
}

/// A tree with a prismatic joint and a branch: Y π = RNEA τ and CRBA equals
/// unit-acceleration RNEA (checks the prismatic subspace and branching).
#[test]
fn prismatic_joint_and_branching_tree() {
    use momentlmi::dynamics::spatial::Transform;
    use momentlmi::dynamics::{Joint, JointKind};
    use momentlmi::moments::InertialParams;
    use nalgebra::{Matrix3, Vector3};
    let body = |m: f64, c: [f64; 3]| {
        InertialParams::from_mass_com_inertia(
            m,
            Vector3::from(c),
            Matrix3::from_diagonal(&Vector3::new(0.02, 0.03, 0.04)),
        )
    };
    let j = |name: &str, parent, kind, axis: [f64; 3], p: [f64; 3], inertia| Joint {
        name: name.into(),
        body: name.into(),
        parent,
        kind,
        axis: Vector3::from(axis).normalize(),
        x_tree: Transform::from_pose(
            &momentlmi::moments::rpy_rotation([0.1, -0.2, 0.3]),
            &Vector3::from(p),
        ),
        limits: (-1.0, 1.0),
        inertia,
    };
    let joints = vec![
        j(
            "slide",
            None,
            JointKind::Prismatic,
            [1.0, 0.0, 0.2],
            [0.0, 0.0, 0.1],
            body(2.0, [0.1, 0.0, 0.0]),
        ),
        j(
            "left",
            Some(0),
            JointKind::Revolute,
            [0.0, 1.0, 0.0],
            [0.2, 0.1, 0.0],
            body(1.0, [0.0, 0.0, -0.2]),
        ),
        j(
            "right",
            Some(0),
            JointKind::Revolute,
            [0.0, 0.0, 1.0],
            [-0.2, 0.1, 0.0],
            body(0.7, [0.1, 0.1, 0.0]),
        ),
        j(
            "tip",
            Some(2),
            JointKind::Prismatic,
            [0.0, 0.0, 1.0],
            [0.3, 0.0, 0.0],
            body(0.3, [0.0, 0.05, 0.0]),
        ),
    ];
    let model = Model::new(
        "tree",
        joints,
        vec![],
        nalgebra::Vector3::new(0.0, 0.0, -9.81),
    )
    .unwrap();
    let nog = Model::new(
        "tree",
        model.joints.clone(),
        vec![],
        nalgebra::Vector3::zeros(),
    )
    .unwrap();
    let (mut d, mut dn) = (Data::new(&model), Data::new(&nog));
    let theta = model.params();
    let mut rng = Rng(21);
    for _ in 0..20 {
        let v = |r: &mut Rng, s: f64| (0..4).map(|_| s * r.f()).collect::<Vec<f64>>();
        let (q, qd, qdd) = (v(&mut rng, 1.0), v(&mut rng, 3.0), v(&mut rng, 10.0));
        let tau = rnea(&model, &mut d, &q, &qd, &qdd).unwrap().clone();
        let y = regressor(&model, &mut d, &q, &qd, &qdd).unwrap().clone();
        for i in 0..4 {
            let pred: f64 = (0..40).map(|k| y[(i, k)] * theta[k]).sum();
            assert!((pred - tau[i]).abs() < 1e-10 * (1.0 + tau[i].abs()));
        }
        let m = crba(&model, &mut d, &q).unwrap().clone();
        for jj in 0..4 {
            let mut e = vec![0.0; 4];
            e[jj] = 1.0;
            let col = rnea(&nog, &mut dn, &q, &[0.0; 4], &e).unwrap();
            for i in 0..4 {
                assert!((m[(i, jj)] - col[i]).abs() < 1e-12);
            }
        }
        // left and right are on different branches: no coupling
        assert_eq!(m[(1, 2)], 0.0);
        assert_eq!(m[(1, 3)], 0.0);
    }
    structure_holds(&model, 4);
    // the branch: 'left' moves only itself, 'slide' everything
    let cols = momentlmi::dynamics::regressor_row_columns(&model);
    assert_eq!(cols[1], (10..20).chain([41, 45]).collect::<Vec<_>>());
    assert_eq!(cols[0].len(), 40 + 2);
}

/// Every regressor row is zero outside the columns
/// `regressor_row_columns` gives it, and each of those is non-zero at
/// some random state (the structure is neither too small nor padded).
fn structure_holds(model: &Model, n: usize) {
    let cols = momentlmi::dynamics::regressor_row_columns(model);
    let p = model.regressor_columns();
    let mut seen = vec![vec![false; p]; n];
    let (mut d, mut rng) = (Data::new(model), Rng(5));
    for _ in 0..20 {
        let v = |r: &mut Rng, s: f64| (0..n).map(|_| s * r.f()).collect::<Vec<f64>>();
        let (q, qd, qdd) = (v(&mut rng, 1.0), v(&mut rng, 3.0), v(&mut rng, 10.0));
        let y = regressor(model, &mut d, &q, &qd, &qdd).unwrap();
        for (i, s) in seen.iter_mut().enumerate() {
            for (c, z) in s.iter_mut().enumerate() {
                if y[(i, c)] != 0.0 {
                    assert!(cols[i].contains(&c), "row {i} column {c}");
                    *z = true;
                }
            }
        }
    }
    for i in 0..n {
        // a body's inertia columns may vanish in a row by its axis (the
        // row sees only the moments about it), but never a whole body
        for chunk in cols[i].chunks(10).filter(|c| c.len() == 10) {
            assert!(
                chunk.iter().any(|&c| seen[i][c]),
                "row {i}: {chunk:?} all zero"
            );
        }
    }
}

#[test]
fn the_leg_regressor_has_the_row_structure_given() {
    let model = cheetah3::model();
    structure_holds(&model, 3);
    let cols = momentlmi::dynamics::regressor_row_columns(&model);
    // the knee (joint 2) moves the shank and drives its rotor, carried by the thigh
    assert_eq!(
        cols[2],
        (20..30).chain(50..60).chain([62, 65]).collect::<Vec<_>>()
    );
}
