//! Your own convex constraint set on two bodies' inertial parameters.
//!
//! Question: a 3 kg two-link assembly — the split of the mass between the
//! links is unknown — has link A inside a 0.35 × 0.06 × 0.06 m box and link B
//! inside a 0.25 × 0.05 × 0.05 m box (CAD envelopes, each link's frame at
//! its joint), and both CoMs were measured on the links' axes at x = 0.14 m
//! and x = 0.10 m. What are the smallest and largest possible moments of
//! inertia of link A about its joint axis z, if each link weighs at least 1 kg?
//! Density realizability in each box's bounding ellipsoid (Theorem 4: the
//! convex relaxation the paper uses; the mass may reach beyond the box's
//! corners into the ellipsoid) and a few linear equalities answer it with
//! two small SDPs; each optimum is then four point masses in the ellipsoid.
//!
//! Run: `cargo run --release --example custom_constraints`
//!
//! In CVXPY one writes the pseudo-inertia of each body by hand (`cp.bmat`
//! with ½tr(Ī)·1 − Ī, h, m: ~10 lines per body) before the 10 lines of
//! model below.

use momentlmi::conic::{Problem, Settings};
use momentlmi::moments::{
    Ellipsoid, InertialParams, PointMass, four_point_masses_in, lmi::BodyVars,
};
use nalgebra::{Matrix3, Vector3};

/// An envelope box from x = 0 to x = `length` on the x axis.
fn envelope(length: f64, side: f64) -> Result<Ellipsoid, Box<dyn std::error::Error>> {
    let e = Ellipsoid::bounding_box(Vector3::new(length, side, side))?;
    Ok(e.transformed(&Matrix3::identity(), &Vector3::new(length / 2.0, 0.0, 0.0)))
}

/// The extreme link A (Izz about its joint axis) and its point masses.
pub fn run(maximise: bool) -> Result<(InertialParams, Vec<PointMass>), Box<dyn std::error::Error>> {
    let (ea, eb) = (envelope(0.35, 0.06)?, envelope(0.25, 0.05)?);
    let mut p = Problem::new();
    let (a, b) = (BodyVars::new(&mut p, "A"), BodyVars::new(&mut p, "B"));
    a.add_realizable(&mut p, &ea)?;
    b.add_realizable(&mut p, &eb)?;
    p.add_eq(a.mass() + b.mass(), 3.0)?;
    p.add_ge(a.mass(), 1.0)?;
    p.add_ge(b.mass(), 1.0)?;
    a.add_com(&mut p, Vector3::new(0.14, 0.0, 0.0))?;
    b.add_com(&mut p, Vector3::new(0.10, 0.0, 0.0))?;
    if maximise {
        p.maximize(a.izz())
    } else {
        p.minimize(a.izz())
    }
    let sol = p.solve(&Settings::default())?.solved()?;
    let link = a.value(&sol)?;
    Ok((link, four_point_masses_in(&link, &ea)?.to_vec()))
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    for maximise in [false, true] {
        let (link, points) = run(maximise)?;
        println!(
            "{} Izz of link A: {:.6} kg·m² (mass {:.3} kg)",
            if maximise { "largest " } else { "smallest" },
            link.0[9],
            link.mass()
        );
        for pm in points {
            println!(
                "  point mass {:.4} kg at ({:+.4}, {:+.4}, {:+.4}) m",
                pm.mass, pm.position.x, pm.position.y, pm.position.z
            );
        }
    }
    Ok(())
}
