//! The paper's experiment (Section VI) on simulated Cheetah 3 leg data:
//! simulate, identify at every constraint level, validate on the next
//! samples, and write the tables and figures (Fig. 4–6).

use crate::plots::figures::{Series, line_panels};
use momentlmi::data::write_whole;
use momentlmi::dynamics::cheetah3;
use momentlmi::identify::{IdentifyOptions, IdentifyResult, Level, identify};
use momentlmi::sim::{Effects, SimConfig, simulate};
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
    /// Files written.
    pub files: Vec<String>,
}

fn overall(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

/// Runs the experiment into `out`; `progress(step, total, what)`.
pub fn run_experiment(
    out: &Path,
    cfg: &ExperimentConfig,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<(ExperimentSummary, Vec<IdentifyResult>), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let model = cheetah3::model();
    let total_steps = 2 + 4 + 4 * cfg.sizes.len();
    let mut step = 0;
    progress(step, total_steps, "simulating the true leg");
    let seconds = (cfg.train + cfg.validate) as f64 / 1000.0;
    let effects = Effects::parse("rotor_inertia,coulomb,viscous", &[])?;
    let mut sim = SimConfig::for_model("cheetah3-leg", &model, seconds, effects, cfg.seed);
    sim.noise_sigma = cfg.noise;
    let all = simulate(&model, &sim, |_, _| {})?;
    let mut files = vec![];
    let data_path = out.join("leg.csv");
    all.write_csv(&data_path).map_err(|e| e.to_string())?;
    write_whole(
        &out.join("leg.json"),
        &serde_json::to_string_pretty(&sim).map_err(|e| e.to_string())?,
    )
    .map_err(|e| e.to_string())?;
    files.push(data_path.display().to_string());
    step += 1;
    let train = all.slice(0..cfg.train);
    let val = all.slice(cfg.train..cfg.train + cfg.validate);
    let opts = |level| IdentifyOptions::cheetah3(level, cfg.weight);
    let levels = [
        Level::None,
        Level::Semi,
        Level::Consistent,
        Level::Ellipsoid,
    ];
    let mut results = vec![];
    let mut table = vec![];
    for level in levels {
        progress(
            step,
            total_steps,
            &format!("identifying ({})", level.as_str()),
        );
        let r = identify(&model, &train, Some(&val), &opts(level)).map_err(|e| e.to_string())?;
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
        write_whole(
            &f,
            &serde_json::to_string_pretty(&r).map_err(|e| e.to_string())?,
        )
        .map_err(|e| e.to_string())?;
        files.push(f.display().to_string());
        results.push(r);
        step += 1;
    }
    // Fig. 6: validation RMS vs training samples
    let mut study = vec![];
    for level in levels {
        for &n in &cfg.sizes {
            progress(
                step,
                total_steps,
                &format!("sample study ({}, {n})", level.as_str()),
            );
            let n = n.min(cfg.train);
            let r = identify(&model, &train.slice(0..n), Some(&val), &opts(level))
                .map_err(|e| e.to_string())?;
            study.push((level, n, overall(&r.validation_rms.unwrap_or_default())));
            step += 1;
        }
    }
    progress(step, total_steps, "writing figures");
    let joints = ["abad", "hip", "knee"];
    let best = &results[3];
    // Fig. 4: measured vs predicted validation torques
    let t0 = val.t.first().copied().unwrap_or(0.0);
    let stride = (val.len() / 2500).max(1);
    // a time series of the validation set, thinned to ~2,500 points
    let series = |label: &'static str, color: usize, f: &dyn Fn(usize) -> f64| Series {
        label,
        points: (0..val.len())
            .step_by(stride)
            .map(|k| (val.t[k] - t0, f(k)))
            .collect(),
        color,
    };
    let panels: Vec<Vec<Series>> = (0..3)
        .map(|j| {
            vec![
                series("measured", 5, &|k| val.tau[k][j]),
                series("predicted (ellipsoid)", 0, &|k| {
                    best.validation_prediction[k][j]
                }),
            ]
        })
        .collect();
    let titles: Vec<String> = joints
        .iter()
        .zip(best.validation_rms.clone().unwrap_or_default())
        .map(|(j, r)| format!("{j}: validation RMS {r:.3} N·m"))
        .collect();
    let f4 = out.join("fig4_validation.svg");
    line_panels(
        &f4,
        "Fig. 4 — held-out torques, measured vs predicted",
        "time in validation set [s]",
        &titles,
        "torque [N·m]",
        &panels,
        false,
    )?;
    // Fig. 5: contributions
    let c = &best.contributions;
    let panels: Vec<Vec<Series>> = (0..3)
        .map(|j| {
            vec![
                series("link inertia + gravity", 0, &|k| c.links[k][j]),
                series("rotor inertia", 1, &|k| c.rotors[k][j]),
                series("friction", 2, &|k| c.friction[k][j]),
            ]
        })
        .collect();
    let titles: Vec<String> = joints.iter().map(|j| j.to_string()).collect();
    let f5 = out.join("fig5_contributions.svg");
    line_panels(
        &f5,
        "Fig. 5 — contributions to the predicted torque",
        "time in validation set [s]",
        &titles,
        "torque [N·m]",
        &panels,
        false,
    )?;
    // Fig. 6
    let panel: Vec<Series> = levels
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
    line_panels(
        &f6,
        "Fig. 6 — validation RMS vs training samples",
        "training samples",
        &["overall validation RMS".into()],
        "RMS [N·m]",
        &[panel],
        true,
    )?;
    let mut csv = String::from("constraints,samples,overall_validation_rms\n");
    for (l, n, r) in &study {
        csv += &format!("{},{n},{r}\n", l.as_str());
    }
    let f6c = out.join("fig6_samples.csv");
    write_whole(&f6c, &csv).map_err(|e| e.to_string())?;
    let mut csv = String::from("t,joint,measured,predicted,links,rotors,friction\n");
    for k in (0..val.len()).step_by(stride) {
        for (j, name) in joints.iter().enumerate() {
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
    write_whole(&f45, &csv).map_err(|e| e.to_string())?;
    files.extend(
        [f4, f5, f6, f6c, f45]
            .iter()
            .map(|p| p.display().to_string()),
    );
    let summary = ExperimentSummary {
        config: cfg.clone(),
        levels: table,
        sample_study: study,
        files,
    };
    write_whole(
        &out.join("summary.json"),
        &serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?,
    )
    .map_err(|e| e.to_string())?;
    progress(total_steps, total_steps, "done");
    Ok((summary, results))
}
