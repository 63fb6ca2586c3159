//! `simulate --floating-base [--contacts suspended|standing]`: a
//! floating-base log (docs/floating-base.md) and its JSON record.

use super::floating::{Contacts, Robot, refuse, stance};
use super::simulate::SimulateArgs;
use momentlmi::data::Dataset;
use momentlmi::data::{Staged, record_path};
use momentlmi::dynamics::Model;
use momentlmi::sim::floating::{FloatingNoise, SuspendedConfig, simulate_suspended};
use momentlmi::sim::standing::{StandingConfig, simulate_standing};

/// A floating-base log is written as CSV: an output named as another
/// format is refused rather than filled with CSV text.
fn csv_out(out: &std::path::Path) -> Result<(), String> {
    let ext = (out.extension()).map(|e| e.to_string_lossy().to_lowercase());
    if matches!(ext.as_deref(), Some("npz" | "npy" | "mcap" | "parquet")) {
        return Err(format!(
            "--out {}: a floating-base log is written as CSV (name it .csv; docs/floating-base.md)",
            out.display()
        ));
    }
    Ok(())
}

/// Simulates, writes the CSV and its record whole (or nothing).
pub fn run(a: &SimulateArgs, robot: Robot) -> Result<(), String> {
    refuse(&[
        ("--trajectory", a.trajectory.as_deref().is_some()),
        ("--effects", !a.effects.is_empty()),
        ("--effect-param", !a.effect_param.is_empty()),
        ("--cutoff", a.cutoff.is_some()),
        ("--link-encoder-bits", a.link_encoder_bits.is_some()),
    ])?;
    let mut staged = Staged::protecting(
        a.robot
            .sidecar
            .as_deref()
            .into_iter()
            .chain([std::path::Path::new(a.robot.robot.as_str())]),
    );
    csv_out(&a.out)?;
    let rec = record_path(a.out.as_path());
    for p in [a.out.as_path(), &rec] {
        staged.claim(p).map_err(|e| e.to_string())?;
    }
    let (described, facts) = (
        robot.describe(&a.robot.package_path)?,
        robot.floating_facts()?,
    );
    let ff = described.model;
    check_size(&ff, a.seconds, facts.feet.len().max(1))?;
    let noise = noise(a.noise)?;
    let effects = super::floating::SimEffect::effects(&a.floating_effects)?;
    let contacts = a.contacts.unwrap_or(Contacts::Suspended);
    let log = match contacts {
        Contacts::Suspended => simulate_suspended(&ff, &SuspendedConfig {
            seconds: a.seconds,
            seed: a.seed,
            noise,
            effects,
            ..SuspendedConfig::default()
        }),
        Contacts::Standing => {
            if facts.feet.is_empty() {
                return Err("--contacts standing needs the feet: the sidecar's [floating_base] feet = [\"LINK\", …] (docs/floating-base.md)".into());
            }
            let cfg = StandingConfig {
                seconds: a.seconds,
                seed: a.seed,
                noise,
                effects,
                ..StandingConfig::new(facts.feet.clone(), stance(&ff, &facts)?)
            };
            simulate_standing(&ff, &cfg)
        }
    }
    .map_err(|e| e.to_string())?;
    // (what is written must read back: every value within the readers' limits)
    log.check(&ff).map_err(|e| e.to_string())?;
    let record = record_of(&ff, &log, (contacts, &effects), &noise, a);
    let text = serde_json::to_string_pretty(&record).map_err(|e| e.to_string())?;
    staged
        .add(a.out.as_path(), log.to_csv().as_bytes())
        .map_err(|e| e.to_string())?;
    staged
        .add(&rec, text.as_bytes())
        .map_err(|e| e.to_string())?;
    staged.commit().map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} samples, {}, contacts: {}) and {}",
        a.out.display(),
        log.len(),
        ff.name,
        (log.contacts.iter())
            .map(|c| c.frame.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        rec.display()
    );
    Ok(())
}

/// The sensors' noise: the defaults, all zero with `--noise 0`, or the
/// joint torques' σ (N·m) given.
fn noise(sigma: Option<f64>) -> Result<FloatingNoise, String> {
    match sigma {
        None => Ok(FloatingNoise::default()),
        Some(s) if !(s.is_finite() && s >= 0.0) => {
            Err(format!("--noise {s}: a finite σ ≥ 0 (N·m)"))
        }
        Some(s) if s == 0.0 => Ok(FloatingNoise::none()),
        Some(s) => Ok(FloatingNoise {
            torque: s,
            ..FloatingNoise::default()
        }),
    }
}

/// What the record says of the log: how it was made.
fn record_of(
    ff: &Model,
    log: &Dataset,
    (contacts, effects): (Contacts, &momentlmi::sim::floating::FloatingEffects),
    noise: &FloatingNoise,
    a: &SimulateArgs,
) -> serde_json::Value {
    serde_json::json!({
        "generator": format!("momentlmi {}", env!("CARGO_PKG_VERSION")),
        "floating_base": true,
        "robot": ff.name,
        "base": ff.base().map(|b| b.name.as_str()),
        "samples": log.len(),
        "joints": ff.joint_names(),
        "contacts": format!("{contacts:?}").to_lowercase(),
        "contact_frames": log.contacts.iter().map(|c| &c.frame).collect::<Vec<_>>(),
        "effects": effects.names(),
        "effect_values": effects,
        "seconds": a.seconds,
        "seed": a.seed,
        "noise": {
            "force_n": noise.force, "moment_nm": noise.moment, "twist": noise.twist,
            "twist_rate": noise.twist_rate, "encoder_rad": noise.encoder, "torque_nm": noise.torque,
        },
        "true_params": true_params(ff, effects),
    })
}

/// The true robot's parameter file: the payload in its base, its friction.
fn true_params(
    ff: &Model,
    effects: &momentlmi::sim::floating::FloatingEffects,
) -> Option<momentlmi::dynamics::params_file::ParamsFile> {
    use momentlmi::dynamics::{Friction, FrictionTerm};
    let truth = effects.truth(ff).ok()?; // (it simulated: it is valid)
    let n = ff.dof();
    let mut friction = Friction::zeros(n);
    if let Some([b, c]) = effects.joint_friction {
        *friction.coefficients_mut(FrictionTerm::Viscous) = vec![b; n];
        *friction.coefficients_mut(FrictionTerm::Coulomb) = vec![c; n];
    }
    Some(momentlmi::dynamics::params_file::ParamsFile::from_model(
        &truth, friction,
    ))
}

/// The most memory a simulated log and its CSV text may take (GiB): they
/// are written whole.
const MAX_GIB: f64 = 8.0;

/// Refuses a `--seconds` whose log (numbers and text, ≈ 40 bytes a column
/// a sample) would not fit in [`MAX_GIB`].
fn check_size(ff: &Model, seconds: f64, contacts: usize) -> Result<(), String> {
    let rate = SuspendedConfig::default().rate;
    let columns = 1 + ff.nq() + 2 * ff.nv() + ff.dof() + 6 * contacts;
    let gib = seconds * rate * (40 * columns) as f64 / (1u64 << 30) as f64;
    if gib > MAX_GIB {
        let most = MAX_GIB * (1u64 << 30) as f64 / (rate * (40 * columns) as f64);
        return Err(format!(
            "--seconds {seconds}: a floating-base log of that length ({rate} Hz) needs ≈ {gib:.0} GiB in memory; at most {most:.0} s"
        ));
    }
    Ok(())
}
