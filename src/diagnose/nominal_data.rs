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
    library: &Library,
) -> Result<Prior, DiagnoseError> {
    let model = nominal.0;
    super::check_data(model, own).map_err(|e| DiagnoseError::NominalData(Box::new(e)))?;
    let r = residual_of(nominal, own, library)?;
    let (n, m) = (model.dof(), model.params().len());
    let piece = |start: usize| -> Result<(Mat<f64>, Vec<f64>, f64), DiagnoseError> {
        let mut g = Mat::<f64>::zeros(m, m);
        let (mut xr, mut rr) = (vec![0.0; m], 0.0);
        let mut data = Data::new(model);
        for k in start..(start + PIECE).min(own.len()) {
            // the load friction column's load (no body column reads it)
            data.load.copy_from_slice(&own.tau[k]);
            let y = regressor(model, &mut data, &own.q[k], &own.qd[k], &own.qdd[k])
                .map_err(|source| DiagnoseError::Regressor { sample: k, source })?;
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
    let parts: Vec<_> = (0..own.len())
        .step_by(PIECE)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(piece)
        .collect::<Result<_, _>>()?;
    let mut g = Mat::<f64>::zeros(m, m);
    let (mut xr, mut rr) = (vec![0.0; m], 0.0);
    for (pg, px, pr) in parts {
        g += &pg;
        xr.iter_mut().zip(&px).for_each(|(a, b)| *a += b);
        rr += pr;
    }
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
