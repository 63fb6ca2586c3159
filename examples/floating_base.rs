//! A floating-base robot identified from its base rows and the measured
//! contact wrench alone (no joint torque): Solo12 (robots/solo12) suspended
//! from a harness whose load cell measures the wrench at the base, 60 s of
//! training, 20 s held out (docs/floating-base.md).
//!
//! ```sh
//! cargo run --release --example floating_base [-- LOG.csv]
//! ```
//! prints the held-out base-wrench RMS against its floor and the whole
//! robot's mass, CoM and centroidal inertia against the truth; with a path,
//! also writes the training log in the floating-base CSV format.

use momentlmi::dynamics::urdf::free_flyer_from_urdf_file;
use momentlmi::dynamics::{Data, Model};
use momentlmi::identify::floating::measured;
use momentlmi::identify::{Identification, Rows, reduce_floating};
use momentlmi::sim::floating::{SuspendedConfig, simulate_suspended};
use std::error::Error;
use std::path::Path;

/// RMS of the base rows' residual `measured − Y θ` over a log.
fn base_rms(
    ff: &Model,
    log: &momentlmi::data::Dataset,
    theta: &[f64],
) -> Result<f64, Box<dyn Error>> {
    let mut data = Data::new(ff);
    let mut sum = 0.0;
    for k in 0..log.len() {
        let b = measured(ff, &mut data, log, k)?;
        let (q, v, a) = log.state(k);
        let y = momentlmi::dynamics::regressor(ff, &mut data, &q, &v, &a)?;
        for i in 0..6 {
            let pred: f64 = (0..theta.len()).map(|j| y[(i, j)] * theta[j]).sum();
            sum += (b[i] - pred).powi(2);
        }
    }
    Ok((sum / (6 * log.len()) as f64).sqrt())
}

fn main() -> Result<(), Box<dyn Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let ff = free_flyer_from_urdf_file(&root.join("robots/solo12/solo12.urdf"), None)?;
    let cfg = |seconds, seed| SuspendedConfig {
        seconds,
        seed,
        ..SuspendedConfig::default()
    };
    let (train, test) = (
        simulate_suspended(&ff, &cfg(60.0, 1))?,
        simulate_suspended(&ff, &cfg(20.0, 2))?,
    );
    if let Some(out) = std::env::args().nth(1) {
        momentlmi::data::write_whole(Path::new(&out), &train.to_csv())?;
    }
    let red = reduce_floating(&ff, &train, Rows::Base)?;
    let solved = Identification::for_free_flyer(&ff, Rows::Base).solve(&red)?;
    let mut truth = ff.params();
    truth.resize(ff.regressor_columns(), 0.0);
    println!(
        "held-out base wrench RMS {:.4} (floor, the true model: {:.4})",
        base_rms(&ff, &test, &solved.theta)?,
        base_rms(&ff, &test, &truth)?
    );
    println!(
        "base rows: rank {} of {} columns",
        solved.identifiability.rank, solved.identifiability.columns
    );
    let mut fitted = ff.clone();
    fitted.set_params(&solved.theta[..10 * ff.num_bodies()])?;
    let mut data = Data::new(&ff);
    let q = &test.state(0).0;
    let (m0, c0, i0) = ff.centroidal(&mut data, q)?;
    let (m1, c1, i1) = fitted.centroidal(&mut data, q)?;
    println!("mass {m1:.4} kg (truth {m0:.4})");
    println!("CoM off by {:.2} mm", 1e3 * (c1 - c0).norm());
    println!(
        "centroidal inertia off by {:.2} %",
        100.0 * (i1 - i0).norm() / i0.norm()
    );
    Ok(())
}
