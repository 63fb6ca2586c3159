//! Checking and repairing inertias from code (the library behind
//! `momentlmi check`).
//!
//! Run: `cargo run --release --example check_inertias`

use momentlmi::moments::{
    InertialParams, NearestOptions, Verdict, check_consistency, nearest_consistent,
};
use nalgebra::{Matrix3, Vector3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // A CAD export with principal moments (0.01, 0.01, 0.05) kg·m²: 0.01 + 0.01 < 0.05.
    let cad = InertialParams::from_mass_com_inertia(
        2.0,
        Vector3::new(0.0, 0.1, 0.0),
        Matrix3::from_diagonal(&Vector3::new(0.01, 0.01, 0.05)),
    );
    let r = check_consistency(&cad, 1e-12);
    println!(
        "CAD inertia: {:?}, worst triangle margin {:.1} %",
        r.verdict,
        100.0 * r.triangle_margin_rel()
    );
    assert_eq!(r.verdict, Verdict::TriangleViolation);
    let fixed = nearest_consistent(&cad, &NearestOptions::default())?;
    let r2 = check_consistency(&fixed.params, 1e-12);
    let (moments, _) = fixed.params.principal_moments();
    println!(
        "nearest consistent: {:?}, principal moments {:.5?} kg·m², distance {:.4} (length scale {:.3} m)",
        r2.verdict,
        moments.as_slice(),
        fixed.distance,
        fixed.length_scale
    );
    // URDF-style numbers (inertia about the CoM, rpy = 0)
    let (m, xyz, i) = fixed.params.to_urdf();
    println!(
        "<mass value=\"{m}\"/> <origin xyz=\"{} {} {}\"/>",
        xyz[0], xyz[1], xyz[2]
    );
    println!(
        "<inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" iyz=\"{}\" izz=\"{}\"/>",
        i[0], i[1], i[2], i[3], i[4], i[5]
    );
    Ok(())
}
