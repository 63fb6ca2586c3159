//! The data the nominal model was identified on
//! ([`super::DiagnoseOptions::with_nominal_data`]). A model identified on
//! one motion is wrong on another wherever that motion did not determine
//! it (a direction its prior set, a link its joints barely moved): against
//! another run, that error looks like a payload, a gain or a change of the
//! links, and a diagnosis that holds the bodies would name it. With the
//! nominal's own data the bodies are instead refit with the friction law in
//! every fit — the baseline and every candidate — on the diagnosed fitting
//! folds *and* those data (rows no fold holds out, [`Prior`]): a change of
//! the bodies costs what it costs there, so what those data could not tell
//! is the baseline's, and only what they contradict is a finding.

use super::error::DiagnoseError;
use super::heldout::residual_of;
use super::store::Prior;
use crate::data::Dataset;
use crate::dynamics::params_file::FittedEffect;
use crate::dynamics::{Data, Friction, Model, regressor};
use crate::effects::Library;
use faer::Mat;
use rayon::prelude::*;

/// Samples per piece of the pass over the nominal's data.
const PIECE: usize = 1024;

/// The body columns' normal equations over `own` (the data `nominal` was
/// identified on, with their residual against it): `YᵀY`, `Yᵀr`, `rᵀr`
/// for the model's `10·bodies` inertial parameters. Read in pieces:
/// memory does not grow with the data.
pub fn prior(
    nominal: (&Model, &Friction, &[FittedEffect]),
    own: &Dataset,
    diagnosed: &Dataset,
    library: &Library,
) -> Result<Prior, DiagnoseError> {
    let model = nominal.0;
    let named = |e: DiagnoseError| DiagnoseError::NominalData(Box::new(e));
    super::check::check_data(model, own).map_err(named)?;
    overlap(own, diagnosed)?;
    let r = residual_of(nominal, own, library).map_err(named)?;
    let (n, m) = (model.dof(), model.params().len());
    let piece = |start: usize| -> Result<(Mat<f64>, Vec<f64>, f64), DiagnoseError> {
        let mut g = Mat::<f64>::zeros(m, m);
        let (mut xr, mut rr) = (vec![0.0; m], 0.0);
        let mut data = Data::new(model);
        for k in start..(start + PIECE).min(own.len()) {
            // the load friction column's load (no body column reads it)
            (data.load.iter_mut().zip(&own.tau[k])).for_each(|(l, t)| *l = *t);
            let y = regressor(model, &mut data, &own.q[k], &own.qd[k], &own.qdd[k])
                .map_err(|source| named(DiagnoseError::Regressor { sample: k, source }))?;
            for i in 0..n {
                let ri = r[k * n + i];
                rr += ri * ri;
                for a in 0..m {
                    let ya = y[(i, a)];
                    if ya == 0.0 {
                        continue;
                    }
                    xr[a] += ya * ri;
                    for b in a..m {
                        g[(a, b)] += ya * y[(i, b)];
                    }
                }
            }
        }
        Ok((g, xr, rr))
    };
    let zero = || Ok((Mat::<f64>::zeros(m, m), vec![0.0; m], 0.0));
    let add = |a: Result<(Mat<f64>, Vec<f64>, f64), DiagnoseError>, b| {
        let ((mut g, mut xr, rr), (pg, px, pr)) = (a?, b?);
        g += &pg;
        xr.iter_mut().zip(&px).for_each(|(a, b)| *a += b);
        Ok((g, xr, rr + pr))
    };
    // summed as they are made (one sum per thread): memory does not grow
    // with the pieces
    let (mut g, xr, rr) = (0..own.len().div_ceil(PIECE))
        .into_par_iter()
        .map(|p| piece(p * PIECE))
        .fold(zero, add)
        .reduce(zero, add)?;
    for a in 0..m {
        for b in 0..a {
            g[(a, b)] = g[(b, a)];
        }
    }
    if !(rr.is_finite() && xr.iter().all(|x| x.is_finite())) {
        return Err(DiagnoseError::NominalData(Box::new(
            DiagnoseError::NonFinite {
                what: "the nominal model's residual on its own data",
            },
        )));
    }
    Ok(Prior {
        ids: vec![],
        g,
        xr,
        rr,
    })
}

/// The diagnosed samples must not be the nominal's own: their rows would
/// join every fit, the held-out folds' included. A sample is the same when
/// its positions and torques are, bit for bit (two runs of one motion
/// differ in their noise); 1 % of the samples or more is refused.
fn overlap(own: &Dataset, diagnosed: &Dataset) -> Result<(), DiagnoseError> {
    use std::collections::HashSet;
    use std::hash::{DefaultHasher, Hash, Hasher};
    let key = |d: &Dataset, k: usize| {
        let mut h = DefaultHasher::new();
        (d.q[k].iter().chain(&d.tau[k])).for_each(|x| x.to_bits().hash(&mut h));
        h.finish()
    };
    let seen: HashSet<u64> = (0..own.len()).map(|k| key(own, k)).collect();
    let rows = (0..diagnosed.len())
        .filter(|&k| seen.contains(&key(diagnosed, k)))
        .count();
    match rows > 0 && rows * 100 >= diagnosed.len() {
        true => Err(DiagnoseError::Overlap {
            rows,
            total: diagnosed.len(),
        }),
        false => Ok(()),
    }
}
