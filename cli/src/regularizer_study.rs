//! Euclidean against entropic prior on the paper's experiment: for each
//! training size and regulariser, the weight that predicts best on a
//! selection set (the first half of the held-out samples) is chosen from a
//! grid, and that fit is scored on the test set (the second half) and
//! against the true parameters, in the divergence and in the Euclidean
//! metric (docs/identification.md, "Entropic prior").

use crate::plots::figures::{Series, line_panels};
use momentlmi::data::{Dataset, Staged};
use momentlmi::dynamics::RobotDescription;
use momentlmi::identify::{
    Identification, IdentifyError, Level, Reduced, Regularizer, reduce_samples,
};
use momentlmi::moments::{InertialParams, entropic_divergence};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Weights tried per regulariser.
const GRID: [(Regularizer, &[f64]); 2] = [
    (
        Regularizer::Euclidean,
        &[1e-8, 1e-6, 1e-4, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3, 1e4],
    ),
    (
        Regularizer::Entropic,
        &[1e-5, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1, 1.0, 1e1],
    ),
];

/// One (training size, regulariser) cell at its chosen weight.
#[derive(Clone, Debug, Serialize)]
pub struct RegularizerRow {
    /// The regulariser.
    pub regularizer: Regularizer,
    /// Training samples.
    pub samples: usize,
    /// The weight chosen on the selection set.
    pub weight: f64,
    /// The chosen weight is the grid's first or last (the best may lie beyond).
    pub at_grid_edge: bool,
    /// Overall RMS on the test set (N·m).
    pub test_rms: f64,
    /// `Σ_b d(J_b ‖ J_b,true)` (dimensionless; `None`: a body singular).
    pub divergence_from_truth: Option<f64>,
    /// `‖π − π_true‖₂` over every body's ten parameters (mixed units).
    pub euclidean_error: f64,
}

/// Overall RMS `√(‖Aθ − b‖² / (samples · dof))` from a reduced set's Gram
/// matrix `[A b]ᵀ[A b]`.
fn rms_of(red: &Reduced, theta: &[f64], dof: usize) -> f64 {
    let g = &red.gram;
    let p = red.p;
    let mut x = theta.to_vec();
    x.push(-1.0);
    let sq: f64 = (0..=p)
        .map(|i| x[i] * (0..=p).map(|j| g[(i, j)] * x[j]).sum::<f64>())
        .sum();
    (sq.max(0.0) / (red.samples * dof) as f64).sqrt()
}

/// The errors of θ's bodies against the truth.
fn errors(theta: &[f64], truth: &[f64]) -> (Option<f64>, f64) {
    let body = |v: &[f64], b: usize| InertialParams(std::array::from_fn(|k| v[10 * b + k]));
    let nb = truth.len() / 10;
    let div = (0..nb)
        .map(|b| entropic_divergence(&body(theta, b), &body(truth, b)).ok())
        .sum::<Option<f64>>();
    let euc = (0..truth.len())
        .map(|k| (theta[k] - truth[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    (div, euc)
}

fn reduce(robot: &RobotDescription, d: &Dataset) -> Result<Reduced, IdentifyError> {
    reduce_samples(&robot.model, &d.q, &d.qd, &d.qdd, &d.tau, 1024)
}

/// The study on `train` (first `sizes` samples) and `held_out` (split into
/// selection and test halves), at the ellipsoid level with the robot's prior.
pub fn regularizer_study(
    robot: &RobotDescription,
    (train, held_out): (&Dataset, &Dataset),
    sizes: &[usize],
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<RegularizerRow>, String> {
    let text = |e: IdentifyError| e.to_string();
    let half = held_out.len() / 2;
    let select = reduce(robot, &held_out.slice(0..half)).map_err(text)?;
    let test = reduce(robot, &held_out.slice(half..held_out.len())).map_err(text)?;
    let truth = robot.model.params();
    let dof = robot.model.dof();
    let mut rows = vec![];
    for &n in sizes {
        let n = n.min(train.len());
        progress(&format!("regulariser study ({n} samples)"));
        let red = reduce(robot, &train.slice(0..n)).map_err(text)?;
        for (reg, weights) in GRID {
            let mut best: Option<(f64, f64, Vec<f64>)> = None;
            for &w in weights {
                let theta = Identification::for_robot(robot, Level::Ellipsoid, w)
                    .map_err(text)?
                    .regularizer(reg)
                    .solve(&red)
                    .map_err(text)?
                    .theta;
                let score = rms_of(&select, &theta, dof);
                if best.as_ref().is_none_or(|b| score < b.1) {
                    best = Some((w, score, theta));
                }
            }
            let (weight, _, theta) = best.ok_or("an empty weight grid")?;
            let at_grid_edge = weights.first() == Some(&weight) || weights.last() == Some(&weight);
            let (divergence_from_truth, euclidean_error) = errors(&theta, &truth);
            rows.push(RegularizerRow {
                regularizer: reg,
                samples: n,
                weight,
                at_grid_edge,
                test_rms: rms_of(&test, &theta, dof),
                divergence_from_truth,
                euclidean_error,
            });
        }
    }
    Ok(rows)
}

/// The study's figure (test RMS and both parameter errors against the
/// training samples) and its CSV.
pub fn regularizer_figure(
    rows: &[RegularizerRow],
    (out, staged): (&Path, &mut Staged),
) -> Result<Vec<PathBuf>, String> {
    let series = |f: &dyn Fn(&RegularizerRow) -> Option<f64>| -> Vec<Series<'static>> {
        GRID.iter()
            .enumerate()
            .map(|(i, (reg, _))| Series {
                label: reg.as_str(),
                points: rows
                    .iter()
                    .filter(|r| r.regularizer == *reg)
                    .filter_map(|r| f(r).map(|y| (r.samples as f64, y)))
                    .collect(),
                color: i,
            })
            .collect()
    };
    // both axes are logarithmic (`line_panels` with `log_x`): raw values
    let panels = vec![
        series(&|r| Some(r.test_rms)),
        series(&|r| r.divergence_from_truth),
        series(&|r| Some(r.euclidean_error)),
    ];
    let titles = [
        "test RMS [N·m] at the weight chosen on the selection set".to_string(),
        "Σ d(J ‖ J_true) (entropic metric, dimensionless)".to_string(),
        "‖π − π_true‖ (Euclidean metric, mixed units)".to_string(),
    ];
    let svg = line_panels(
        "Euclidean vs entropic prior (ellipsoid level), beside Fig. 6",
        "training samples",
        &titles,
        "panel's quantity (log scale)",
        &panels,
        true,
    )?;
    let fig = out.join("fig7_regularizers.svg");
    staged.add_text(&fig, &svg).map_err(|e| e.to_string())?;
    let mut csv = String::from(
        "regularizer,samples,weight,weight_at_grid_edge,test_rms,divergence_from_truth,euclidean_error\n",
    );
    for r in rows {
        let div = r
            .divergence_from_truth
            .map_or_else(String::new, |d| d.to_string());
        csv += &format!(
            "{},{},{:e},{},{},{div},{}\n",
            r.regularizer.as_str(),
            r.samples,
            r.weight,
            r.at_grid_edge,
            r.test_rms,
            r.euclidean_error
        );
    }
    let f = out.join("fig7_regularizers.csv");
    staged.add_text(&f, &csv).map_err(|e| e.to_string())?;
    Ok(vec![fig, f])
}
