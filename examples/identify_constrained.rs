//! Identification with your own constraints: the leg with (a) its total
//! mass known from a scale, (b) the ellipsoid level on the knee link only,
//! (c) the two identical rotors forced equal — then results read by name.
//!
//! Run: `cargo run --release --example identify_constrained`
//! (from the command line: `momentlmi identify --robot cheetah3-leg --data leg.csv
//! --level knee=ellipsoid --total-mass 5.25 --equal hip_rotor,knee_rotor`)

use momentlmi::dynamics::cheetah3;
use momentlmi::effects::simulate;
use momentlmi::identify::{Identification, IdentifyResult, Level};
use momentlmi::sim::{Effects, SimConfig};

/// The identification of 10 s of simulated leg data (5 s to fit, 5 s to
/// validate) with the total mass `total` (kg).
pub fn run(total: f64) -> Result<IdentifyResult, Box<dyn std::error::Error>> {
    let leg = cheetah3::description();
    let effects = Effects::new(["rotor_inertia", "coulomb", "viscous"]);
    let data = simulate(
        &leg,
        &SimConfig::for_robot(&leg, 10.0, effects, 3),
        |_, _| {},
    )?;
    let (train, val) = (data.slice(0..5000), data.slice(5000..10000));
    let id = Identification::for_robot(&leg, Level::Consistent, 1e-6)?
        .level("knee", Level::Ellipsoid)?
        .constrain(move |p, v| {
            p.add_eq(v.total_mass(), total)?;
            v.body("hip_rotor")?.add_equal(p, v.body("knee_rotor")?)?;
            Ok(())
        });
    Ok(id.identify(&train, Some(&val))?)
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let r = run(5.25)?;
    for b in &r.bodies {
        println!(
            "{:<11} {:<10} mass {:.4} kg, consistent {}",
            b.name,
            b.level.as_str(),
            b.mass,
            b.consistent
        );
    }
    let total: f64 = r.bodies.iter().map(|b| b.mass).sum();
    println!("total mass {total:.6} kg");
    let (viscous, coulomb) = r.friction("knee")?;
    println!("knee friction: viscous {viscous:.4}, Coulomb {coulomb:.4}");
    println!(
        "validation RMS {:?} N·m",
        r.validation_rms.unwrap_or_default()
    );
    Ok(())
}
