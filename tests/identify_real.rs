//! Identification on the KUKA LWR4+'s real runs copied into
//! `robots/kuka-lwr4` (no test here needs `../shared`).

#[path = "support/rank.rs"]
mod rank;

use momentlmi::data::{Mapping, ReadOptions, read_logs};
use momentlmi::dynamics::{RobotDescription, regressor_batch};
use momentlmi::identify::{Identification, Level};
use std::path::Path;

/// The KUKA with its sidecar, and its run `k` read with the sidecar's mapping.
fn kuka_run(k: u32) -> (RobotDescription, momentlmi::data::Dataset) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/kuka-lwr4");
    let robot = momentlmi::dynamics::robots::load_robot(
        root.join("kuka_lwr4.urdf").to_str().unwrap(),
        Some(&root.join("kuka_lwr4.toml")),
    )
    .unwrap();
    let mapping = Mapping::read(robot.data_mapping.as_ref().unwrap()).unwrap();
    let o = ReadOptions {
        mapping: Some(mapping),
        ..ReadOptions::default()
    };
    let path = root.join(format!("data/measurements_{k}.npz"));
    let data = read_logs(&[&path], &robot.model.joint_names(), &o)
        .unwrap()
        .data;
    (robot, data)
}

/// The rank reported is the stacked regressor's own: its singular values
/// (columns scaled to unit norm, a column at rounding level zeroed) above
/// 1e-8 of the largest, 57 of 84 on run 1 (the next is ~1e-16; scaled up,
/// lwr_2_link.hy's rounding-level column counted as a 58th). Taken from the Gram matrix by an
/// eigen-decomposition, an unexcited direction came out at ~1e-8 and the
/// rank as 59.
#[test]
fn the_reported_rank_is_the_stacked_regressors() {
    let (robot, d) = kuka_run(1);
    let r = Identification::for_robot(&robot, Level::None, 1e-6)
        .unwrap()
        .fit(&d)
        .unwrap();
    let flat = |s: &momentlmi::dynamics::Samples| s.as_flat().to_vec();
    let y = regressor_batch(&robot.model, &flat(&d.q), &flat(&d.qd), &flat(&d.qdd)).unwrap();
    let p = robot.model.regressor_columns();
    // lwr_2_link.hy's column is rounding (~6e-15): zero, not scaled up
    let s = rank::scaled_singular_values(&y, p);
    let rank = s.iter().filter(|&&v| v > 1e-8 * s[0]).count();
    assert_eq!(rank, 57, "singular values {s:?}");
    assert_eq!(
        (r.identifiability.rank, r.identifiability.columns),
        (rank, p)
    );
    assert_eq!(r.identifiability.directions.len(), p - rank);
}
