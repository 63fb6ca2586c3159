//! The diagnosis given the data its nominal model was identified on
//! (`DiagnoseOptions::with_nominal_data`, `diagnose --nominal-data`): the
//! nominal's bodies are refit with the friction law on those data and the
//! fitting part together. A nominal identified on a short run is wrong on
//! a longer one wherever the short run did not determine it; with its data
//! that error is the baseline's, not an effect, while a payload those data
//! contradict is still found at its mass.

use momentlmi::data::Dataset;
use momentlmi::diagnose::{DiagnoseOptions, diagnose};
use momentlmi::dynamics::params_file::ParamsFile;
use momentlmi::dynamics::{Friction, Model, cheetah3};
use momentlmi::effects::{Library, fitted::predict_with, simulate};
use momentlmi::identify::{IdentifyOptions, Level, identify};
use momentlmi::sim::{Effects, SimConfig};

const BASE: &str = "rotor_inertia,coulomb,viscous";

fn data(effects: &str, seconds: f64, seed: u64) -> Dataset {
    let leg = cheetah3::description();
    let cfg = SimConfig::for_robot(&leg, seconds, Effects::parse(effects, &[]).unwrap(), seed);
    simulate(&leg, &cfg, |_, _| {}).unwrap()
}

/// The leg identified (ellipsoid level) on `seconds` of data of seed 101;
/// the model, its friction and the data.
fn nominal(seconds: f64) -> (Model, Friction, Dataset) {
    nominal_at(seconds, 1e-6)
}

/// [`nominal`] with the prior's weight `weight`.
fn nominal_at(seconds: f64, weight: f64) -> (Model, Friction, Dataset) {
    let d = data(BASE, seconds, 101);
    let opts =
        IdentifyOptions::for_robot(&cheetah3::description(), Level::Ellipsoid, weight).unwrap();
    let model = cheetah3::model();
    let r = identify(&model, &d, None, &opts).unwrap();
    let (m, f) = r.applied_to(&model).unwrap();
    (m, f, d)
}

/// Against the model of 20 s of other data, untouched data accept nothing
/// with its data given; a 0.5 kg payload is found within 10 % of its mass;
/// the inertial corrections are not proposed (their change is the law's
/// now), and the model the diagnosis writes predicts the held-out error it
/// reports (its bodies refit with the law).
#[test]
fn with_its_data_the_nominal_invents_nothing_and_finds_a_payload() {
    let (m, f, own) = nominal(20.0);
    let opts = DiagnoseOptions::default().with_nominal_data(own);
    let untouched = diagnose(&m, &f, &data(BASE, 15.0, 7), &opts).unwrap();
    assert!(untouched.accepted.is_empty(), "{:?}", untouched.accepted);
    let not_proposed = |name: &str| {
        (untouched.warnings.iter()).any(|w| {
            w.to_string().contains(name) && w.to_string().contains("refit with the friction law")
        })
    };
    assert!(not_proposed("link_inertia") && not_proposed("rotor_inertia"));
    let d = data(&format!("{BASE},payload"), 15.0, 7);
    let dg = diagnose(&m, &f, &d, &opts).unwrap();
    let e = (dg.ranked_effects.iter())
        .find(|e| e.accepted && e.effect == "payload")
        .unwrap_or_else(|| panic!("accepted {:?}", dg.accepted));
    let mass = e.sizes.iter().find(|s| s.name == "payload mass").unwrap();
    assert!((mass.value - 0.5).abs() <= 0.05, "{}", mass.words());
    let text = serde_json::to_string(&dg.model).unwrap();
    let file: ParamsFile = serde_json::from_str(&text).unwrap();
    let mut model = cheetah3::model();
    let friction = file.apply(&mut model, "model").unwrap();
    assert_ne!(model.params(), m.params(), "the bodies are refit");
    let held = d.slice(d.len() * 3 / 5..d.len());
    let pred = predict_with(&model, &friction, &file.effects, &held, &Library::builtin()).unwrap();
    for i in 0..3 {
        let se: f64 = (0..held.len())
            .map(|k| (held.tau[k][i] - pred[k][i]).powi(2))
            .sum();
        let rms = (se / held.len() as f64).sqrt();
        assert!(
            (rms - dg.heldout_rms_final[i]).abs() < 1e-9,
            "joint {i}: {rms} vs {}",
            dg.heldout_rms_final[i]
        );
    }
}

/// A nominal identified on 2 s with a heavy prior (weight 1: the CAD
/// values hold wherever 2 s say little) is wrong on other data there:
/// held as given, its bodies are named as an effect (measured 2026-12-07:
/// `payload`); with its 2 s given, that error is the baseline's and the
/// same data accept no inertial effect (measured: nothing at all).
#[test]
fn a_short_runs_own_estimation_error_is_not_an_effect_with_its_data() {
    let (m, f, own) = nominal_at(2.0, 1.0);
    let d = data(BASE, 15.0, 7);
    let held = diagnose(&m, &f, &d, &DiagnoseOptions::default()).unwrap();
    let inertial = |accepted: &[String]| {
        (accepted.iter())
            .any(|a| ["payload", "link_inertia", "rotor_inertia"].contains(&a.as_str()))
    };
    assert!(inertial(&held.accepted), "held: {:?}", held.accepted);
    let opts = DiagnoseOptions::default().with_nominal_data(own);
    let given = diagnose(&m, &f, &d, &opts).unwrap();
    assert!(!inertial(&given.accepted), "given: {:?}", given.accepted);
}

/// Data the nominal was identified on that do not fit it are a named
/// error: other joints, the diagnosed data themselves, no torques.
#[test]
fn nominal_data_that_do_not_fit_are_named() {
    let (m, f, own) = nominal(2.0);
    let d = data(BASE, 3.0, 7);
    let mut renamed = own.clone();
    renamed.joints[0] = "elbow".into();
    let e = diagnose(
        &m,
        &f,
        &d,
        &DiagnoseOptions::default().with_nominal_data(renamed),
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("identified on") && e.to_string().contains("elbow"),
        "{e}"
    );
    let e = diagnose(
        &m,
        &f,
        &d,
        &DiagnoseOptions::default().with_nominal_data(d.clone()),
    )
    .unwrap_err();
    assert!(
        matches!(e, momentlmi::diagnose::DiagnoseError::Overlap { rows, total } if rows == total),
        "{e}"
    );
    let mut bare = own;
    bare.tau.clear();
    let e = diagnose(
        &m,
        &f,
        &d,
        &DiagnoseOptions::default().with_nominal_data(bare),
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("identified on") && e.to_string().contains("torques"),
        "{e}"
    );
}
