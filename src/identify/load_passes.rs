//! The reductions a load friction term's passes make from kept rows
//! ([`LoadRows`]): the first one, and each pass's, one row and column per
//! joint replaced.

use super::error::IdentifyError;
use super::load_rows::LoadRows;
use super::reduce::{Reduced, finite_gram, keep_joint_grams, not_finite};
use crate::dynamics::Samples;

/// The reduction of the kept `rows` (`p` regressor columns), the load
/// column's load the measured torque (as
/// [`reduce_samples`](super::reduce::reduce_samples) makes it), with the
/// rows in it for the passes; `t0` when their building began.
pub(crate) fn reduced_from(
    rows: LoadRows,
    p: usize,
    t0: std::time::Instant,
) -> Result<Reduced, IdentifyError> {
    let per_joint = keep_joint_grams(rows.joints(), p + 1);
    let grams = rows.kept_grams(per_joint).map_err(|e| not_finite(0, e))?;
    let shape = (rows.samples(), rows.joints());
    Reduced::assembled(grams, shape, t0, Some(std::sync::Arc::new(rows)))
}

/// `base` (the reduction of the same samples as `rows`, any load) with
/// every joint's load column made from `load` (N·m, n per sample).
pub(crate) fn with_load(
    rows: &LoadRows,
    base: &Reduced,
    load: &Samples,
) -> Result<Reduced, IdentifyError> {
    for (what, found) in [
        ("a pass's reduction", base.samples),
        ("a pass's load", load.len()),
    ] {
        if found != rows.samples() {
            return Err(IdentifyError::SampleCount {
                what,
                expected: rows.samples(),
                found,
            });
        }
    }
    let mut red = base.clone();
    for j in 0..rows.joints() {
        let (col, products) = rows.load_column(j, load);
        for (g, x) in products {
            for m in std::iter::once(&mut red.gram).chain(red.joint_grams.get_mut(j)) {
                m[(col, g)] = x;
                m[(g, col)] = x;
            }
        }
    }
    finite_gram(&red.gram)?;
    Ok(red)
}

#[cfg(test)]
mod tests {
    use super::{reduced_from, with_load};
    use crate::data::Dataset;
    use crate::dynamics::{FrictionTerm, Samples, random_states};
    use crate::identify::load_rows::LoadRows;
    use crate::identify::reduce::Reduced;
    use crate::identify::reduce::{reduce_samples, reduce_with_load};

    /// A pass's Gram matrices from the kept rows equal a reduction made
    /// again with the new load (the full matrix and each joint's), on the
    /// leg with offset and load terms.
    #[test]
    fn a_pass_from_kept_rows_equals_a_new_reduction() {
        use FrictionTerm::*;
        let model = crate::dynamics::cheetah3::model()
            .with_friction_terms(&[Viscous, Coulomb, Load, Offset]);
        let n = model.dof();
        let [q, qd, qdd] = random_states(&model, 80, 7).map(|v| Samples::from_flat(n, v).unwrap());
        let wave = |k: usize, a: f64| {
            (0..80 * n)
                .map(|i| a * (0.3 * (i + k) as f64).sin())
                .collect()
        };
        let tau = Samples::from_flat(n, wave(1, 5.0)).unwrap();
        let load = Samples::from_flat(n, wave(5, 3.0)).unwrap();
        let joints: Vec<String> = model.joint_names().iter().map(|j| j.to_string()).collect();
        let t = (0..80).map(|s| s as f64 * 1e-3).collect();
        let train = Dataset {
            joints,
            t,
            q,
            qd,
            qdd,
            tau,
            segments: vec![],
            base: None,
            contacts: vec![],
        };
        let base = reduce_samples(&model, &train.q, &train.qd, &train.qdd, &train.tau, 16).unwrap();
        let rows = LoadRows::new(&model, &train)
            .unwrap()
            .expect("within the budget");
        let got = with_load(&rows, &base, &load).unwrap();
        let states = [&train.q, &train.qd, &train.qdd, &train.tau];
        let want = reduce_with_load(&model, states, &load, 16).unwrap();
        let scale = (0..want.gram.nrows())
            .map(|i| want.gram[(i, i)])
            .fold(0.0, f64::max);
        // every entry of the full and the joints' Gram matrices
        let same = |x: &Reduced, y: &Reduced| crate::identify::reduce::assert_same(x, y, 1e-11);
        assert_eq!(got.joint_grams.len(), n);
        same(&got, &want);
        // the reduction made from the kept rows is the reduction's own
        let own = LoadRows::new(&model, &train).unwrap().unwrap();
        let own = reduced_from(own, model.regressor_columns(), std::time::Instant::now()).unwrap();
        assert!(own.load_rows.is_some() && own.samples == base.samples);
        // a sum of reductions keeps no part's rows
        let merged = own.clone().merge(&base).unwrap();
        assert!(merged.load_rows.is_none() && merged.samples == 2 * base.samples);
        same(&own, &base);
        // the load changed the Gram matrix: the test compares something
        let moved = (0..base.gram.nrows())
            .any(|i| (base.gram[(i, i)] - got.gram[(i, i)]).abs() > 1e-6 * scale);
        assert!(moved);
        // the rigid torques from the kept rows are the dynamics' own
        let theta: Vec<f64> = (0..model.regressor_columns())
            .map(|k| 0.1 + 0.01 * k as f64)
            .collect();
        let nb = 10 * model.num_bodies();
        let got = rows.rigid_torques(&theta, nb);
        let mut rigid = model.clone();
        rigid.set_params(&theta[..nb]).unwrap();
        let none = crate::dynamics::Friction::zeros(n);
        let want = crate::dynamics::predict::predict_torques(
            &rigid, &none, &train.q, &train.qd, &train.qdd,
        )
        .unwrap();
        let big = want.as_flat().iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (a, b) in got.as_flat().iter().zip(want.as_flat()) {
            assert!((a - b).abs() <= 1e-10 * big, "{a} vs {b}");
        }
        // a model without the load term keeps no rows
        let plain = crate::dynamics::cheetah3::model();
        assert!(LoadRows::new(&plain, &train).unwrap().is_none());
    }
}
