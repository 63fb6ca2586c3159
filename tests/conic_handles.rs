//! Handles are tied to their problem: a foreign `Var`, expression or
//! `ConstraintId` is an error in every method that takes one, and no method
//! of `Solution` panics on any handle or status.

use momentlmi::conic::{AffExpr, ConicError, MatExpr, Problem, Sense, Settings, Status};
use nalgebra::DMatrix;

fn foreign(r: Result<impl std::fmt::Debug, ConicError>) {
    match r {
        Err(ConicError::ForeignHandle { what }) => assert!(!what.is_empty()),
        other => panic!("expected a foreign-handle error, got {other:?}"),
    }
}

#[test]
fn a_foreign_variable_is_refused_by_every_constraint_and_objective() {
    let mut a = Problem::new();
    let a0 = a.scalar("a0");
    let mut b = Problem::new();
    let b0 = b.scalar("b0"); // same index as a0
    let bs = b.symmetric("B", 2);
    // constraints
    foreign(a.add_eq(b0, 1.0));
    foreign(a.add_le(b0, 1.0));
    foreign(a.add_ge(b0 + 0.0, 1.0));
    foreign(a.add_zeros(vec![AffExpr::from(b0)]));
    foreign(a.add_nonneg(vec![AffExpr::from(b0)]));
    foreign(a.add_soc(a0, vec![AffExpr::from(b0)]));
    foreign(a.add_psd(&bs));
    foreign(a.add_psd_eps(bs.expr(), 1e-3));
    foreign(a.add_eq_mat(&bs, MatExpr::identity(2)));
    // an expression that mixes the two problems
    foreign(a.add_ge(a0 + b0, 0.0));
    foreign(b.add_ge(a0 + b0, 0.0));
    assert_eq!(a.num_constraints(), 0, "nothing was added");
    // objectives: refused when compiled
    for obj in 0..5 {
        let mut p = a.clone();
        p.add_ge(a0, 1.0).unwrap();
        match obj {
            0 => p.minimize(b0),
            1 => p.maximize(b0 * 2.0),
            2 => p.add_square(1.0, b0 - 1.0),
            3 => p.add_squares(1.0, [AffExpr::from(b0)]),
            _ => p.add_frobenius(1.0, &bs),
        }
        foreign(p.solve(&Settings::default()));
    }
    // a clone shares its original's variables
    let mut c = a.clone();
    c.add_ge(a0, 1.0).unwrap();
    assert!(a.var_name(b0).is_none());
    assert_eq!(a.var_name(a0), Some("a0"));
}

#[test]
fn a_foreign_constraint_handle_is_refused() {
    let mut a = Problem::new();
    let x = a.scalar("x");
    let ca = a.add_ge(x, 1.0).unwrap();
    let mut b = Problem::new();
    let y = b.scalar("y");
    let cb = b.add_ge(y, 2.0).unwrap(); // same index as ca
    foreign(a.set_name(cb, "renamed"));
    foreign(a.constraint_name(cb));
    foreign(a.constraint_kind(cb));
    assert!(a.constraint_name(ca).unwrap().contains("≥"));
    a.minimize(x);
    let sol = a.solve(&Settings::default()).unwrap().solved().unwrap();
    foreign(sol.dual(cb));
    foreign(sol.dual_scalar(cb));
    foreign(sol.dual_vector(cb));
    foreign(sol.dual_matrix(cb));
    foreign(sol.sensitivity(cb));
    foreign(sol.raw_dual(cb));
    assert!((sol.dual_scalar(ca).unwrap() - 1.0).abs() < 1e-7);
}

#[test]
fn no_solution_method_panics_on_any_handle() {
    let mut a = Problem::new();
    let x = a.scalar("x");
    let xs = a.symmetric("X", 2);
    let c = a.add_psd(&xs).unwrap();
    a.add_eq(xs.expr().trace(), 1.0).unwrap();
    a.minimize(x + xs[(0, 1)]);
    a.add_ge(x, 0.0).unwrap();
    let sol = a.solve(&Settings::default()).unwrap();
    assert!(sol.status.is_solved());
    let mut b = Problem::new();
    let bv = b.vector("b", 7); // indices beyond and within a's
    let bs = b.symmetric("B", 3);
    let bc = b.add_ge(bv[6], 0.0).unwrap();
    for v in &bv {
        foreign(sol.value(*v));
        foreign(sol.eval(&(*v * 2.0)));
    }
    foreign(sol.values(&bv));
    foreign(sol.eval_all(&[AffExpr::from(bv[0])]));
    foreign(sol.eval_mat(&bs.expr()));
    foreign(sol.sym_value(&bs));
    foreign(sol.dual(bc));
    // the wrong kind of dual is an error naming the constraint, not a panic
    let e = sol.dual_scalar(c).unwrap_err();
    assert!(matches!(e, ConicError::DualKind { .. }), "{e}");
    assert!(sol.dual_vector(c).is_err());
    assert!(sol.dual_matrix(c).is_ok());
    // this problem's handles work
    assert!(sol.value(x).unwrap().abs() < 1e-6);
    assert!((sol.sym_value(&xs).unwrap().trace() - 1.0).abs() < 1e-7);
}

#[test]
fn values_of_an_unsolved_problem_are_the_status() {
    // infeasible: x ≥ 1 and x ≤ 0
    let mut p = Problem::new();
    let x = p.scalar("x");
    let lo = p.add_ge(x, 1.0).unwrap();
    p.add_le(x, 0.0).unwrap();
    p.minimize(x);
    let sol = p.solve(&Settings::default()).unwrap();
    assert!(sol.status.is_primal_infeasible());
    match sol.value(x) {
        Err(ConicError::NotSolved { status, .. }) => assert_eq!(status, sol.status),
        other => panic!("{other:?}"),
    }
    assert!(sol.eval(&(x + 1.0)).is_err());
    // the duals hold the infeasibility certificate
    assert!(sol.dual_scalar(lo).is_ok());
    // `solved()` turns the status into an error in one call
    let e = sol.clone().solved().unwrap_err();
    assert!(e.to_string().contains("primal_infeasible"), "{e}");
    // unbounded: min x with no constraint below
    let mut q = Problem::new();
    let y = q.scalar("y");
    q.add_le(y, 1.0).unwrap();
    q.minimize(y);
    let s = q.solve(&Settings::default()).unwrap();
    assert!(s.status.is_dual_infeasible());
    assert!(s.value(y).is_err() && s.clone().solved().is_err());
    assert_ne!(s.status, Status::Solved);
}

#[test]
fn duals_under_maximize_and_their_sensitivity() {
    // Lovász θ of the 5-cycle: max ⟨J, X⟩ s.t. tr X = 1, X_ij = 0 on edges, X ⪰ 0; θ = √5
    let n = 5;
    let mut p = Problem::new();
    let x = p.symmetric("X", n);
    let tr = p.add_eq(x.expr().trace(), 1.0).unwrap();
    for i in 0..n {
        p.add_eq(x[(i, (i + 1) % n)], 0.0).unwrap();
    }
    p.add_psd(&x).unwrap();
    p.maximize(x.expr().sum());
    let sol = p.solve(&Settings::default()).unwrap().solved().unwrap();
    let theta = 5f64.sqrt();
    assert!((sol.primal_objective - theta).abs() < 1e-6);
    assert_eq!(sol.sense(), Sense::Maximize);
    // the multiplier of the minimisation solved (of −⟨J, X⟩), and the shadow price
    assert!((sol.dual_scalar(tr).unwrap() + theta).abs() < 1e-6);
    assert!((sol.sensitivity(tr).unwrap() - theta).abs() < 1e-6);
    // a ≤ constraint: min y s.t. y ≥ 2 − … as y ≥ 2 and y ≤ 5: shadow price of the ≥ row is 1
    let mut q = Problem::new();
    let y = q.scalar("y");
    let ge = q.add_ge(y, 2.0).unwrap();
    let le = q.add_le(y, 5.0).unwrap();
    q.minimize(y);
    let s = q.solve(&Settings::default()).unwrap().solved().unwrap();
    assert!((s.sensitivity(ge).unwrap() - 1.0).abs() < 1e-6);
    assert!(s.sensitivity(le).unwrap().abs() < 1e-6);
    // maximised: the ≤ row binds, raising its right-hand side raises the optimum
    q.maximize(y);
    let s = q.solve(&Settings::default()).unwrap().solved().unwrap();
    assert!(
        (s.sensitivity(le).unwrap() - 1.0).abs() < 1e-6,
        "{:?}",
        s.sensitivity(le)
    );
}

#[test]
fn weights_and_lengths_have_their_own_errors() {
    let mut p = Problem::new();
    let v = p.vector("v", 3);
    let e = AffExpr::linear(&v, &[1.0, 2.0], 0.0).unwrap_err();
    assert!(matches!(e, ConicError::DimensionMismatch { .. }), "{e}");
    p.add_square(-1.0, v[0] - 1.0);
    match p.solve(&Settings::default()) {
        Err(ConicError::NegativeWeight { square: 0, weight }) => assert_eq!(weight, -1.0),
        other => panic!("{other:?}"),
    }
    // operators panic on a shape mismatch; the try_ methods say why
    let a = MatExpr::identity(2);
    let b = MatExpr::identity(3);
    assert!(a.try_add(&b).is_err());
    assert!(std::panic::catch_unwind(|| &a + &b).is_err());
    let c = DMatrix::<f64>::identity(3, 3);
    assert!(a.try_dot(&c).is_err());
    assert!(MatExpr::zeros(2, 3).try_trace().is_err());
}

#[test]
fn handles_newer_than_a_solution_are_stale_not_a_panic() {
    let mut p = Problem::new();
    let u = p.scalar("u");
    p.add_ge(u, 1.0).unwrap();
    p.minimize(u);
    let sol = p.solve(&Settings::default()).unwrap().solved().unwrap();
    let w = p.scalar("w"); // added after the solve
    let c = p.add_ge(w, 0.0).unwrap();
    for r in [sol.value(w), sol.eval(&(u + w))] {
        match r {
            Err(ConicError::Stale { what }) => assert!(what.contains("variable")),
            other => panic!("{other:?}"),
        }
    }
    assert!(matches!(sol.dual(c), Err(ConicError::Stale { .. })));
    assert!((sol.value(u).unwrap() - 1.0).abs() < 1e-7);
}

#[test]
fn a_clone_is_its_own_problem_for_handles_made_after_it() {
    let mut g = Problem::new();
    let a = g.scalar("a");
    let ca = g.add_ge(a, 1.0).unwrap();
    let mut h = g.clone();
    let wg = g.scalar("w_g");
    let wh = h.scalar("w_h"); // the same index as w_g, in the clone
    // handles from before the clone work in both …
    h.add_le(a, 5.0).unwrap();
    assert!(h.constraint_name(ca).is_ok());
    // … and may be mixed with the clone's own …
    h.add_ge(a + wh, 2.0).unwrap();
    // … but what either made after the clone belongs to it alone
    foreign(g.add_eq(wh, 3.0));
    foreign(h.add_eq(wg, 3.0));
    h.minimize(a + wh);
    let sol = h.solve(&Settings::default()).unwrap().solved().unwrap();
    assert!(sol.value(a).is_ok() && sol.value(wh).is_ok());
    foreign(sol.value(wg));
    assert!(sol.dual_scalar(ca).is_ok());
}

#[test]
fn a_lyapunov_lmi_reads_like_its_math() {
    // find P ⪰ I with AᵀP + PA ⪯ −I for a stable A
    let a = DMatrix::from_row_slice(2, 2, &[-1.0, 2.0, 0.0, -3.0]);
    let mut p = Problem::new();
    let pv = p.symmetric("P", 2);
    let pm = pv.expr();
    p.add_psd_eps(&pv, 1.0).unwrap();
    p.add_psd_le(&a.transpose() * &pm + &pm * &a, -MatExpr::identity(2))
        .unwrap();
    p.minimize(pv.trace());
    let sol = p.solve(&Settings::default()).unwrap().solved().unwrap();
    let pn = sol.sym_value(&pv).unwrap();
    let lyap = a.transpose() * &pn + &pn * &a;
    assert!(pn.symmetric_eigenvalues().min() >= 1.0 - 1e-6);
    assert!(lyap.symmetric_eigenvalues().max() <= -1.0 + 1e-6);
    assert_eq!(pv.diagonal().len(), 2);
    assert!((sol.eval(&pv.trace()).unwrap() - pn.trace()).abs() < 1e-9);
}
