//! The root joint of one `Model`: the Cheetah 3 leg (three geared rotors,
//! one of them on the base) hung from a free-flying base, its algorithms
//! against each other — the composite-rigid-body mass matrix against the
//! inverse dynamics of unit accelerations, the regressor against the
//! inverse dynamics, the regressor's blocks and row structure against the
//! dense regressor, the potential energy against the base's height — and a
//! fixed-base model unchanged by the root's bookkeeping.

use momentlmi::dynamics::{
    Data, DynamicsError, Model, RootJoint, cheetah3, crba, energy, regressor, regressor_batch,
    regressor_blocks, regressor_row_columns, rnea,
};
use momentlmi::moments::InertialParams;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

fn floating_leg() -> Model {
    let base = InertialParams::from_mass_com_inertia(
        3.0,
        Vector3::new(0.02, -0.01, 0.03),
        Matrix3::from_diagonal(&Vector3::new(0.02, 0.03, 0.04)),
    );
    cheetah3::model().with_free_flyer("trunk", base).unwrap()
}

/// A state: base at a tilted pose with a twist, the leg bent and moving.
fn state(m: &Model) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let quat = [0.1, -0.2, 0.3, 0.9];
    let norm = quat.iter().map(|x: &f64| x * x).sum::<f64>().sqrt();
    let mut q = vec![0.1, -0.2, 0.5];
    q.extend(quat.iter().map(|x| x / norm));
    q.extend([0.2, -0.7, 1.3]);
    let v = vec![0.3, -0.1, 0.2, 0.5, -0.4, 0.7, 1.1, -2.0, 3.0];
    let a = vec![-0.6, 0.4, 1.0, 2.0, -1.5, 0.5, -3.0, 4.0, 2.5];
    assert_eq!((q.len(), v.len()), (m.nq(), m.nv()));
    (q, v, a)
}

#[test]
fn the_free_flyer_is_the_models_root_joint() {
    let m = floating_leg();
    assert!(m.is_floating() && matches!(m.root, RootJoint::FreeFlyer(_)));
    assert_eq!((m.dof(), m.nq(), m.nv()), (3, 10, 9));
    assert_eq!(m.num_bodies(), 7, "the base, 3 links, 3 rotors");
    assert_eq!(m.body_names()[0], "trunk");
    assert_eq!(m.params()[0], 3.0, "the base's mass first");
    let mut changed = m.clone();
    let mut p = m.params();
    p[0] = 4.0;
    changed.set_params(&p).unwrap();
    assert_eq!(changed.base().unwrap().inertia.mass(), 4.0);
    assert_eq!(changed.joints[0].inertia, m.joints[0].inertia);
    // a base named as a body is refused, naming it
    let e = cheetah3::model()
        .with_free_flyer(&m.joints[1].body, m.base().unwrap().inertia)
        .unwrap_err();
    assert!(e.to_string().contains(&m.joints[1].body), "{e}");
}

#[test]
fn the_composite_mass_matrix_is_the_inverse_dynamics_of_unit_accelerations() {
    let m = floating_leg();
    let mut data = Data::new(&m);
    let (q, v, _) = state(&m);
    let mm = crba(&m, &mut data, &q).unwrap().clone();
    let zero = vec![0.0; m.nv()];
    let bias = rnea(&m, &mut data, &q, &zero, &zero).unwrap().clone();
    let mut worst = 0.0f64;
    for j in 0..m.nv() {
        let mut e = zero.clone();
        e[j] = 1.0;
        let col = rnea(&m, &mut data, &q, &zero, &e).unwrap() - &bias;
        worst = worst.max((col - mm.column(j)).amax());
    }
    assert!(worst < 1e-12, "CRBA and RNEA columns differ by {worst:e}");
    assert!((&mm - mm.transpose()).amax() < 1e-15);
    // the base block is the whole robot's mass (base 3 kg and the leg)
    let total: f64 = m.params().chunks(10).map(|p| p[0]).sum();
    assert!((mm[(0, 0)] - total).abs() < 1e-12 && (mm[(2, 2)] - total).abs() < 1e-12);
    // kinetic energy is ½ vᵀ M v (energy's own use of the matrix)
    let (t, _) = energy(&m, &mut data, &q, &v).unwrap();
    let vv = DVector::from_vec(v);
    assert!((t - 0.5 * vv.dot(&(&mm * &vv))).abs() < 1e-12);
}

#[test]
fn the_regressor_times_the_parameters_is_the_inverse_dynamics() {
    let m = floating_leg();
    let mut data = Data::new(&m);
    let (q, v, a) = state(&m);
    let tau = rnea(&m, &mut data, &q, &v, &a).unwrap().clone();
    let y = regressor(&m, &mut data, &q, &v, &a).unwrap().clone();
    let mut p = m.params();
    p.resize(m.regressor_columns(), 0.0);
    let err = (&y * DVector::from_vec(p) - &tau).amax();
    assert!(err < 1e-10, "Y π − τ = {err:e}");
    // blocks, gathered densely, are the regressor; each row's non-zeros
    // are within its listed columns
    let mut dense = DMatrix::zeros(m.nv(), m.regressor_columns());
    regressor_blocks(&m, &mut data, [&q, &v, &a], |r, c0, vals| {
        for (c, x) in vals.iter().enumerate() {
            dense[(r, c0 + c)] += x;
        }
    })
    .unwrap();
    assert!((&dense - &y).amax() < 1e-12);
    let rows = regressor_row_columns(&m);
    assert_eq!(rows.len(), m.nv());
    for (r, cols) in rows.iter().enumerate() {
        for c in 0..m.regressor_columns() {
            assert!(cols.contains(&c) || y[(r, c)] == 0.0, "row {r} column {c}");
        }
    }
    // the batch form: two samples, the same rows
    let q2 = [q.clone(), q.clone()].concat();
    let v2 = [v.clone(), v.clone()].concat();
    let a2 = [a.clone(), a.clone()].concat();
    let b = regressor_batch(&m, &q2, &v2, &a2).unwrap();
    let cols = m.regressor_columns();
    let second = &b[m.nv() * cols..];
    let worst = (0..m.nv())
        .flat_map(|r| (0..cols).map(move |c| (r, c)))
        .map(|(r, c)| (second[r * cols + c] - y[(r, c)]).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-15);
}

#[test]
fn lifting_the_base_raises_the_potential_by_the_whole_weight() {
    let m = floating_leg();
    let mut data = Data::new(&m);
    let (mut q, v, _) = state(&m);
    let (_, u0) = energy(&m, &mut data, &q, &v).unwrap();
    q[2] += 1.0;
    let (_, u1) = energy(&m, &mut data, &q, &v).unwrap();
    let total: f64 = m.params().chunks(10).map(|p| p[0]).sum();
    assert!((u1 - u0 - 9.81 * total).abs() < 1e-10, "ΔU = {}", u1 - u0);
}

#[test]
fn a_fixed_base_has_no_base_state_and_its_sizes_are_the_joints() {
    let m = cheetah3::model();
    assert_eq!((m.nq(), m.nv(), m.num_bodies()), (3, 3, 6));
    let e = m.base_state(&[0.0; 3], &[0.0; 3], &[0.0; 3]).unwrap_err();
    assert!(matches!(e, DynamicsError::FixedBase { .. }), "{e}");
    // welding the floating leg back gives the fixed leg's dynamics
    let fixed = floating_leg().fixed_tree();
    let (mut d1, mut d2) = (Data::new(&m), Data::new(&fixed));
    let s = [0.2, -0.7, 1.3];
    let t1 = rnea(&m, &mut d1, &s, &[1.0, 2.0, 3.0], &[0.5, 0.1, -0.2]).unwrap();
    let t2 = rnea(&fixed, &mut d2, &s, &[1.0, 2.0, 3.0], &[0.5, 0.1, -0.2]).unwrap();
    assert_eq!(t1, t2);
}
