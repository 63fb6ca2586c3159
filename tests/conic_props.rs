//! Property tests of the expression algebra: evaluating an expression at
//! random values equals the same arithmetic done on numbers.

use momentlmi::conic::{AffExpr, MatExpr, Problem, svec_to_mat};
use nalgebra::DMatrix;
use proptest::prelude::*;

fn coef() -> impl Strategy<Value = f64> {
    -10.0f64..10.0
}

proptest! {
    #[test]
    fn affine_ops_commute_with_evaluation(
        xs in prop::collection::vec(coef(), 4),
        a in prop::collection::vec(coef(), 4),
        b in prop::collection::vec(coef(), 4),
        ca in coef(), cb in coef(), s in coef(),
    ) {
        let mut p = Problem::new();
        let v = p.vector("v", 4);
        let ea = AffExpr::linear(&v, &a, ca).unwrap();
        let eb = AffExpr::linear(&v, &b, cb).unwrap();
        let va = ea.eval(&xs);
        let vb = eb.eval(&xs);
        let tol = 1e-9 * (1.0 + va.abs() + vb.abs()) * (1.0 + s.abs());
        prop_assert!(((ea.clone() + eb.clone()).eval(&xs) - (va + vb)).abs() < tol);
        prop_assert!(((ea.clone() - eb.clone()).eval(&xs) - (va - vb)).abs() < tol);
        prop_assert!(((ea.clone() * s).eval(&xs) - va * s).abs() < tol);
        prop_assert!(((-ea.clone()).eval(&xs) + va).abs() < tol);
        prop_assert!(((ea.clone() + s).eval(&xs) - (va + s)).abs() < tol);
        prop_assert!(((s - eb.clone()).eval(&xs) - (s - vb)).abs() < tol);
        let mut c = ea.clone();
        c.compact();
        prop_assert!((c.eval(&xs) - va).abs() < tol);
        prop_assert!((momentlmi::conic::sum([ea.clone(), eb.clone(), ea]).eval(&xs) - (2.0 * va + vb)).abs() < 2.0 * tol);
    }

    #[test]
    fn matrix_ops_commute_with_evaluation(
        xs in prop::collection::vec(coef(), 6),
        cm in prop::collection::vec(coef(), 9),
        k in prop::collection::vec(coef(), 6),
    ) {
        let mut p = Problem::new();
        let sv = p.symmetric("S", 3); // 6 variables
        let s = sv.expr();
        let c = DMatrix::from_column_slice(3, 3, &cm);
        let sval = s.eval(&xs);
        prop_assert!((sval.clone() - sval.transpose()).abs().max() == 0.0);
        let close = |a: &DMatrix<f64>, b: &DMatrix<f64>| (a - b).abs().max() <= 1e-9 * (1.0 + b.abs().max());
        prop_assert!(close(&s.left_mul(&c).unwrap().eval(&xs), &(&c * &sval)));
        prop_assert!(close(&s.right_mul(&c).unwrap().eval(&xs), &(&sval * &c)));
        prop_assert!(close(&s.congruence(&c).unwrap().eval(&xs), &(&c * &sval * c.transpose())));
        prop_assert!(close(&s.transpose().eval(&xs), &sval.transpose()));
        prop_assert!(close(&s.try_add(&MatExpr::constant(&c)).unwrap().eval(&xs), &(&sval + &c)));
        prop_assert!(close(&(&s * 2.5).eval(&xs), &(&sval * 2.5)));
        prop_assert!((s.trace().eval(&xs) - sval.trace()).abs() < 1e-9 * (1.0 + sval.abs().max()));
        prop_assert!((s.dot(&c).eval(&xs) - sval.dot(&c)).abs() < 1e-8 * (1.0 + sval.abs().max() * c.abs().max()));
        // congruence keeps symmetry
        prop_assert!(s.congruence(&c).unwrap().symmetry_defect(1e-9 * (1.0 + c.abs().max().powi(2))).is_none());
        // svec round trip (√2 scaling of off-diagonals)
        let n = 3;
        let mut z = Vec::new();
        for j in 0..n { for i in 0..=j {
            let v = k[j * (j + 1) / 2 + i];
            z.push(if i == j { v } else { v * std::f64::consts::SQRT_2 });
        } }
        let m = svec_to_mat(&z, n);
        for j in 0..n { for i in 0..=j {
            prop_assert!((m[(i, j)] - k[j * (j + 1) / 2 + i]).abs() < 1e-12);
            prop_assert_eq!(m[(i, j)], m[(j, i)]);
        } }
    }
}
