//! The exponential cone and the atoms on it (`log`, relative entropy,
//! `log det`) on problems with closed-form answers, their duals checked
//! with the optimality conditions, and the minimum-volume enclosing
//! ellipsoid through `conic` against `moments`' MVEE (Todd–Yildirim with away steps).

#[path = "support/rng.rs"]
mod rng;

use momentlmi::conic::{
    AffExpr, ConeKind, ConicError, MatExpr, Problem, Solution, check_optimality,
};
use momentlmi::moments::Ellipsoid;
use momentlmi::sdpa::SdpaProblem;
use nalgebra::{DMatrix, Matrix3, Vector3};
use rng::Rng;

#[path = "support/tight.rs"]
mod tight;
use tight::tight;

/// Solves, asserts an optimum whose KKT residuals are all below `kkt`.
fn solve_checked(p: &Problem, kkt: f64) -> Solution {
    let sol = p.solve(&tight()).unwrap().solved().unwrap();
    let r = check_optimality(p, &sol);
    assert!(r.max() < kkt, "KKT residuals {r:?}");
    sol
}

#[test]
fn exp_cone_boundary_point_is_e() {
    // min z s.t. (1, 1, z) ∈ K_exp: z = e
    let mut p = Problem::new();
    let z = p.scalar("z");
    let c = p.add_exp_cone(1.0, 1.0, z).unwrap();
    assert_eq!(p.constraint_kind(c).unwrap(), ConeKind::Exponential);
    p.minimize(z);
    let sol = solve_checked(&p, 1e-7);
    assert!((sol.value(z).unwrap() - std::f64::consts::E).abs() < 1e-7);
    // its dual (u, v, w) is in K_exp*: w = 1 (∂z), and on the boundary
    // −u e^{v/u} = e w
    let d = sol.dual_vector(c).unwrap();
    assert!((d[2] - 1.0).abs() < 1e-7, "{d:?}");
    assert!(d[0] < 0.0);
    let lhs = -d[0] * (d[1] / d[0]).exp();
    assert!((lhs - std::f64::consts::E * d[2]).abs() < 1e-6, "{d:?}");
}

#[test]
fn log_of_a_bounded_variable() {
    // max t s.t. t ≤ log x, x ≤ 2: ln 2
    let mut p = Problem::new();
    let (x, t) = (p.scalar("x"), p.scalar("t"));
    p.add_log_ge(x, t).unwrap();
    let bound = p.add_le(x, 2.0).unwrap();
    p.maximize(t);
    let sol = solve_checked(&p, 1e-7);
    assert!((sol.value(t).unwrap() - 2f64.ln()).abs() < 1e-7);
    // d(ln x)/dx at 2 is the bound's shadow price
    assert!((sol.sensitivity(bound).unwrap() - 0.5).abs() < 1e-5);
}

#[test]
fn maximum_entropy_distribution() {
    // max Σ −xᵢ ln xᵢ s.t. Σ x = 1 (n = 5): uniform, ln 5; with x₀ ≤ 0.1 the
    // rest share 0.9 equally
    for cap in [None, Some(0.1)] {
        let n = 5;
        let mut p = Problem::new();
        let x = p.vector("x", n);
        let h = p.vector("h", n);
        for i in 0..n {
            // x ln(x / 1) ≤ −h
            p.add_rel_entropy_le(x[i], 1.0, -AffExpr::from(h[i]))
                .unwrap();
        }
        p.add_eq(x.iter().copied().sum::<AffExpr>(), 1.0).unwrap();
        if let Some(c) = cap {
            p.add_le(x[0], c).unwrap();
        }
        p.maximize(h.iter().copied().sum::<AffExpr>());
        let sol = solve_checked(&p, 1e-7);
        let want = match cap {
            None => (n as f64).ln(),
            Some(c) => {
                let r = (1.0 - c) / (n - 1) as f64;
                -(c * c.ln()) - (n - 1) as f64 * r * r.ln()
            }
        };
        assert!(
            (sol.primal_objective - want).abs() < 1e-7,
            "{cap:?}: {} vs {want}",
            sol.primal_objective
        );
    }
}

#[test]
fn logdet_with_fixed_diagonal_is_the_diagonal() {
    // max log det X s.t. diag X = d: X = diag(d), Σ ln dᵢ; with X₀₁ = a as
    // well, ln(d₀d₁ − a²) + Σᵢ≥₂ ln dᵢ
    let d = [0.5, 2.0, 3.0, 0.25];
    for a in [None, Some(0.6)] {
        let mut p = Problem::new();
        let x = p.symmetric("X", 4);
        let t = p.scalar("t");
        p.add_logdet_ge(&x, t).unwrap();
        for (i, di) in d.iter().enumerate() {
            p.add_eq(x[(i, i)], *di).unwrap();
        }
        if let Some(a) = a {
            p.add_eq(x[(0, 1)], a).unwrap();
        }
        p.maximize(t);
        let sol = solve_checked(&p, 1e-7);
        let want = match a {
            None => d.iter().map(|v| v.ln()).sum::<f64>(),
            Some(a) => (d[0] * d[1] - a * a).ln() + d[2].ln() + d[3].ln(),
        };
        assert!((sol.value(t).unwrap() - want).abs() < 1e-7, "{a:?}");
        if a.is_none() {
            let xv = x.expr().eval(sol.x());
            let off = DMatrix::from_fn(4, 4, |i, j| if i == j { 0.0 } else { xv[(i, j)] });
            assert!(off.amax() < 1e-6, "{xv}");
        }
    }
}

#[test]
fn logdet_minus_trace_is_the_inverse() {
    // max log det X − ⟨S, X⟩ over X ≻ 0: X = S⁻¹, optimum −ln det S − n
    let mut rng = Rng(19);
    for n in [1usize, 2, 4, 6] {
        let s = rng.spd(n);
        let mut p = Problem::new();
        let x = p.symmetric("X", n);
        let t = p.scalar("t");
        let ld = p.add_logdet_ge(&x, t).unwrap();
        assert_eq!(ld.logs.len(), n);
        assert_eq!(
            p.constraint_kind(ld.psd).unwrap(),
            ConeKind::Psd { n: 2 * n }
        );
        p.maximize(AffExpr::from(t) - x.expr().dot(&s));
        let sol = solve_checked(&p, 1e-7);
        let want = -s.determinant().ln() - n as f64;
        assert!(
            (sol.primal_objective - want).abs() < 1e-7,
            "n = {n}: {} vs {want}",
            sol.primal_objective
        );
        let inv = s.clone().try_inverse().unwrap();
        let xv = x.expr().eval(sol.x());
        // the maximiser is known to about √(gap)
        assert!((xv - &inv).amax() < 1e-4 * inv.amax(), "n = {n}");
    }
}

#[test]
fn logdet_of_an_affine_matrix_expression() {
    // X = A + y B with y free: max log det(A + y B) for A = I₂, B = diag(1, −1):
    // (1 + y)(1 − y) is largest at y = 0, value 0; shifted by A = diag(2, 1)
    // the optimum of (2 + y)(1 − y) is y = −½, value ln 2.25
    let mut p = Problem::new();
    let y = p.scalar("y");
    let t = p.scalar("t");
    let a = MatExpr::constant(&DMatrix::from_diagonal(&nalgebra::dvector![2.0, 1.0]));
    let x = a + MatExpr::diag(vec![AffExpr::from(y), -AffExpr::from(y)]);
    p.add_logdet_ge(x, t).unwrap();
    p.maximize(t);
    let sol = solve_checked(&p, 1e-7);
    // the optimum is flat in y: its error is about √(gap)
    assert!((sol.value(y).unwrap() + 0.5).abs() < 1e-4);
    assert!((sol.value(t).unwrap() - 2.25f64.ln()).abs() < 1e-7);
}

#[test]
fn logdet_refuses_non_square() {
    let mut p = Problem::new();
    let t = p.scalar("t");
    let m = MatExpr::zeros(2, 3);
    assert!(matches!(
        p.add_logdet_ge(m, t),
        Err(ConicError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        p.add_logdet_ge(MatExpr::zeros(0, 0), t),
        Err(ConicError::DimensionMismatch { .. })
    ));
}

#[test]
fn infeasible_log_is_reported() {
    // t ≤ log x with x ≤ −1: no x > 0
    let mut p = Problem::new();
    let (x, t) = (p.scalar("x"), p.scalar("t"));
    p.add_log_ge(x, t).unwrap();
    p.add_le(x, -1.0).unwrap();
    p.maximize(t);
    let sol = p.solve(&tight()).unwrap();
    assert!(sol.status.is_primal_infeasible(), "{:?}", sol.status);
}

#[test]
fn exponential_cones_have_no_sdpa_form() {
    let mut p = Problem::new();
    let z = p.scalar("z");
    p.add_exp_cone(1.0, 1.0, z).unwrap();
    p.minimize(z);
    let e = SdpaProblem::from_problem(&p).unwrap_err().to_string();
    assert!(e.contains("exponential cone"), "{e}");
}

/// The MVEE `{x : ‖A x + b‖ ≤ 1}` (A ≻ 0): max log det A s.t. every point
/// inside, returned as an [`Ellipsoid`].
fn mvee_by_conic(points: &[Vector3<f64>]) -> Ellipsoid {
    let mut p = Problem::new();
    let a = p.symmetric("A", 3);
    let b = p.vector("b", 3);
    let t = p.scalar("t");
    p.add_logdet_ge(&a, t).unwrap();
    let ae = a.expr();
    for q in points {
        let rows: Vec<AffExpr> = (0..3)
            .map(|i| (0..3).map(|j| ae[(i, j)].clone() * q[j]).sum::<AffExpr>() + b[i])
            .collect();
        p.add_soc(1.0, rows).unwrap();
    }
    p.maximize(t);
    let sol = solve_checked(&p, 1e-6);
    let am = Matrix3::from_fn(|i, j| ae[(i, j)].eval(sol.x()));
    let bv = Vector3::from_fn(|i, _| sol.value(b[i]).unwrap());
    let center = -am.try_inverse().unwrap() * bv;
    let eig = am.symmetric_eigen();
    let mut r = eig.eigenvectors;
    if r.determinant() < 0.0 {
        r.set_column(2, &(-r.column(2)));
    }
    Ellipsoid::with_rotation(center, eig.eigenvalues.map(|l| 1.0 / l), r).unwrap()
}

#[test]
fn mvee_through_conic_matches_todd_yildirim() {
    let mut rng = Rng(2024);
    for case in 0..5 {
        let n = 12 + 7 * case;
        // an anisotropic, shifted, rotated cloud
        let scale = Vector3::new(0.3, 0.1, 0.05 + 0.02 * case as f64);
        let rot = momentlmi::moments::rpy_rotation([rng.f(), rng.f(), rng.f()]);
        let shift = Vector3::new(rng.f(), rng.f(), rng.f());
        let pts: Vec<Vector3<f64>> = (0..n)
            .map(|_| shift + rot * Vector3::new(rng.f(), rng.f(), rng.f()).component_mul(&scale))
            .collect();
        let conic = mvee_by_conic(&pts);
        let ty = Ellipsoid::minimum_volume_enclosing(&pts, 1e-10).unwrap();
        // both enclose every point
        for q in &pts {
            assert!(conic.contains(q, 1e-6), "case {case}");
            assert!(ty.contains(q, 1e-9), "case {case}");
        }
        // the MVEE is unique: the two algorithms reach the same ellipsoid
        // (the first-order one to its 1e-10 tolerance, the conic one to
        // the interior-point solver's)
        let (vc, vk) = (conic.volume(), ty.volume());
        assert!(
            (vk / vc - 1.0).abs() < 1e-6,
            "case {case}: volumes {vc} vs {vk}"
        );
        let size = scale.max();
        let dc = (conic.center - ty.center).norm() / size;
        assert!(dc < 1e-5, "case {case}: centres differ by {dc:e}");
        let (pc, pk) = (conic.shape_inverse(), ty.shape_inverse());
        let ds = (pc - pk).norm() / pk.norm();
        assert!(
            ds < 1e-5,
            "case {case}: shapes differ by {ds:e}\n{pc}\n{pk}"
        );
    }
}
