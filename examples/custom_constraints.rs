//! Writing your own convex constraint set on inertial parameters.
//!
//! Question: a 1.2 kg link is known to lie inside a 0.35 m × 0.06 m × 0.06 m
//! box (its CAD envelope), with its CoM measured at x = 0.12 m on the
//! symmetry axis. What are the smallest and largest possible moments of
//! inertia about the joint axis z through the origin? Density realizability
//! in the bounding ellipsoid (Theorem 4) plus a few linear equalities answer
//! it with two small SDPs.
//!
//! Run: `cargo run --release --example custom_constraints`

use momentlmi::conic::{Problem, Settings};
use momentlmi::moments::{Ellipsoid, check_realizable, four_point_masses_in, lmi::BodyVars};
use nalgebra::Vector3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let envelope = Ellipsoid::bounding_box(Vector3::new(0.35, 0.06, 0.06))?.transformed(
        &nalgebra::Matrix3::identity(),
        &Vector3::new(0.175, 0.0, 0.0), // box from x = 0 to x = 0.35
    );
    for maximise in [false, true] {
        let mut p = Problem::new();
        let pi = BodyVars::new(&mut p, "link");
        p.add_psd(&pi.pseudo_inertia())?; // J(π) ⪰ 0: physically consistent
        p.add_ge(pi.trace_jq(&envelope), 0.0)?; // tr(J Q) ≥ 0: inside the envelope
        p.add_eq(pi.mass(), 1.2)?; // known mass
        let [hx, hy, hz] = pi.h();
        p.add_eq(hx, 1.2 * 0.12)?; // known CoM
        p.add_eq(hy, 0.0)?;
        p.add_eq(hz, 0.0)?;
        let izz = pi.izz();
        if maximise {
            p.maximize(izz)
        } else {
            p.minimize(izz)
        }
        let sol = p.solve(&Settings::default())?;
        let sol = sol.solved()?;
        let v = pi.value(&sol)?;
        println!(
            "{} Izz about the joint axis: {:.6} kg·m² ({})",
            if maximise { "largest " } else { "smallest" },
            sol.primal_objective,
            sol.status
        );
        let r = check_realizable(&v, &envelope, 1e-7);
        println!(
            "  realizable in the envelope: {} (tr(JQ) = {:.2e})",
            r.realizable, r.trace_jq
        );
        for pm in four_point_masses_in(&v, &envelope)? {
            println!(
                "  point mass {:.4} kg at ({:+.4}, {:+.4}, {:+.4}) m",
                pm.mass, pm.position.x, pm.position.y, pm.position.z
            );
        }
    }
    Ok(())
}
