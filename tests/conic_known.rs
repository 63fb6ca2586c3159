//! The conic layer on problems with known answers, optimality checks of the
//! duals, infeasible/unbounded statuses and input errors.

use approx::assert_relative_eq;
use momentlmi::conic::{
    AffExpr, ConicError, Dual, LeastSquaresForm, MatExpr, Problem, Settings, Status,
    check_optimality,
};
use nalgebra::DMatrix;

#[path = "support/rng.rs"]
mod rng;
use rng::Rng;

#[path = "support/tight.rs"]
mod tight;
use tight::tight;

#[test]
fn lambda_max_equals_largest_eigenvalue() {
    let mut rng = Rng(1);
    for n in [1usize, 2, 4, 7] {
        let a = rng.sym(n);
        let mut p = Problem::new();
        let t = p.scalar("t");
        let m = MatExpr::scaled_identity(n, t)
            .try_sub(&MatExpr::constant(&a))
            .unwrap();
        let c = p.add_psd(&m).unwrap();
        p.minimize(t);
        let sol = p.solve(&tight()).unwrap();
        assert_eq!(sol.status, Status::Solved);
        let lmax = a.symmetric_eigenvalues().max();
        assert_relative_eq!(sol.value(t).unwrap(), lmax, epsilon = 1e-7);
        // the dual is the projector on the top eigenvector: PSD, trace 1
        let Ok(Dual::Matrix(z)) = sol.dual(c) else {
            panic!("PSD dual must be a matrix")
        };
        assert_relative_eq!(z.trace(), 1.0, epsilon = 1e-6);
        assert!(z.symmetric_eigenvalues().min() > -1e-7);
        assert!(check_optimality(&p, &sol).max() < 1e-6);
    }
}

fn lovasz_theta(n: usize, edges: &[(usize, usize)]) -> f64 {
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let xe = x.expr();
    p.add_eq(xe.trace(), 1.0).unwrap();
    for &(i, j) in edges {
        p.add_eq(xe.get(i, j).unwrap().clone(), 0.0).unwrap();
    }
    p.add_psd(&xe).unwrap();
    p.maximize(xe.dot(&DMatrix::from_element(n, n, 1.0)));
    let sol = p.solve(&tight()).unwrap();
    assert_eq!(sol.status, Status::Solved);
    assert!(
        check_optimality(&p, &sol).max() < 1e-6,
        "{:?}",
        check_optimality(&p, &sol)
    );
    sol.primal_objective
}

#[test]
fn lovasz_theta_of_c5_and_petersen() {
    let c5: Vec<_> = (0..5).map(|i| (i, (i + 1) % 5)).collect();
    assert_relative_eq!(lovasz_theta(5, &c5), 5f64.sqrt(), epsilon = 1e-7);
    let mut pet: Vec<_> = (0..5).map(|i| (i, (i + 1) % 5)).collect();
    pet.extend((0..5).map(|i| (5 + i, 5 + (i + 2) % 5)));
    pet.extend((0..5).map(|i| (i, i + 5)));
    assert_relative_eq!(lovasz_theta(10, &pet), 4.0, epsilon = 1e-7);
}

#[test]
fn maxcut_relaxation_of_c5() {
    // max ¼⟨L, X⟩ s.t. diag X = 1, X ⪰ 0
    let n = 5;
    let mut l = DMatrix::zeros(n, n);
    for i in 0..n {
        let j = (i + 1) % n;
        l[(i, i)] += 1.0;
        l[(j, j)] += 1.0;
        l[(i, j)] -= 1.0;
        l[(j, i)] -= 1.0;
    }
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let xe = x.expr();
    p.add_zeros((0..n).map(|i| xe.get(i, i).unwrap().clone() - 1.0))
        .unwrap();
    p.add_psd(&xe).unwrap();
    p.maximize(xe.dot(&l) * 0.25);
    let sol = p.solve(&tight()).unwrap();
    assert_eq!(sol.status, Status::Solved);
    assert_relative_eq!(
        sol.primal_objective,
        (25.0 + 5.0 * 5f64.sqrt()) / 8.0,
        epsilon = 1e-7
    );
    assert_relative_eq!(sol.dual_objective, sol.primal_objective, epsilon = 1e-7);
}

#[test]
fn small_lp_with_hand_computed_optimum_and_duals() {
    // max 3x + 2y s.t. x + y ≤ 4, x + 3y ≤ 6, x, y ≥ 0 → (4, 0), value 12.
    // Duals: the first constraint binds with multiplier 3; x + 3y ≤ 6 is
    // slack (multiplier 0); y ≥ 0 binds with multiplier 1 (= 3 − 2).
    let mut p = Problem::new();
    let x = p.scalar("x");
    let y = p.scalar("y");
    let c1 = p.add_le(x + y, 4.0).unwrap();
    let c2 = p.add_le(x + 3.0 * y, 6.0).unwrap();
    let c3 = p.add_ge(y, 0.0).unwrap();
    p.add_ge(x, 0.0).unwrap();
    p.maximize(3.0 * x + 2.0 * y);
    let sol = p.solve(&tight()).unwrap();
    assert_eq!(sol.status, Status::Solved);
    assert_relative_eq!(sol.primal_objective, 12.0, epsilon = 1e-7);
    assert_relative_eq!(sol.value(x).unwrap(), 4.0, epsilon = 1e-7);
    assert_relative_eq!(sol.value(y).unwrap(), 0.0, epsilon = 1e-7);
    let d = |c| match sol.dual(c) {
        Ok(Dual::Vector(v)) => v[0],
        _ => panic!(),
    };
    assert_relative_eq!(d(c1), 3.0, epsilon = 1e-6);
    assert_relative_eq!(d(c2), 0.0, epsilon = 1e-6);
    assert_relative_eq!(d(c3), 1.0, epsilon = 1e-6);
}

#[test]
fn small_qp_in_both_least_squares_forms() {
    // min (x − 1)² + (y − 2)² s.t. x + y ≤ 1 → (0, 1), value 2, dual 2.
    for form in [
        LeastSquaresForm::Quadratic,
        LeastSquaresForm::SecondOrderCone,
    ] {
        let mut p = Problem::new();
        let x = p.scalar("x");
        let y = p.scalar("y");
        let c = p.add_le(x + y, 1.0).unwrap();
        p.add_square(1.0, x - 1.0);
        p.add_square(1.0, y - 2.0);
        let sol = p.solve(&tight().least_squares(form)).unwrap();
        assert_eq!(sol.status, Status::Solved);
        assert_relative_eq!(sol.primal_objective, 2.0, epsilon = 1e-7);
        assert_relative_eq!(sol.value(x).unwrap(), 0.0, epsilon = 1e-6);
        assert_relative_eq!(sol.value(y).unwrap(), 1.0, epsilon = 1e-6);
        if form == LeastSquaresForm::Quadratic {
            let Ok(Dual::Vector(z)) = sol.dual(c) else {
                panic!()
            };
            assert_relative_eq!(z[0], 2.0, epsilon = 1e-6);
            assert!(check_optimality(&p, &sol).max() < 1e-6);
        }
    }
}

#[test]
fn soc_constraint_projection() {
    // min t s.t. ‖(x − 3, y − 4)‖ ≤ t with x = y = 0 fixed → t = 5.
    let mut p = Problem::new();
    let t = p.scalar("t");
    let x = p.scalar("x");
    let y = p.scalar("y");
    p.add_eq(x, 0.0).unwrap();
    p.add_eq(y, 0.0).unwrap();
    p.add_soc(t, vec![x - 3.0, y - 4.0]).unwrap();
    p.minimize(t);
    let sol = p.solve(&tight()).unwrap();
    assert_relative_eq!(sol.value(t).unwrap(), 5.0, epsilon = 1e-7);
    assert!(check_optimality(&p, &sol).max() < 1e-6);
}

/// A random SDP in standard form with strictly feasible primal and dual:
/// min ⟨C, X⟩ s.t. ⟨Aᵢ, X⟩ = bᵢ, X ⪰ 0, with b from an X₀ ≻ 0 and
/// C = Σ yᵢ Aᵢ + S₀, S₀ ≻ 0.
#[test]
fn random_sdps_close_the_gap_and_pass_the_optimality_check() {
    let mut rng = Rng(77);
    for trial in 0..8 {
        let n = 3 + trial % 4;
        let m = 2 + trial % 3;
        let x0 = rng.spd(n);
        let a: Vec<DMatrix<f64>> = (0..m).map(|_| rng.sym(n)).collect();
        let y0: Vec<f64> = (0..m).map(|_| rng.f()).collect();
        let mut c = rng.spd(n);
        for i in 0..m {
            c += &a[i] * y0[i];
        }
        let mut p = Problem::new();
        let x = p.symmetric("X", n);
        let xe = x.expr();
        for ai in &a {
            p.add_eq(xe.dot(ai), ai.dot(&x0)).unwrap();
        }
        p.add_psd(&xe).unwrap();
        p.minimize(xe.dot(&c));
        let sol = p.solve(&tight()).unwrap();
        assert_eq!(sol.status, Status::Solved, "trial {trial}");
        let scale = 1.0 + sol.primal_objective.abs();
        assert!(
            (sol.primal_objective - sol.dual_objective).abs() / scale < 1e-7,
            "trial {trial}"
        );
        let k = check_optimality(&p, &sol);
        assert!(k.max() < 1e-6, "trial {trial}: {k:?}");
    }
}

#[test]
fn infeasible_and_unbounded_statuses() {
    let mut p = Problem::new();
    let x = p.scalar("x");
    p.add_ge(x, 1.0).unwrap();
    p.add_le(x, 0.0).unwrap();
    p.minimize(x);
    assert!(
        p.solve(&Settings::default())
            .unwrap()
            .status
            .is_primal_infeasible()
    );

    let mut p = Problem::new();
    let x = p.scalar("x");
    p.add_le(x, 0.0).unwrap();
    p.minimize(x);
    assert!(
        p.solve(&Settings::default())
            .unwrap()
            .status
            .is_dual_infeasible()
    );

    // X ⪰ 0 with X₀₀ = −1
    let mut p = Problem::new();
    let x = p.symmetric("X", 3);
    let xe = x.expr();
    p.add_psd(&xe).unwrap();
    p.add_eq(xe.get(0, 0).unwrap().clone(), -1.0).unwrap();
    p.minimize(xe.trace());
    assert!(
        p.solve(&Settings::default())
            .unwrap()
            .status
            .is_primal_infeasible()
    );
}

#[test]
fn strict_lmi_margin_is_respected() {
    // min λ s.t. X ⪰ 0.1 I with tr X = λ → λ = 0.3 for 3×3
    let mut p = Problem::new();
    let x = p.symmetric("X", 3);
    let xe = x.expr();
    p.add_psd_eps(&xe, 0.1).unwrap();
    p.minimize(xe.trace());
    let sol = p.solve(&tight()).unwrap();
    assert_relative_eq!(sol.primal_objective, 0.3, epsilon = 1e-7);
    let v = sol.sym_value(&x).unwrap();
    assert!(v.symmetric_eigenvalues().min() > 0.1 - 1e-7);
}

#[test]
fn errors_not_panics() {
    let mut p = Problem::new();
    let x = p.scalar("x");
    // dimension mismatch
    let a = MatExpr::zeros(2, 2);
    let b = MatExpr::zeros(3, 3);
    assert!(matches!(
        a.try_add(&b),
        Err(ConicError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        p.add_psd(&MatExpr::zeros(2, 3)),
        Err(ConicError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        a.get(5, 0),
        Err(ConicError::IndexOutOfRange { .. })
    ));
    // non-finite
    assert!(matches!(
        p.add_ge(x * f64::NAN, 0.0),
        Err(ConicError::NonFinite { .. })
    ));
    assert!(matches!(
        p.add_le(x, f64::INFINITY),
        Err(ConicError::NonFinite { .. })
    ));
    // two finite coefficients of one variable whose sum is not
    assert!(matches!(
        p.add_ge(x * 1.7e308 + x * 1.7e308, 0.0),
        Err(ConicError::NonFinite { .. })
    ));
    // not symmetric
    let m = MatExpr::from_fn(2, 2, |i, j| {
        if i == 0 && j == 1 {
            AffExpr::from(x)
        } else {
            AffExpr::zero()
        }
    });
    let e = p.add_psd(&m).unwrap_err();
    assert!(
        matches!(e, ConicError::NotSymmetric { row: 0, col: 1, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("not symmetric"));
    // empty
    assert!(matches!(
        Problem::new().solve(&Settings::default()),
        Err(ConicError::EmptyProblem)
    ));
    // a variable from another problem (beyond this one's variables, or not)
    let mut big = Problem::new();
    let v = big.vector("v", 5);
    assert!(matches!(
        p.add_ge(v[4], 0.0),
        Err(ConicError::ForeignHandle { .. })
    ));
    assert!(matches!(
        p.add_ge(v[0], 0.0),
        Err(ConicError::ForeignHandle { .. })
    ));
    // invalid settings
    assert!(matches!(
        p.solve(&Settings::default().tol_feas(-1.0)),
        Err(ConicError::InvalidSetting { .. })
    ));
}

#[test]
fn block_matrices_congruence_and_schur_complement() {
    // ‖v‖² ≤ t as [[t, vᵀ], [v, I]] ⪰ 0 with v = (x − 1, 2) → min t = 4 at x = 1.
    let mut p = Problem::new();
    let t = p.scalar("t");
    let x = p.scalar("x");
    let tt = MatExpr::scaled_identity(1, t);
    let v = MatExpr::column(vec![x - 1.0, AffExpr::constant(2.0)]);
    let i2 = MatExpr::constant(&DMatrix::identity(2, 2));
    let vt = v.transpose();
    let m = MatExpr::block(&[vec![Some(&tt), Some(&vt)], vec![Some(&v), Some(&i2)]]).unwrap();
    // a congruence by an invertible constant keeps feasibility unchanged
    let c = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 0.0, 0.5, 2.0, 0.0, 0.0, 1.0, 1.0]);
    p.add_psd(&m.congruence(&c).unwrap()).unwrap();
    p.minimize(t);
    let sol = p.solve(&tight()).unwrap();
    assert_relative_eq!(sol.value(t).unwrap(), 4.0, epsilon = 1e-6);
    assert_relative_eq!(sol.value(x).unwrap(), 1.0, epsilon = 1e-4);
    // None blocks take their size from their row/column
    let z = MatExpr::block(&[vec![Some(&tt), None], vec![None, Some(&i2)]]).unwrap();
    assert_eq!(z.shape(), (3, 3));
    assert!(MatExpr::block(&[vec![Some(&tt), None], vec![None, None]]).is_err());
}
