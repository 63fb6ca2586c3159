//! The moments layer: conversions, checks, ellipsoids, four point masses,
//! unions (Corollary 2), nearest consistent inertia and the LMI blocks.

use approx::assert_relative_eq;
use momentlmi::conic::{AffExpr, Problem};
use momentlmi::moments::{
    Ellipsoid, InertialParams, NearestOptions, UnionRealization, Verdict, check_consistency,
    check_realizable, four_point_masses, four_point_masses_in, lmi::BodyVars, nearest_consistent,
    point_masses_on_union, pseudo_inertia_of, realize_on_union, rpy_rotation,
};
use nalgebra::{Matrix3, Matrix4, Vector3};
use proptest::prelude::*;

/// Identified Cheetah 3 parameters (Cheetah-Software order
/// [m, hx, hy, hz, Ixx, Iyy, Izz, Iyz, Ixz, Ixy]) and bounding ellipsoids
/// (centre, semi-axes), from the project's reference notes.
const CHEETAH: [(&str, [f64; 10], [f64; 3], [f64; 3]); 6] = [
    (
        "abad",
        [
            1.645278752937798,
            3.987e-24,
            1.050694793045323e-01,
            -7.248117018543008e-03,
            6.871761154771191e-03,
            2.715028710162546e-04,
            6.820782113449669e-03,
            4.545198314447007e-04,
            1.0e-25,
            -2.2e-25,
        ],
        [0.0, 0.045, 0.0],
        [0.081, 0.081, 0.081],
    ),
    (
        "hip",
        [
            1.071200401412615,
            -7.564034441661159e-04,
            -3.180527291037499e-02,
            -1.047496808654130e-01,
            2.020976253260794e-02,
            1.856851411013688e-02,
            3.115448656660994e-03,
            1.294666102054298e-04,
            1.217274116646696e-03,
            -4.116533457993085e-04,
        ],
        [0.0, 0.0, -0.171],
        [0.0594, 0.0594, 0.36936],
    ),
    (
        "knee",
        [
            9.019384095786234e-01,
            2.215928611851693e-02,
            3.623331361414656e-03,
            -4.411934868569409e-02,
            2.269554734974269e-02,
            2.714252268535285e-02,
            5.566745484613744e-03,
            -3.238036214456428e-04,
            -2.194717054345885e-03,
            1.274627163554897e-03,
        ],
        [0.0, 0.0, -0.16],
        [0.12, 0.09, 0.32],
    ),
    (
        "abad rotor",
        [
            4.999939189070923e-01,
            1.18e-24,
            1.976769699734076e-03,
            -3.681440077402916e-04,
            9.908339941420835e-04,
            4.955917167197880e-04,
            4.956200895280653e-04,
            3.533262919985919e-08,
            5.8e-27,
            1.3e-27,
        ],
        [0.0; 3],
        [0.081; 3],
    ),
    (
        "hip rotor",
        [
            5.405045213157799e-01,
            -3.164547557293410e-03,
            -6.776800604201722e-03,
            7.158586831736347e-04,
            4.352341568156850e-04,
            1.015373256571613e-03,
            9.126776037286181e-04,
            -3.097121515937353e-05,
            -2.154046949222089e-04,
            1.306997274233568e-04,
        ],
        [0.0; 3],
        [0.081; 3],
    ),
    (
        "knee rotor",
        [
            5.398676189202086e-01,
            -2.571556872957194e-04,
            -7.550002224983261e-03,
            1.125959428120149e-03,
            7.035267590972641e-04,
            8.693209041255046e-04,
            4.122075637011218e-04,
            -3.986925582339967e-05,
            -2.295396403157565e-04,
            2.324567952553503e-05,
        ],
        [0.0; 3],
        [0.081; 3],
    ),
];

#[test]
fn cheetah_identified_bodies_are_consistent_on_the_boundary() {
    for (name, p, c, a) in CHEETAH {
        let pi = InertialParams::from_spatial_v2(p);
        let r = check_consistency(&pi, 1e-12);
        assert_eq!(r.verdict, Verdict::Ok, "{name}: {r:?}");
        assert!(r.consistent, "{name}");
        // tiny but positive margin: on the boundary, not rejected
        assert!(
            r.pseudo_inertia_min_eig > 0.0 && r.pseudo_inertia_min_eig < 1e-6,
            "{name}: {}",
            r.pseudo_inertia_min_eig
        );
        let s = Ellipsoid::new(Vector3::from(c), Vector3::from(a)).unwrap();
        let q = check_realizable(&pi, &s, 1e-12);
        assert!(q.realizable && q.com_inside, "{name}: {q:?}");
        assert!(
            q.trace_jq > 0.05 && q.trace_jq < 2.0,
            "{name}: tr(JQ) = {}",
            q.trace_jq
        );
    }
    // the public example's own knee ellipsoid does not contain the identified knee
    let knee = InertialParams::from_spatial_v2(CHEETAH[2].1);
    let small = Ellipsoid::new(
        Vector3::new(0.0, 0.0, -0.1725),
        Vector3::new(0.042, 0.042, 0.2898),
    )
    .unwrap();
    let q = check_realizable(&knee, &small, 1e-12);
    assert!(!q.realizable);
    assert_relative_eq!(q.trace_jq, -2.66, epsilon = 0.01);
}

#[test]
fn conversions_round_trip() {
    let pi = InertialParams::from_spatial_v2(CHEETAH[1].1);
    assert_eq!(InertialParams::from_pinocchio(pi.to_pinocchio()), pi);
    assert_eq!(InertialParams::from_spatial_v2(pi.to_spatial_v2()), pi);
    let close = |a: &InertialParams, b: &InertialParams| {
        a.0.iter().zip(&b.0).all(|(x, y)| (x - y).abs() < 1e-14)
    };
    assert!(close(&InertialParams::from_spatial(&pi.spatial()), &pi));
    assert!(close(
        &InertialParams::from_pseudo_inertia(&pi.pseudo_inertia()),
        &pi
    ));
    let mci = pi.to_mass_com_inertia();
    assert!(close(
        &InertialParams::from_mass_com_inertia(mci.mass, mci.com, mci.inertia_com),
        &pi
    ));
    let (m, xyz, ic) = pi.to_urdf();
    assert!(close(&InertialParams::from_urdf(m, xyz, [0.0; 3], ic), &pi));
    // URDF with rpy: a rotated principal frame gives the same body
    let rpy = [0.3, -0.2, 1.1];
    let r = rpy_rotation(rpy);
    let ic_m = mci.inertia_com;
    let local = r.transpose() * ic_m * r;
    let u = InertialParams::from_urdf(
        m,
        xyz,
        rpy,
        [
            local[(0, 0)],
            local[(0, 1)],
            local[(0, 2)],
            local[(1, 1)],
            local[(1, 2)],
            local[(2, 2)],
        ],
    );
    assert!(close(&u, &pi));
    // Pinocchio order puts Iyy before Ixz
    let pin = pi.to_pinocchio();
    assert_eq!(pin[6], pi.0[7]);
    assert_eq!(pin[7], pi.0[6]);
    // Σ_C = ½tr(Ī_C)1 − Ī_C and J's Schur complement is Σ_C
    let ic = pi.inertia_com();
    let sc = Matrix3::identity() * (0.5 * ic.trace()) - ic;
    assert!((sc - pi.covariance()).abs().max() < 1e-15);
    // kinetic energy: ½vᵀI v = ½tr(V J Vᵀ)
    let w = Vector3::new(0.3, -1.2, 0.7);
    let v = Vector3::new(0.5, 0.1, -0.4);
    let mut vv = Matrix4::zeros();
    vv.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&momentlmi::moments::skew(&w));
    for k in 0..3 {
        vv[(k, 3)] = v[k];
    }
    let tw = nalgebra::Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z);
    let ke1 = 0.5 * (tw.transpose() * pi.spatial() * tw)[(0, 0)];
    let ke2 = 0.5 * (vv * pi.pseudo_inertia() * vv.transpose()).trace();
    assert_relative_eq!(ke1, ke2, epsilon = 1e-14);
}

/// Random point masses inside an ellipsoid and their π.
fn cloud(seed: &[f64], s: &Ellipsoid, n: usize) -> InertialParams {
    let mut acc = Matrix4::zeros();
    for k in 0..n {
        let u = Vector3::new(
            seed[(3 * k) % seed.len()],
            seed[(3 * k + 1) % seed.len()],
            seed[(3 * k + 2) % seed.len()],
        );
        let u = if u.norm() > 1.0 { u / u.norm() } else { u } * 0.999;
        let x = s.center + s.rotation * u.component_mul(&s.semi_axes);
        let w = 0.1 + seed[k % seed.len()].abs();
        let v = nalgebra::Vector4::new(x.x, x.y, x.z, 1.0);
        acc += v * v.transpose() * w;
    }
    InertialParams::from_pseudo_inertia(&acc)
}

fn ellipsoid_from(v: &[f64]) -> Ellipsoid {
    let r = rpy_rotation([v[0] * 3.0, v[1] * 3.0, v[2] * 3.0]);
    Ellipsoid::with_rotation(
        Vector3::new(v[3], v[4], v[5]),
        Vector3::new(0.1 + v[6].abs(), 0.1 + v[7].abs(), 0.1 + v[8].abs()),
        r,
    )
    .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn clouds_in_ellipsoids_pass_every_check(e in prop::collection::vec(-1.0f64..1.0, 9), pts in prop::collection::vec(-1.0f64..1.0, 30)) {
        let s = ellipsoid_from(&e);
        let pi = cloud(&pts, &s, 10);
        let c = check_consistency(&pi, 1e-12);
        prop_assert_eq!(c.verdict, Verdict::Ok);
        prop_assert!(c.semi_consistent && c.consistent);
        let r = check_realizable(&pi, &s, 1e-12);
        prop_assert!(r.realizable && r.com_inside, "{:?}", r);
        prop_assert!(r.trace_jq >= 0.0);
    }

    #[test]
    fn four_point_recovery_round_trips(e in prop::collection::vec(-1.0f64..1.0, 9), pts in prop::collection::vec(-1.0f64..1.0, 30)) {
        let s = ellipsoid_from(&e);
        let pi = cloud(&pts, &s, 10);
        let j = pi.pseudo_inertia();
        for points in [four_point_masses(&pi).unwrap(), four_point_masses_in(&pi, &s).unwrap()] {
            let back = pseudo_inertia_of(&points);
            let rel = (back - j).abs().max() / j.abs().max();
            prop_assert!(rel <= 1e-9, "rel err {}", rel);
            prop_assert!(points.iter().all(|p| p.mass >= 0.0));
        }
        for p in four_point_masses_in(&pi, &s).unwrap() {
            prop_assert!(s.contains(&p.position, 1e-9), "{:?} outside", p.position);
        }
    }

    #[test]
    fn triangle_inequalities_iff_pseudo_inertia_pd_iff_covariance_psd(
        m in 0.1f64..5.0, c in prop::collection::vec(-1.0f64..1.0, 3),
        mom in prop::collection::vec(0.01f64..1.0, 3), ang in prop::collection::vec(-3.0f64..3.0, 3),
    ) {
        // principal moments drawn freely: triangle inequalities may or may not hold
        let r = rpy_rotation([ang[0], ang[1], ang[2]]);
        let ic = r * Matrix3::from_diagonal(&Vector3::new(mom[0], mom[1], mom[2])) * r.transpose();
        let pi = InertialParams::from_mass_com_inertia(m, Vector3::new(c[0], c[1], c[2]), ic);
        let mut j = mom.clone();
        j.sort_by(f64::total_cmp);
        let triangle = j[0] + j[1] >= j[2];
        let jpd = pi.pseudo_inertia().symmetric_eigenvalues().min() >= 0.0;
        let sc_psd = pi.covariance().symmetric_eigenvalues().min() >= 0.0;
        let margin = (j[0] + j[1] - j[2]).abs() / j[2];
        if margin > 1e-9 {
            prop_assert_eq!(triangle, jpd);
            prop_assert_eq!(triangle, sc_psd);
            let rep = check_consistency(&pi, 1e-12);
            prop_assert_eq!(rep.consistent, triangle);
            prop_assert_eq!(rep.verdict == Verdict::TriangleViolation, !triangle);
            if !triangle { prop_assert_eq!(rep.violated_triangle, Some(2)); }
        }
    }
}

#[test]
fn figure3_verdicts_follow_from_theorem_4() {
    // S: semi-axes √5, √2, 1 at the origin. E_π: semi-axes √0.9, √0.2, √0.2
    // (mass 1, Σ_C = diag(0.9, 0.2, 0.2)), centred at c. With Q =
    // diag(−1/5, −1/2, −1, 1): tr(JQ) = 1 − tr(P Σ_C) − cᵀPc = 0.52 − cᵀPc,
    // so π is realizable iff cᵀPc ≤ 0.52.
    let s = Ellipsoid::new(
        Vector3::zeros(),
        Vector3::new(5f64.sqrt(), 2f64.sqrt(), 1.0),
    )
    .unwrap();
    let p = Matrix3::from_diagonal(&Vector3::new(0.2, 0.5, 1.0));
    let sigma_c = Matrix3::from_diagonal(&Vector3::new(0.9, 0.2, 0.2));
    let predicted_margin = 1.0 - (p * sigma_c).trace();
    assert_relative_eq!(predicted_margin, 0.52, epsilon = 1e-15);
    let centres = [
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.5, 0.0, 0.0),
        Vector3::new(1.7, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.0, 1.2, 0.0),
        Vector3::new(0.0, 0.0, 0.7),
        Vector3::new(0.0, 0.0, 0.75),
        Vector3::new(1.0, 0.6, 0.3),
    ];
    let mut seen = (false, false);
    for c in centres {
        // Σ_C / m with m = 1: I_C = tr(Σ_C)1 − Σ_C
        let ic = Matrix3::identity() * sigma_c.trace() - sigma_c;
        let pi = InertialParams::from_mass_com_inertia(1.0, c, ic);
        let ccp = c.dot(&(p * c));
        let predicted = ccp <= predicted_margin;
        let r = check_realizable(&pi, &s, 1e-12);
        assert_eq!(r.realizable, predicted, "centre {c:?}: cᵀPc = {ccp}");
        assert_relative_eq!(r.trace_jq, predicted_margin - ccp, epsilon = 1e-12);
        // the CoM itself is inside S in every case: (22) alone would accept all
        assert!(r.com_inside);
        if predicted {
            let pts = four_point_masses_in(&pi, &s).unwrap();
            assert!(pts.iter().all(|q| s.contains(&q.position, 1e-9)));
            seen.0 = true;
        } else {
            assert!(four_point_masses_in(&pi, &s).is_err());
            seen.1 = true;
        }
    }
    assert!(seen.0 && seen.1, "both verdicts must occur");
}

#[test]
fn union_of_ellipsoids_splits_a_dumbbell() {
    let a = Ellipsoid::sphere(Vector3::new(-1.0, 0.0, 0.0), 0.2).unwrap();
    let b = Ellipsoid::sphere(Vector3::new(1.0, 0.0, 0.0), 0.2).unwrap();
    // two 1 kg balls (solid spheres r = 0.1) at ±1 m
    let ball = |x: f64| {
        InertialParams::from_mass_com_inertia(
            1.0,
            Vector3::new(x, 0.0, 0.0),
            Matrix3::identity() * (0.4 * 0.01),
        )
    };
    let dumbbell = ball(-1.0).plus(&ball(1.0));
    assert!(!check_realizable(&dumbbell, &a, 1e-9).realizable);
    assert!(!check_realizable(&dumbbell, &b, 1e-9).realizable);
    match realize_on_union(&dumbbell, &[a, b]).unwrap() {
        UnionRealization::Realizable(pieces) => {
            let sum = pieces[0].plus(&pieces[1]);
            for k in 0..10 {
                assert!((sum.0[k] - dumbbell.0[k]).abs() < 1e-6);
            }
            assert!(check_realizable(&pieces[0], &a, 1e-6).realizable);
            assert!(check_realizable(&pieces[1], &b, 1e-6).realizable);
        }
        UnionRealization::NotRealizable => panic!("the dumbbell is realizable in the union"),
    }
    let pts = point_masses_on_union(&dumbbell, &[a, b]).unwrap();
    let rel = (pseudo_inertia_of(&pts) - dumbbell.pseudo_inertia())
        .abs()
        .max()
        / dumbbell.pseudo_inertia().abs().max();
    assert!(rel < 1e-6, "{rel}");
    assert!(
        pts.iter()
            .all(|p| a.contains(&p.position, 1e-6) || b.contains(&p.position, 1e-6))
    );
    // a 2 kg ball at the origin is consistent, but no split into the two spheres exists
    let middle =
        InertialParams::from_mass_com_inertia(2.0, Vector3::zeros(), Matrix3::identity() * 0.008);
    assert!(check_consistency(&middle, 1e-12).consistent);
    assert_eq!(
        realize_on_union(&middle, &[a, b]).unwrap(),
        UnionRealization::NotRealizable
    );
}

#[test]
fn nearest_consistent_repairs_a_triangle_violation() {
    // principal moments (0.01, 0.01, 0.05): 0.01 + 0.01 < 0.05
    let bad = InertialParams::from_mass_com_inertia(
        2.0,
        Vector3::new(0.0, 0.1, 0.0),
        Matrix3::from_diagonal(&Vector3::new(0.01, 0.01, 0.05)),
    );
    let rep = check_consistency(&bad, 1e-12);
    assert_eq!(rep.verdict, Verdict::TriangleViolation);
    assert_eq!(rep.violated_triangle, Some(2));
    assert_relative_eq!(rep.triangle_margin_rel(), -0.6, epsilon = 1e-12);
    let fixed = nearest_consistent(&bad, &NearestOptions::default()).unwrap();
    let r2 = check_consistency(&fixed.params, 1e-12);
    assert_eq!(r2.verdict, Verdict::Ok, "{r2:?}");
    assert_relative_eq!(fixed.params.mass(), 2.0, epsilon = 1e-9);
    assert!(fixed.distance > 0.0);
    // a strictly consistent body is its own nearest
    let good = InertialParams::from_mass_com_inertia(
        2.0,
        Vector3::new(0.0, 0.1, 0.0),
        Matrix3::from_diagonal(&Vector3::new(0.03, 0.02, 0.04)),
    );
    let same = nearest_consistent(&good, &NearestOptions::default()).unwrap();
    assert!(same.distance < 1e-8, "{}", same.distance);
    // a body on the boundary (Cheetah ab/ad link) moves only by the solver's
    // accuracy near a degenerate covariance, and stays consistent
    let edge = InertialParams::from_spatial_v2(CHEETAH[0].1);
    let near = nearest_consistent(
        &edge,
        &NearestOptions {
            eps: 0.0,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(near.distance < 1e-3, "{}", near.distance);
    assert!(check_consistency(&near.params, 1e-9).consistent);
    // with an ellipsoid, the repaired body is realizable in it
    let s = Ellipsoid::sphere(Vector3::zeros(), 0.3).unwrap();
    let f = nearest_consistent(
        &bad,
        &NearestOptions {
            within: vec![s],
            ..Default::default()
        },
    )
    .unwrap();
    assert!(check_realizable(&f.params, &s, 1e-9).realizable);
}

#[test]
fn lmi_blocks_evaluate_to_the_numeric_matrices() {
    let pi = InertialParams::from_spatial_v2(CHEETAH[2].1);
    let s = Ellipsoid::new(
        Vector3::new(0.0, 0.0, -0.16),
        Vector3::new(0.12, 0.09, 0.32),
    )
    .unwrap();
    let mut p = Problem::new();
    let b = BodyVars::new(&mut p, "knee");
    let x = pi.0.to_vec();
    let j = b.pseudo_inertia().eval(&x);
    assert!(
        (j - nalgebra::DMatrix::from_fn(4, 4, |r, c| pi.pseudo_inertia()[(r, c)]))
            .abs()
            .max()
            < 1e-15
    );
    let sp = b.spatial_inertia().eval(&x);
    assert!(
        (sp - nalgebra::DMatrix::from_fn(6, 6, |r, c| pi.spatial()[(r, c)]))
            .abs()
            .max()
            < 1e-15
    );
    assert_relative_eq!(
        b.trace_jq(&s).eval(&x),
        check_realizable(&pi, &s, 0.0).trace_jq,
        epsilon = 1e-14
    );
    // CoM LMI (22) is PSD iff the CoM is inside
    let com_in = b.com_lmi(&s).eval(&x).symmetric_eigenvalues().min() >= -1e-15;
    assert_eq!(com_in, s.contains(&pi.com(), 0.0));
    let far = Ellipsoid::sphere(Vector3::new(1.0, 0.0, 0.0), 0.1).unwrap();
    assert!(b.com_lmi(&far).eval(&x).symmetric_eigenvalues().min() < 0.0);
    let _ = AffExpr::zero();
}

#[test]
fn ellipsoid_q_round_trip_and_bounding_shapes() {
    let e = Ellipsoid::with_rotation(
        Vector3::new(0.1, -0.2, 0.3),
        Vector3::new(0.5, 0.2, 0.1),
        rpy_rotation([0.4, 0.2, -0.7]),
    )
    .unwrap();
    let back = Ellipsoid::from_q_matrix(&(e.q_matrix() * 3.7)).unwrap();
    assert!((back.shape() - e.shape()).abs().max() < 1e-12);
    assert!((back.center - e.center).norm() < 1e-12);
    // box corners lie on the bounding ellipsoid; the MVEE of the corners is it
    let sides = Vector3::new(0.09, 0.06, 0.342);
    let bx = Ellipsoid::bounding_box(sides).unwrap();
    let mut corners = vec![];
    for sx in [-0.5, 0.5] {
        for sy in [-0.5, 0.5] {
            for sz in [-0.5, 0.5] {
                corners.push(Vector3::new(sx * sides.x, sy * sides.y, sz * sides.z));
            }
        }
    }
    for c in &corners {
        assert_relative_eq!(bx.level(c), 0.0, epsilon = 1e-12);
    }
    let mvee = Ellipsoid::minimum_volume_enclosing(&corners, 1e-10).unwrap();
    assert_relative_eq!(mvee.volume(), bx.volume(), max_relative = 1e-4);
    assert!(corners.iter().all(|c| mvee.contains(c, 1e-12)));
    // cylinder rim points inside its bounding ellipsoid
    let cy = Ellipsoid::bounding_cylinder(0.03, 0.3).unwrap();
    assert!(cy.contains(&Vector3::new(0.03, 0.0, 0.15), 1e-12));
    assert!(
        Ellipsoid::bounding_capsule(0.03, 0.3)
            .unwrap()
            .contains(&Vector3::new(0.0, 0.0, 0.18), 1e-12)
    );
    // invalid input is an error
    assert!(Ellipsoid::new(Vector3::zeros(), Vector3::new(1.0, -1.0, 1.0)).is_err());
    assert!(Ellipsoid::from_q_matrix(&Matrix4::identity()).is_err());
    assert!(Ellipsoid::minimum_volume_enclosing(&corners[..3], 1e-9).is_err());
}

#[test]
fn nearest_within_a_union_is_realizable_there_and_no_farther_than_within_one_part() {
    // 2 kg spread along x with rms 0.3 m: too wide for two 0.1 m spheres at ±0.2 m
    let wide = InertialParams::from_mass_com_inertia(
        2.0,
        Vector3::zeros(),
        Matrix3::from_diagonal(&Vector3::new(0.002, 0.18, 0.18)),
    );
    let parts = [
        Ellipsoid::sphere(Vector3::new(0.2, 0.0, 0.0), 0.1).unwrap(),
        Ellipsoid::sphere(Vector3::new(-0.2, 0.0, 0.0), 0.1).unwrap(),
    ];
    assert_eq!(
        realize_on_union(&wide, &parts).unwrap(),
        UnionRealization::NotRealizable
    );
    let opts = |within: Vec<Ellipsoid>| NearestOptions {
        within,
        length_scale: Some(0.3),
        ..Default::default()
    };
    let union = nearest_consistent(&wide, &opts(parts.to_vec())).unwrap();
    assert!(matches!(
        realize_on_union(&union.params, &parts).unwrap(),
        UnionRealization::Realizable(_)
    ));
    assert_relative_eq!(union.params.mass(), 2.0, epsilon = 1e-9);
    // the mass sits in both spheres: rms along x about 0.2 m, CoM near 0
    let sxx = union.params.covariance()[(0, 0)] / 2.0;
    assert!(
        sxx > 0.15f64.powi(2) && union.params.com().norm() < 0.05,
        "{sxx}"
    );
    // a union is a larger set than either part: its nearest point is nearer
    let one = nearest_consistent(&wide, &opts(vec![parts[0]])).unwrap();
    assert!(
        union.distance < one.distance,
        "{} {}",
        union.distance,
        one.distance
    );
    assert!(check_realizable(&one.params, &parts[0], 1e-9).realizable);
}
