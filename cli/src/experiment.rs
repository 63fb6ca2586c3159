//! The paper's experiment (Section VI) on simulated Cheetah 3 leg data:
//! simulate, identify at every constraint level, validate on the next
//! samples, and write the tables and figures (Fig. 4–6), and the
//! Euclidean-against-entropic prior study beside Fig. 6
//! ([`crate::regularizer_study`]).

use crate::plots::figures::{Series, line_panels};
use crate::regularizer_study::{RegularizerRow, regularizer_figure, regularizer_study};
use momentlmi::data::{Dataset, Staged, stage_with_record};
use momentlmi::dynamics::{RobotDescription, cheetah3};
use momentlmi::effects::simulate;
use momentlmi::identify::{IdentifyOptions, IdentifyResult, Level, identify};
use momentlmi::sim::{Effects, SimConfig};
use serde::Serialize;
use std::path::Path;

/// Settings of the experiment.
#[derive(Clone, Debug, Serialize)]
pub struct ExperimentConfig {
    /// Training samples (the paper: 10,000).
    pub train: usize,
    /// Validation samples, the ones right after (the paper: 10,000).
    pub validate: usize,
    /// Torque noise σ (N·m).
    pub noise: f64,
    /// Regularisation weight toward the CAD prior (the paper: 1e-6).
    pub weight: f64,
    /// Training sizes for the sample-size study (Fig. 6).
    pub sizes: Vec<usize>,
    /// Training sizes for the regulariser study (Fig. 7).
    pub regularizer_sizes: Vec<usize>,
    /// Seed.
    pub seed: u64,
}

impl Default for ExperimentConfig {
    fn default() -> Self {
        Self {
            train: 10_000,
            validate: 10_000,
            noise: 0.3,
            weight: 1e-6,
            sizes: vec![100, 200, 400, 700, 1000, 2000, 4000, 7000, 10_000],
            regularizer_sizes: vec![100, 200, 400, 1000, 4000, 10_000],
            seed: 1,
        }
    }
}

/// One row of the summary table.
#[derive(Clone, Debug, Serialize)]
pub struct LevelSummary {
    /// Level.
    pub constraints: Level,
    /// Validation RMS per joint (N·m).
    pub validation_rms: Vec<f64>,
    /// Overall validation RMS (N·m).
    pub overall_rms: f64,
    /// Bodies that are physically consistent (of 6).
    pub consistent_bodies: usize,
    /// Identified Coulomb friction.
    pub coulomb: Vec<f64>,
    /// Solve time (s).
    pub solve_time_s: f64,
}

/// Everything the experiment produced.
#[derive(Clone, Debug, Serialize)]
pub struct ExperimentSummary {
    /// The settings.
    pub config: ExperimentConfig,
    /// Table per level (full training set).
    pub levels: Vec<LevelSummary>,
    /// Sample-size study: `(level, samples, overall validation RMS)`.
    pub sample_study: Vec<(Level, usize, f64)>,
    /// Euclidean against entropic prior, each at its chosen weight.
    pub regularizers: Vec<RegularizerRow>,
    /// Files written.
    pub files: Vec<String>,
}

fn overall(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

const LEVELS: [Level; 4] = [
    Level::None,
    Level::Semi,
    Level::Consistent,
    Level::Ellipsoid,
];

fn text<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Simulates the leg (rotors, Coulomb and viscous friction) for the training
/// and validation samples and stages `leg.csv` with its `leg.json` record.
fn simulate_leg(
    robot: &RobotDescription,
    (out, staged): (&Path, &mut Staged),
    cfg: &ExperimentConfig,
) -> Result<(Dataset, String), String> {
    let seconds = (cfg.train + cfg.validate) as f64 / 1000.0;
    let effects = Effects::new(["rotor_inertia", "coulomb", "viscous"]);
    let mut sim = SimConfig::for_robot(robot, seconds, effects, cfg.seed);
    sim.noise_sigma = cfg.noise;
    let all = simulate(robot, &sim, |_, _| {}).map_err(text)?;
    let data_path = out.join("leg.csv");
    stage_with_record(staged, &all, &data_path, &sim).map_err(text)?;
    Ok((all, data_path.display().to_string()))
}

/// Identifies at every level on the whole training set, staging
/// `identified_<level>.json`.
fn identify_levels(
    robot: &RobotDescription,
    (train, val): (&Dataset, &Dataset),
    cfg: &ExperimentConfig,
    (out, staged): (&Path, &mut Staged),
    files: &mut Vec<String>,
    progress: &mut dyn FnMut(&str),
) -> Result<(Vec<LevelSummary>, Vec<IdentifyResult>), String> {
    let mut results = vec![];
    let mut table = vec![];
    for level in LEVELS {
        progress(&format!("identifying ({})", level.as_str()));
        let opts = IdentifyOptions::for_robot(robot, level, cfg.weight).map_err(text)?;
        let r = identify(&robot.model, train, Some(val), &opts).map_err(text)?;
        let v = r.validation_rms.clone().unwrap_or_default();
        table.push(LevelSummary {
            constraints: level,
            overall_rms: overall(&v),
            validation_rms: v,
            consistent_bodies: r.bodies.iter().filter(|b| b.consistent).count(),
            coulomb: r.friction.coulomb.clone(),
            solve_time_s: r.solve_time_s,
        });
        let f = out.join(format!("identified_{}.json", level.as_str()));
        staged
            .add_text(&f, &serde_json::to_string_pretty(&r).map_err(text)?)
            .map_err(text)?;
        files.push(f.display().to_string());
        results.push(r);
    }
    Ok((table, results))
}

/// Fig. 6's data: validation RMS against the number of training samples.
fn sample_study(
    robot: &RobotDescription,
    (train, val): (&Dataset, &Dataset),
    cfg: &ExperimentConfig,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<(Level, usize, f64)>, String> {
    let mut study = vec![];
    for level in LEVELS {
        let opts = IdentifyOptions::for_robot(robot, level, cfg.weight).map_err(text)?;
        for &n in &cfg.sizes {
            progress(&format!("sample study ({}, {n})", level.as_str()));
            let n = n.min(cfg.train);
            let r = identify(&robot.model, &train.slice(0..n), Some(val), &opts).map_err(text)?;
            study.push((level, n, overall(&r.validation_rms.unwrap_or_default())));
        }
    }
    Ok(study)
}

/// A time series of the validation set, thinned to ~2,500 points.
fn series<'a>(val: &Dataset, label: &'a str, color: usize, f: &dyn Fn(usize) -> f64) -> Series<'a> {
    let t0 = val.t.first().copied().unwrap_or(0.0);
    let stride = (val.len() / 2500).max(1);
    Series {
        label,
        points: (0..val.len())
            .step_by(stride)
            .map(|k| (val.t[k] - t0, f(k)))
            .collect(),
        color,
    }
}

/// Fig. 4 (measured vs predicted held-out torques) and Fig. 5 (the
/// contributions) of the ellipsoid-level fit.
fn figures_4_5(
    best: &IdentifyResult,
    val: &Dataset,
    (out, staged): (&Path, &mut Staged),
) -> Result<Vec<std::path::PathBuf>, String> {
    let panels: Vec<Vec<Series>> = (0..3)
        .map(|j| {
            vec![
                series(val, "measured", 5, &|k| val.tau[k][j]),
                series(val, "predicted (ellipsoid)", 0, &|k| {
                    best.validation_prediction[k][j]
                }),
            ]
        })
        .collect();
    let titles: Vec<String> = cheetah3::JOINTS
        .iter()
        .zip(best.validation_rms.clone().unwrap_or_default())
        .map(|(j, r)| format!("{j}: validation RMS {r:.3} N·m"))
        .collect();
    let f4 = out.join("fig4_validation.svg");
    let svg = line_panels(
        "Fig. 4 — held-out torques, measured vs predicted",
        "time in validation set [s]",
        &titles,
        "torque [N·m]",
        &panels,
        false,
    )?;
    let c = &best.contributions;
    let panels: Vec<Vec<Series>> = (0..3)
        .map(|j| {
            vec![
                series(val, "link inertia + gravity", 0, &|k| c.links[k][j]),
                series(val, "rotor inertia", 1, &|k| c.rotors[k][j]),
                series(val, "friction", 2, &|k| c.friction[k][j]),
            ]
        })
        .collect();
    let titles: Vec<String> = cheetah3::JOINTS.iter().map(|j| j.to_string()).collect();
    staged.add_text(&f4, &svg).map_err(text)?;
    let f5 = out.join("fig5_contributions.svg");
    let svg = line_panels(
        "Fig. 5 — contributions to the predicted torque",
        "time in validation set [s]",
        &titles,
        "torque [N·m]",
        &panels,
        false,
    )?;
    staged.add_text(&f5, &svg).map_err(text)?;
    Ok(vec![f4, f5])
}

/// Fig. 6 and its CSV.
fn figure_6(
    study: &[(Level, usize, f64)],
    (out, staged): (&Path, &mut Staged),
) -> Result<Vec<std::path::PathBuf>, String> {
    let panel: Vec<Series> = LEVELS
        .iter()
        .enumerate()
        .map(|(i, l)| Series {
            label: l.as_str(),
            points: study
                .iter()
                .filter(|s| s.0 == *l)
                .map(|s| (s.1 as f64, s.2))
                .collect(),
            color: i,
        })
        .collect();
    let f6 = out.join("fig6_samples.svg");
    let svg = line_panels(
        "Fig. 6 — validation RMS vs training samples",
        "training samples",
        &["overall validation RMS".into()],
        "RMS [N·m]",
        &[panel],
        true,
    )?;
    staged.add_text(&f6, &svg).map_err(text)?;
    let mut csv = String::from("constraints,samples,overall_validation_rms\n");
    for (l, n, r) in study {
        csv += &format!("{},{n},{r}\n", l.as_str());
    }
    let f6c = out.join("fig6_samples.csv");
    staged.add_text(&f6c, &csv).map_err(text)?;
    Ok(vec![f6, f6c])
}

/// The data behind Fig. 4 and 5 as CSV.
fn figure_4_5_csv(
    best: &IdentifyResult,
    val: &Dataset,
    (out, staged): (&Path, &mut Staged),
) -> Result<std::path::PathBuf, String> {
    let c = &best.contributions;
    let stride = (val.len() / 2500).max(1);
    let mut csv = String::from("t,joint,measured,predicted,links,rotors,friction\n");
    for k in (0..val.len()).step_by(stride) {
        for (j, name) in cheetah3::JOINTS.iter().enumerate() {
            csv += &format!(
                "{},{name},{},{},{},{},{}\n",
                val.t[k],
                val.tau[k][j],
                best.validation_prediction[k][j],
                c.links[k][j],
                c.rotors[k][j],
                c.friction[k][j]
            );
        }
    }
    let f45 = out.join("fig4_fig5_data.csv");
    staged.add_text(&f45, &csv).map_err(text)?;
    Ok(f45)
}

/// Runs the experiment, staging its files for `out` in `staged` (the
/// caller commits them, so a later failure leaves nothing);
/// `progress(step, total, what)`. `out` must exist.
pub fn run_experiment(
    (out, staged): (&Path, &mut Staged),
    cfg: &ExperimentConfig,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<(ExperimentSummary, Vec<IdentifyResult>), String> {
    let robot = cheetah3::description();
    let total_steps = 2 + 4 + 4 * cfg.sizes.len() + cfg.regularizer_sizes.len();
    let mut step = 0;
    let mut tick = |what: &str| {
        progress(step, total_steps, what);
        step += 1;
    };
    tick("simulating the true leg");
    let (all, data_file) = simulate_leg(&robot, (out, &mut *staged), cfg)?;
    let mut files = vec![data_file];
    let train = all.slice(0..cfg.train);
    let val = all.slice(cfg.train..cfg.train + cfg.validate);
    let (table, results) = identify_levels(
        &robot,
        (&train, &val),
        cfg,
        (out, &mut *staged),
        &mut files,
        &mut tick,
    )?;
    let study = sample_study(&robot, (&train, &val), cfg, &mut tick)?;
    let regs = regularizer_study(&robot, (&train, &val), &cfg.regularizer_sizes, &mut tick)?;
    tick("writing figures");
    let best = &results[3];
    let mut written = figures_4_5(best, &val, (out, &mut *staged))?;
    written.extend(figure_6(&study, (out, &mut *staged))?);
    written.push(figure_4_5_csv(best, &val, (out, &mut *staged))?);
    written.extend(regularizer_figure(&regs, (out, &mut *staged))?);
    files.extend(written.iter().map(|p| p.display().to_string()));
    let summary = ExperimentSummary {
        config: cfg.clone(),
        levels: table,
        sample_study: study,
        regularizers: regs,
        files,
    };
    staged
        .add_text(
            &out.join("summary.json"),
            &serde_json::to_string_pretty(&summary).map_err(text)?,
        )
        .map_err(text)?;
    progress(total_steps, total_steps, "done");
    Ok((summary, results))
}
