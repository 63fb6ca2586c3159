//! The entropic (log-det) divergence in `moments` and the entropic prior in
//! `identify`: the divergence's invariances and gradient, its conic form
//! against the closed form, and identifications of the leg with it.

#[path = "support/rng.rs"]
mod rng;
#[path = "support/tight.rs"]
mod tight;

use momentlmi::conic::Problem;
use momentlmi::data::Dataset;
use momentlmi::dynamics::cheetah3;
use momentlmi::effects::simulate;
use momentlmi::identify::{IdentifyError, IdentifyOptions, Level, Regularizer, identify};
use momentlmi::moments::{
    InertialParams, MomentsError, add_entropic_divergence, entropic_divergence, entropic_gradient,
    lmi::BodyVars, rpy_rotation,
};
use momentlmi::sim::{Effects, SimConfig};
use nalgebra::{Matrix3, Vector3};
use rng::Rng;
use tight::tight;

/// A random strictly consistent body: mass 0.5–2.5 kg, CoM within 0.2 m,
/// principal moments of an ellipsoid of density, rotated.
fn body(rng: &mut Rng) -> InertialParams {
    let m = 1.5 + rng.f();
    let semi = Vector3::new(
        0.1 + 0.05 * rng.f(),
        0.06 + 0.03 * rng.f(),
        0.03 + 0.01 * rng.f(),
    );
    // a solid ellipsoid: Σ_C = m/5 diag(a²)
    let sigma = Matrix3::from_diagonal(&semi.component_mul(&semi)) * (m / 5.0);
    let r = rpy_rotation([rng.f(), rng.f(), rng.f()]);
    let sigma = r * sigma * r.transpose();
    let ic = Matrix3::identity() * sigma.trace() - sigma;
    let com = Vector3::new(0.2 * rng.f(), 0.2 * rng.f(), 0.2 * rng.f());
    InertialParams::from_mass_com_inertia(m, com, ic)
}

#[test]
fn divergence_is_zero_at_the_prior_and_positive_elsewhere() {
    let mut rng = Rng(5);
    for _ in 0..20 {
        let (a, b) = (body(&mut rng), body(&mut rng));
        assert!(entropic_divergence(&a, &a).unwrap().abs() < 1e-12);
        assert!(entropic_divergence(&a, &b).unwrap() > 1e-3);
    }
}

#[test]
fn divergence_is_invariant_under_frames_and_units() {
    let mut rng = Rng(6);
    for _ in 0..20 {
        let (a, b) = (body(&mut rng), body(&mut rng));
        let d = entropic_divergence(&a, &b).unwrap();
        // the same two bodies seen from another frame
        let r = rpy_rotation([rng.f(), rng.f(), rng.f()]);
        let p = Vector3::new(rng.f(), rng.f(), rng.f());
        let (at, bt) = (a.transformed(&r, &p), b.transformed(&r, &p));
        let dt = entropic_divergence(&at, &bt).unwrap();
        assert!((d - dt).abs() < 1e-9 * (1.0 + d), "{d} vs {dt}");
        // in grams and millimetres: J scales by 1e3 (mass) and 1e6 (m²)
        let scale = |x: &InertialParams| {
            let s = x.0;
            InertialParams([
                s[0] * 1e3,
                s[1] * 1e6,
                s[2] * 1e6,
                s[3] * 1e6,
                s[4] * 1e9,
                s[5] * 1e9,
                s[6] * 1e9,
                s[7] * 1e9,
                s[8] * 1e9,
                s[9] * 1e9,
            ])
        };
        let du = entropic_divergence(&scale(&a), &scale(&b)).unwrap();
        assert!((d - du).abs() < 1e-8 * (1.0 + d), "{d} vs {du}");
        // while the Euclidean distance changes with the units
        let e = |x: &InertialParams, y: &InertialParams| {
            x.0.iter()
                .zip(&y.0)
                .map(|(u, v)| (u - v).powi(2))
                .sum::<f64>()
        };
        assert!(e(&scale(&a), &scale(&b)) > 1e3 * e(&a, &b));
    }
}

#[test]
fn gradient_matches_central_differences() {
    let mut rng = Rng(7);
    for _ in 0..10 {
        let (a, b) = (body(&mut rng), body(&mut rng));
        let g = entropic_gradient(&a, &b).unwrap();
        for k in 0..10 {
            let h = 1e-6 * a.0[k].abs().max(1e-3);
            let (mut up, mut dn) = (a, a);
            up.0[k] += h;
            dn.0[k] -= h;
            let fd = (entropic_divergence(&up, &b).unwrap()
                - entropic_divergence(&dn, &b).unwrap())
                / (2.0 * h);
            assert!(
                (fd - g[k]).abs() < 1e-5 * (1.0 + g[k].abs()),
                "entry {k}: {} vs {fd}",
                g[k]
            );
        }
    }
}

#[test]
fn a_singular_prior_is_refused() {
    // a point mass: J has rank 1
    let point =
        InertialParams::from_mass_com_inertia(1.0, Vector3::new(0.1, 0.0, 0.0), Matrix3::zeros());
    let mut rng = Rng(8);
    let a = body(&mut rng);
    assert!(matches!(
        entropic_divergence(&a, &point),
        Err(MomentsError::NotPositiveSemidefinite { .. })
    ));
    let mut p = Problem::new();
    let v = BodyVars::new(&mut p, "b");
    assert!(add_entropic_divergence(&mut p, &v, &point).is_err());
}

/// min_π d(J(π) ‖ Ĵ) + ½‖π − π₀‖²_W through `conic` against the divergence
/// evaluated at the answer: the conic bound is tight, and the optimum's
/// gradient condition `∇d = −W (π − π₀)` holds.
#[test]
fn conic_divergence_is_tight_at_its_minimum() {
    let mut rng = Rng(9);
    for _ in 0..5 {
        // a target near the prior keeps the optimum well inside J ≻ 0
        // (near the boundary the stationarity check is ill-conditioned)
        let prior = body(&mut rng);
        let target = InertialParams(std::array::from_fn(|k| prior.0[k] * (1.0 + 0.2 * rng.f())));
        // weights that make the two terms comparable in every unit
        let w: [f64; 10] = std::array::from_fn(|k| 1.0 / prior.0[k].abs().max(1e-2).powi(2));
        let mut p = Problem::new();
        let v = BodyVars::new(&mut p, "b");
        let term = add_entropic_divergence(&mut p, &v, &prior).unwrap();
        for k in 0..10 {
            p.add_square(0.5 * w[k], v.params()[k].clone() - target.0[k]);
        }
        p.minimize(term.divergence.clone());
        let sol = p.solve(&tight()).unwrap().solved().unwrap();
        let pi = v.value(&sol).unwrap();
        let exact = entropic_divergence(&pi, &prior).unwrap();
        let bound = term.divergence.eval(sol.x());
        assert!(
            (bound - exact).abs() < 1e-7 * (1.0 + exact),
            "{bound} vs {exact}"
        );
        let g = entropic_gradient(&pi, &prior).unwrap();
        // ∇d + W(π − π₀) = 0, relative to the two terms' size (which
        // cancel); a wrong gradient or a loose bound would be off by ~1
        let pull: Vec<f64> = (0..10).map(|k| w[k] * (pi.0[k] - target.0[k])).collect();
        let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
        let res = norm(&mut (0..10).map(|k| g[k] + pull[k]));
        let size = norm(&mut g.iter().copied()) + norm(&mut pull.iter().copied());
        assert!(res < 1e-2 * size, "∇d {g:?} against {pull:?}");
    }
}

fn leg_data(seconds: f64, seed: u64) -> Dataset {
    let leg = cheetah3::description();
    let cfg = SimConfig::for_robot(
        &leg,
        seconds,
        Effects::parse("rotor_inertia,coulomb,viscous", &[]).unwrap(),
        seed,
    );
    simulate(&leg, &cfg, |_, _| {}).unwrap()
}

/// The leg with the entropic prior: every body consistent, held-out RMS
/// at the noise floor, each body's divergence reported; with the true
/// parameters as prior and a large weight, the result stays at the truth.
#[test]
fn leg_identifies_with_the_entropic_prior() {
    let leg = cheetah3::description();
    let all = leg_data(6.0, 3);
    let n = all.len();
    let (train, val) = (all.slice(0..n / 2), all.slice(n / 2..n));
    for level in [Level::None, Level::Consistent, Level::Ellipsoid] {
        let opts = IdentifyOptions::for_robot(&leg, level, 1e-2)
            .unwrap()
            .with_regularizer(Regularizer::Entropic);
        let r = identify(&leg.model, &train, Some(&val), &opts).unwrap();
        assert_eq!(r.regularizer, Regularizer::Entropic);
        // J ≻ 0 at every level: the divergence is finite only there
        assert!(r.bodies.iter().all(|b| b.consistent), "{level:?}");
        assert!(r.bodies.iter().all(|b| b.divergence_from_prior.is_some()));
        let rms = r.validation_rms.unwrap();
        // σ = 0.3 N·m default noise
        assert!(rms.iter().all(|&x| x < 0.33), "{level:?}: {rms:?}");
    }
    // the truth as prior, a weight that dominates: the answer is the truth
    let truth = leg.model.params();
    let opts = IdentifyOptions::new(Level::Consistent)
        .with_prior(1e4, truth.clone())
        .unwrap()
        .with_regularizer(Regularizer::Entropic);
    let r = identify(&leg.model, &train, None, &opts).unwrap();
    for b in &r.bodies {
        let d = b.divergence_from_prior.unwrap();
        assert!(d < 1e-4, "{}: divergence {d}", b.name);
    }
}

#[test]
fn entropic_prior_must_be_strictly_consistent() {
    let leg = cheetah3::description();
    let train = leg_data(1.0, 4);
    let mut prior = leg.model.params();
    // the knee a point mass: J singular
    let k = leg
        .model
        .body_names()
        .iter()
        .position(|n| n == "knee")
        .unwrap();
    for j in 4..10 {
        prior[10 * k + j] = 0.0;
    }
    for j in 1..4 {
        prior[10 * k + j] = 0.0;
    }
    let opts = IdentifyOptions::new(Level::Consistent)
        .with_prior(1e-2, prior)
        .unwrap()
        .with_regularizer(Regularizer::Entropic);
    let e = identify(&leg.model, &train, None, &opts).unwrap_err();
    assert!(matches!(e, IdentifyError::PriorNotConsistent { .. }), "{e}");
    assert!(e.to_string().contains("'knee'"), "{e}");
}

/// The pullback prior (the divergence's second-order term at the prior):
/// the direct least-squares solve (level none) and the SDP (the same
/// problem through the conic layer, forced by a caller's hook that adds
/// nothing) agree; near the prior (a large weight) its fit is the entropic
/// prior's up to a small share of their distance from the prior; a prior
/// body not strictly consistent is named.
#[test]
fn the_pullback_prior_is_the_divergences_quadratic_in_the_fit() {
    use momentlmi::identify::Identification;
    let leg = cheetah3::description();
    let train = leg_data(2.0, 7);
    // every body's prior 1.2 × the truth (still strictly consistent)
    let prior: Vec<f64> = leg.model.params().iter().map(|p| 1.2 * p).collect();
    let setup = |level: Level, w: f64, r: Regularizer| {
        let id = Identification::new(&leg.model).level_all(level);
        id.prior(w, prior.clone()).unwrap().regularizer(r)
    };
    let links = prior.len();
    let direct = setup(Level::None, 1e-2, Regularizer::Pullback)
        .identify(&train, None)
        .unwrap();
    let sdp = setup(Level::None, 1e-2, Regularizer::Pullback)
        .constrain(|_, _| Ok(()))
        .identify(&train, None)
        .unwrap();
    assert_eq!(sdp.regularizer, Regularizer::Pullback);
    assert!(sdp.iterations > 0, "through the SDP");
    assert_eq!(sdp.status, "solved", "{:?}", sdp.warnings);
    let gap =
        |a: &[f64], b: &[f64]| (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>()).sqrt();
    let scale = gap(&direct.theta[..links], &prior);
    let d = gap(&direct.theta[..links], &sdp.theta[..links]);
    assert!(d < 1e-4 * scale, "direct against SDP: {d} of {scale}");
    // a weight where the fit stays near the prior
    let fit = |r| {
        setup(Level::Consistent, 10.0, r)
            .identify(&train, None)
            .unwrap()
    };
    let (pb, ent) = (fit(Regularizer::Pullback), fit(Regularizer::Entropic));
    let (from_prior, apart) = (
        gap(&ent.theta[..links], &prior),
        gap(&pb.theta[..links], &ent.theta[..links]),
    );
    assert!(apart < 0.1 * from_prior, "{apart} against {from_prior}");
    // a point-mass knee in the prior
    let k = (leg.model.body_names().iter())
        .position(|n| n == "knee")
        .unwrap();
    let mut bad = prior.clone();
    (1..10).for_each(|j| bad[10 * k + j] = 0.0);
    let opts = IdentifyOptions::new(Level::Consistent)
        .with_prior(1e-2, bad)
        .unwrap()
        .with_regularizer(Regularizer::Pullback);
    let e = identify(&leg.model, &train, None, &opts).unwrap_err();
    assert!(matches!(e, IdentifyError::PriorNotConsistent { .. }), "{e}");
    assert!(e.to_string().contains("'knee'"), "{e}");
}
