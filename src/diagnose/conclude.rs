//! After the selection: the final model (the law and the accepted effects
//! refit on the fitting part, then refined as `predict` uses them), its
//! sizes and the law's re-estimates, its held-out error through `predict`
//! on the held-out part, and the report.

use super::error::DiagnoseError;
use super::final_fit::FinalSetup;
use super::floor::NoiseFloor;
use super::forward::{Selected, Setup};
use super::heldout::{gap_closed, held_out, residual_of, where_of, with_heldout};
use super::law::Law;
use super::model_out::ModelOut;
use super::refine::Refine;
use super::report::{Diagnosis, SizeReport};
use super::split::Split;
use super::warning::DiagnoseWarning;
use super::where_::{JointWhere, summarise};
use crate::data::{Dataset, rms_per_joint};
use crate::dynamics::params_file::FittedEffect;
use crate::dynamics::{Friction, Model};

/// What the conclusion works on.
pub struct Conclude<'a> {
    /// The selection's set-up.
    pub setup: &'a Setup<'a>,
    /// The nominal law.
    pub law: &'a Law,
    /// The data.
    pub data: &'a Dataset,
    /// The held-out part.
    pub split: &'a Split,
    /// The nominal model, friction and fitted effects.
    pub nominal: (&'a Model, &'a Friction, &'a [FittedEffect]),
    /// Its residual.
    pub r_nominal: &'a [f64],
    /// The effects' library.
    pub library: &'a crate::effects::Library,
}

/// The final model's parts the report needs.
struct Final {
    out: ModelOut,
    law_sizes: Vec<SizeReport>,
    sizes: Vec<Vec<SizeReport>>,
    refit: Vec<f64>,
}

impl Conclude<'_> {
    fn fail(what: &'static str) -> impl Fn(super::FitError) -> DiagnoseError {
        move |source| DiagnoseError::Fit { what, source }
    }

    /// The final model of `selected`: fitted, refined, its sizes.
    fn final_model(
        &self,
        selected: &Selected,
        warnings: &mut Vec<DiagnoseWarning>,
    ) -> Result<Final, DiagnoseError> {
        let s = self.setup;
        let fs = FinalSetup {
            store: s.store,
            folds: s.folds,
            law: self.law,
            candidates: s.candidates,
            model: self.nominal.0,
        };
        let fin = fs
            .fit(&selected.accepted)
            .map_err(Self::fail("the final model's fit"))?;
        if let Some(why) = &fin.unconstrained {
            warnings.push(DiagnoseWarning::Unconstrained { why: why.clone() });
        }
        if fin.inaccurate {
            warnings.push(DiagnoseWarning::Inaccurate {
                round: 0,
                effect: "the final model".into(),
                variant: String::new(),
            });
        }
        let (out, beta, stopped) = Refine {
            data: self.data,
            folds: s.folds,
            nominal: self.nominal,
            law: self.law,
            accepted: &selected.accepted,
            candidates: s.candidates,
            store: s.store,
            library: self.library,
        }
        .refine(fin.beta.clone())?;
        if let Some(why) = stopped {
            warnings.push(DiagnoseWarning::RefinementStopped { why });
        }
        let (law_sizes, sizes) = fs.recentred(&selected.accepted, &fin, &beta);
        Ok(Final {
            out,
            law_sizes,
            sizes,
            refit: fin.refit,
        })
    }

    /// The diagnosis of `selected`.
    pub fn report(
        &self,
        mut selected: Selected,
        where_nominal: Vec<JointWhere>,
        floor: NoiseFloor,
        mut warnings: Vec<DiagnoseWarning>,
    ) -> Result<Diagnosis, DiagnoseError> {
        let (s, split, n) = (self.setup, self.split, self.setup.store.joints());
        let fin = self.final_model(&selected, &mut warnings)?;
        let reestimated =
            super::reestimate::reestimates(s, self.law, &selected.accepted, &fin.law_sizes)
                .map_err(Self::fail("the friction law's re-estimates"))?;
        let accepted_reports = selected.ranked.iter_mut().filter(|r| r.accepted);
        accepted_reports
            .zip(fin.sizes)
            .for_each(|(r, sizes)| r.sizes = sizes);
        let heldout_data = self.data.slice(split.first_heldout..self.data.len());
        let out = &fin.out;
        let r_heldout = residual_of(
            (&out.model, &out.friction, &out.effects),
            &heldout_data,
            self.library,
        )?;
        let r_final = with_heldout(self.r_nominal, split, &r_heldout);
        let nominal = rms_per_joint(&self.r_nominal[split.heldout.clone()], n);
        let final_rms = rms_per_joint(&r_heldout, n);
        let noise_floor = floor.per_joint.clone();
        let numbers = [&nominal, &final_rms, &noise_floor];
        if let Some(k) = numbers
            .iter()
            .position(|v| !v.iter().all(|x| x.is_finite()))
        {
            return Err(DiagnoseError::NonFinite {
                what: ["the nominal RMS", "the final RMS", "the noise floor"][k],
            });
        }
        let unexplained: Vec<usize> = (0..n)
            .filter(|&i| {
                final_rms[i] > 1.15 * noise_floor[i] && final_rms[i] - noise_floor[i] > 0.05
            })
            .collect();
        let where_final = where_of(split, self.data, &r_final);
        Ok(Diagnosis {
            joints: self.data.joints.clone(),
            summary: where_nominal.iter().map(summarise).collect(),
            where_: where_nominal,
            accepted: (selected.accepted.iter())
                .map(|a| s.candidates[a.candidate].name().to_string())
                .collect(),
            ranked_effects: selected.ranked,
            folds: s.folds.describe(),
            reestimated,
            friction_refit: fin.law_sizes,
            gap_closed: gap_closed(&nominal, &final_rms, &noise_floor),
            heldout_rms_nominal: nominal,
            heldout_rms_refit: rms_per_joint(&fin.refit, n),
            heldout_rms_final: final_rms,
            noise_floor,
            noise_floor_source: floor.source,
            unexplained: !unexplained.is_empty(),
            unexplained_where: unexplained
                .iter()
                .map(|&i| summarise(&where_final[i]))
                .collect(),
            warnings,
            heldout: held_out(split, self.data, self.r_nominal, &r_final),
            model: fin.out.file(),
        })
    }
}
