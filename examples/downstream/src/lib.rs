//! A downstream program that uses the `momentlmi` library API alone: load a
//! robot description, simulate data, identify with the paper's ellipsoid
//! constraints, then ask a custom question of the identified body with the
//! conic layer.
//!
//! Run: `cargo run --release -p momentlmi-downstream --example leg`

use momentlmi::conic::{Problem, Settings};
use momentlmi::dynamics::robots::load_robot;
use momentlmi::effects::simulate;
use momentlmi::identify::{IdentifyOptions, Level, identify};
use momentlmi::moments::{InertialParams, lmi::BodyVars};
use momentlmi::sim::{Effects, SimConfig};

/// What the program found.
#[derive(Debug)]
pub struct Report {
    /// Held-out RMS per joint (N·m).
    pub validation_rms: Vec<f64>,
    /// Every body satisfies its constraints.
    pub constraints_satisfied: bool,
    /// The knee link's identified mass (kg).
    pub knee_mass: f64,
    /// The largest Izz the knee link could have with that mass, inside its
    /// bounding ellipsoid (kg·m²).
    pub knee_izz_max: f64,
    /// Its identified Izz (kg·m²).
    pub knee_izz: f64,
}

/// Simulates `seconds` of the built-in leg and identifies it.
pub fn run(seconds: f64) -> Result<Report, Box<dyn std::error::Error>> {
    let leg = load_robot("cheetah3-leg", None)?;
    let effects = Effects::new(["rotor_inertia", "coulomb", "viscous"]);
    let data = simulate(
        &leg,
        &SimConfig::for_robot(&leg, seconds, effects, 11),
        |_, _| {},
    )?;
    let half = data.len() / 2;
    let opts = IdentifyOptions::for_robot(&leg, Level::Ellipsoid, 1e-6)?;
    let r = identify(
        &leg.model,
        &data.slice(0..half),
        Some(&data.slice(half..data.len())),
        &opts,
    )?;
    let knee = InertialParams(r.bodies[2].params);
    // a custom constraint set: the knee's mass as identified, consistent,
    // inside its ellipsoid; how large can its Izz be?
    let ellipsoid = leg.single_ellipsoids()?[2];
    let mut p = Problem::new();
    let body = BodyVars::new(&mut p, "knee");
    body.add_realizable(&mut p, &ellipsoid)?;
    p.add_eq(body.mass(), knee.mass())?;
    p.maximize(body.izz());
    let sol = p.solve(&Settings::default())?.solved()?;
    Ok(Report {
        validation_rms: r.validation_rms.unwrap_or_default(),
        constraints_satisfied: r.constraints_satisfied,
        knee_mass: knee.mass(),
        knee_izz_max: sol.eval(&body.izz())?,
        knee_izz: knee.0[9],
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_library_alone_identifies_and_answers_a_custom_question() {
        let r = super::run(10.0).unwrap();
        assert!(r.constraints_satisfied);
        // σ = 0.3 N·m of torque noise: the held-out fit sits near it
        assert!(
            r.validation_rms.iter().all(|&v| v < 0.45),
            "{:?}",
            r.validation_rms
        );
        // the bound is the one of a point mass at the ellipsoid's farthest
        // point from the z axis: x = 0.12 m on the knee's ellipsoid
        // (centre (0, 0, −0.16), semi-axes 0.12 × 0.09 × 0.32)
        let want = r.knee_mass * 0.12 * 0.12;
        assert!(
            (r.knee_izz_max - want).abs() < 1e-6 * want,
            "{} vs {want}",
            r.knee_izz_max
        );
        // and the identified body is inside it
        assert!(
            r.knee_mass > 0.0 && r.knee_izz <= r.knee_izz_max + 1e-9,
            "{r:?}"
        );
    }
}
