//! Time and peak memory of the streaming reduction + SDP for 10⁴, 10⁵ and
//! 10⁶ samples generated on the fly (nothing is stored): the time grows
//! linearly and the memory stays flat.
//!
//! Run: `cargo run --release --example scaling`

use momentlmi::dynamics::cheetah3;
use momentlmi::effects::Library;
use momentlmi::identify::{IdentifyOptions, Level, StreamReducer, solve_identification};
use momentlmi::sim::Effects;
use momentlmi::sim::trajectory::{Shell, Trajectory};

fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn main() {
    let leg = cheetah3::description();
    let model = &leg.model;
    let robot = Library::builtin()
        .true_robot(
            &leg,
            &Effects::parse("rotor_inertia,coulomb,viscous", &[]).unwrap(),
        )
        .unwrap();
    let tr = Trajectory::Shell(Shell::default());
    let opts = IdentifyOptions::for_robot(&leg, Level::Ellipsoid, 1e-6).unwrap();
    // one period of states, reused (the trajectory itself is not what is measured)
    let states: Vec<_> = (0..10_000)
        .map(|k| tr.state(k as f64 * 1e-3).unwrap())
        .collect();
    let taus: Vec<Vec<f64>> = states
        .iter()
        .map(|(q, qd, qdd)| {
            let one = |v: &Vec<f64>| momentlmi::data::Samples::from_rows(&[v]);
            robot.torques(&one(q), &one(qd), &one(qdd)).unwrap()[0].to_vec()
        })
        .collect();
    println!(
        "{:>10} {:>12} {:>12} {:>14}",
        "samples", "reduce [s]", "SDP [ms]", "peak RSS [MiB]"
    );
    for n in [10_000usize, 100_000, 1_000_000] {
        let t = std::time::Instant::now();
        let mut r = StreamReducer::new(model, 1024);
        for k in 0..n {
            let (q, qd, qdd) = &states[k % states.len()];
            r.push(q, qd, qdd, &taus[k % taus.len()]).unwrap();
        }
        let red = r.finish().unwrap();
        let tr = t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let s = solve_identification(model, &red, &opts).unwrap();
        println!(
            "{n:>10} {tr:>12.3} {:>12.1} {:>14.1}   ({})",
            1e3 * t.elapsed().as_secs_f64(),
            peak_rss_mib(),
            s.status
        );
    }
}
