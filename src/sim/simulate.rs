//! Generating a data set: trajectory → true robot → measurement → offline
//! processing. The [`SimConfig`] (written beside the data as JSON) is what
//! reproduces it together with the robot description.

use super::effects::Effects;
use super::error::SimError;
use super::trajectory::Trajectory;
use super::truth::TrueRobot;
use crate::data::filter::{differentiate, filtfilt};
use crate::data::{Dataset, estimate_qdd};
use crate::dynamics::Friction;
use crate::dynamics::predict::predict_torques;
use crate::dynamics::{Model, RobotDescription, Samples};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// The most samples one simulation makes (memory stays bounded: ~ 1 kB per
/// sample for a 9-joint robot).
pub const MAX_SAMPLES: usize = 10_000_000;
/// The memory a simulation may plan for (bytes).
pub const MAX_SIM_BYTES: u64 = 8 << 30;

/// What simulating `samples` samples of `n` joints holds (bytes): the
/// dynamics' n × n matrices (mass matrix, its factor, Jacobians; a few
/// dozen) and per sample the states, torques and their filtered copies.
pub fn memory_estimate(n: usize, samples: usize) -> u64 {
    let (n, s) = (n as u64, samples as u64);
    8 * (40 * n * n + 16 * s * n)
}

fn default_link_bits() -> f64 {
    19.0
}

fn default_linear_resolution() -> f64 {
    1e-6
}

/// The largest torque noise σ (N·m) a simulation may add.
pub const MAX_NOISE_SIGMA: f64 = 1e4;

/// How a data set is made (written beside it as JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimConfig {
    /// Robot (built-in name or URDF path).
    pub robot: String,
    /// The sidecar the robot was described with (a URDF robot's), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sidecar: Option<String>,
    /// Duration (s).
    pub seconds: f64,
    /// Sampling rate (Hz).
    pub rate_hz: f64,
    /// The excitation. A sampled one that does not wrap is read from the
    /// dropped edge before the data (and any delay or compliance pre-roll)
    /// on: the data's time 0 is that far after its first sample.
    pub trajectory: Trajectory,
    /// Effects of the true robot.
    pub effects: Effects,
    /// Torque noise σ (N·m), Gaussian, white.
    pub noise_sigma: f64,
    /// Encoder counts per motor turn, for a joint with a rotor (a gear ratio
    /// N): the joint resolution is `2π / (counts · N)` (0: no quantisation
    /// on any joint).
    pub encoder_counts: f64,
    /// Bits per turn of a link-side encoder, for a revolute joint without a
    /// rotor (default 19: 2π/2¹⁹ ≈ 12 µrad, as on modern arms' joint
    /// encoders; 0: none). `None` (records made before it existed): those
    /// joints had `encoder_counts` per turn of the joint itself.
    #[serde(default)]
    pub link_encoder_bits: Option<f64>,
    /// Resolution (m) of a prismatic joint without a rotor (default 1 µm).
    /// `None` (older records): `2π / encoder_counts` m.
    #[serde(default)]
    pub linear_resolution_m: Option<f64>,
    /// Cut-off (Hz) of the zero-phase filter of the offline processing
    /// (default: 30 Hz, or 10× the top frequency of a multi-sine excitation
    /// when that is lower, at least 5 Hz; 30 Hz for a sampled trajectory).
    pub cutoff_hz: f64,
    /// Seconds simulated and processed before and after the data and then
    /// dropped, as an offline pipeline drops its filter's edges (default
    /// 0.5 s; 0 in records older than it).
    #[serde(default)]
    pub edge_seconds: f64,
    /// RNG seed.
    pub seed: u64,
    /// Whether q̇, q̈ are estimated from the (quantised) positions as the
    /// paper did offline (true unless the data are noise-free and unquantised,
    /// in which case the exact states are written).
    pub processed: bool,
}

impl SimConfig {
    /// Defaults for a robot: 1 kHz, σ = 0.3 N·m, 2¹⁴ counts per motor turn
    /// where a joint has a rotor, 19-bit link-side encoders (1 µm on a
    /// prismatic joint) where not, the cut-off for the excitation's bandwidth,
    /// 0.5 s edges, the description's excitation.
    pub fn for_robot(robot: &RobotDescription, seconds: f64, effects: Effects, seed: u64) -> Self {
        let trajectory = Trajectory::for_excitation(&robot.excitation, &robot.model, seed);
        let cutoff_hz = default_cutoff(&trajectory);
        Self {
            robot: robot.source.clone(),
            sidecar: None,
            seconds,
            rate_hz: 1000.0,
            trajectory,
            effects,
            noise_sigma: 0.3,
            encoder_counts: 16384.0,
            link_encoder_bits: Some(default_link_bits()),
            linear_resolution_m: Some(default_linear_resolution()),
            cutoff_hz,
            edge_seconds: 0.5,
            seed,
            processed: true,
        }
    }

    /// Drives the simulation along `trajectory` instead, with the cut-off
    /// default for it (30 Hz, or 10× a multi-sine's top frequency when that
    /// is lower, at least 5 Hz; 30 Hz for samples).
    pub fn with_trajectory(mut self, trajectory: Trajectory) -> Self {
        self.cutoff_hz = default_cutoff(&trajectory);
        self.trajectory = trajectory;
        self
    }

    /// Where the simulation's time 0 is on the trajectory's clock when it
    /// is needed from `before` s before time 0 to `after` s after (0 but
    /// for samples that do not wrap:
    /// [`super::sampled::SampledTrajectory::start_for`]).
    fn trajectory_start(&self, before: f64, after: f64) -> Result<f64, SimError> {
        match &self.trajectory {
            Trajectory::Sampled(s) => s.start_for(before, after),
            _ => Ok(0.0),
        }
    }

    /// The seconds of trajectory simulated before the data's time 0 (the
    /// dropped edge, when processed) and from it (the data and the edge
    /// after them; the last sample is one step before the end).
    fn time_around(&self, samples: usize) -> (f64, f64) {
        let edge = if self.processed {
            self.edge_samples()
        } else {
            0
        };
        let dt = 1.0 / self.rate_hz;
        (edge as f64 * dt, (samples + edge - 1) as f64 * dt)
    }

    /// Joint `j`'s position resolution (rad or m; 0: exact) and where its
    /// encoder is.
    pub fn encoder(&self, model: &Model, j: usize) -> (f64, &'static str) {
        use std::f64::consts::TAU;
        if self.encoder_counts <= 0.0 {
            return (0.0, "none");
        }
        if let Some(r) = model.rotor_of(j) {
            return (TAU / (self.encoder_counts * r.gear_ratio), "motor side");
        }
        // records made before the link-side settings: counts per joint turn
        let legacy = TAU / self.encoder_counts;
        if model.joints[j].kind == crate::dynamics::JointKind::Prismatic {
            return (
                self.linear_resolution_m.unwrap_or(legacy),
                "link side (linear)",
            );
        }
        match self.link_encoder_bits {
            None => (legacy, "link side"),
            Some(b) if b > 0.0 => (TAU / b.exp2(), "link side"),
            Some(_) => (0.0, "none"),
        }
    }

    /// The samples simulated before and after the data (dropped).
    pub fn edge_samples(&self) -> usize {
        (self.edge_seconds * self.rate_hz).round() as usize
    }

    /// Checks every setting; returns the number of samples.
    pub fn validate(&self, model: &Model) -> Result<usize, SimError> {
        self.check_ranges()?;
        let samples = self.check_size(model.dof())?;
        if self.trajectory.joints() != model.dof() {
            return Err(SimError::Excitation {
                expected: model.dof(),
                found: self.trajectory.joints(),
            });
        }
        if matches!(self.trajectory, Trajectory::Shell(_))
            && !crate::dynamics::leg_kinematics::has_leg_kinematics(model)
        {
            return Err(SimError::Setting {
                setting: "trajectory",
                value: f64::NAN,
                requirement: "the leg shell drives the built-in leg's foot through its inverse kinematics; this model does not have that leg's joints",
            });
        }
        let (before, after) = self.time_around(samples);
        self.trajectory_start(before, after)?;
        Ok(samples)
    }

    /// Each setting within its range.
    fn check_ranges(&self) -> Result<(), SimError> {
        let within = |setting, value: f64, ok: bool, requirement| {
            if ok {
                Ok(())
            } else {
                Err(SimError::Setting {
                    setting,
                    value,
                    requirement,
                })
            }
        };
        let positive = |v: f64| v > 0.0 && v.is_finite();
        within(
            "seconds",
            self.seconds,
            positive(self.seconds),
            "must be positive and finite",
        )?;
        within(
            "rate_hz",
            self.rate_hz,
            positive(self.rate_hz),
            "must be positive and finite",
        )?;
        within(
            "noise_sigma",
            self.noise_sigma,
            self.noise_sigma >= 0.0 && self.noise_sigma <= MAX_NOISE_SIGMA,
            "must be in [0, 1e4] N·m (the data readers refuse torques beyond ±1e8)",
        )?;
        within(
            "encoder_counts",
            self.encoder_counts,
            self.encoder_counts >= 0.0 && self.encoder_counts.is_finite(),
            "must be ≥ 0 and finite",
        )?;
        if let Some(b) = self.link_encoder_bits {
            within(
                "link_encoder_bits",
                b,
                (0.0..=64.0).contains(&b),
                "must be in [0, 64]",
            )?;
        }
        if let Some(r) = self.linear_resolution_m {
            within(
                "linear_resolution_m",
                r,
                (0.0..=1.0).contains(&r),
                "must be in [0, 1] m",
            )?;
        }
        within(
            "edge_seconds",
            self.edge_seconds,
            (0.0..=10.0).contains(&self.edge_seconds),
            "must be in [0, 10] s",
        )?;
        let cutoff_ok =
            !self.processed || (self.cutoff_hz > 0.0 && self.cutoff_hz < 0.5 * self.rate_hz);
        within(
            "cutoff_hz",
            self.cutoff_hz,
            cutoff_ok,
            "must be positive and below half the rate",
        )
    }

    /// The number of samples, within [2, [`MAX_SAMPLES`]] and the memory a
    /// simulation of `n` joints may plan for.
    fn check_size(&self, n: usize) -> Result<usize, SimError> {
        let samples = (self.seconds * self.rate_hz).round();
        if !(2.0..=MAX_SAMPLES as f64).contains(&samples) {
            return Err(SimError::Samples {
                seconds: self.seconds,
                samples,
                most: MAX_SAMPLES,
            });
        }
        let need = memory_estimate(n, samples as usize + 2 * self.edge_samples());
        if need > MAX_SIM_BYTES {
            return Err(SimError::TooLarge {
                joints: n,
                samples: samples as usize,
                needed_gib: need as f64 / (1u64 << 30) as f64,
                limit_gib: (MAX_SIM_BYTES >> 30) as f64,
            });
        }
        Ok(samples as usize)
    }
}

/// The exact states at the sample times, and the states at `t − delay`
/// (the ones the torque is measured at).
struct States {
    t: Vec<f64>,
    exact: [Samples; 3],
    delayed: [Samples; 3],
}

/// The states at the samples `first..first + samples` (times k / rate),
/// the trajectory read at `start` s on its own clock at time 0.
fn sample_states(
    model: &Model,
    cfg: &SimConfig,
    (first, samples): (isize, usize),
    (delay, start): (f64, f64),
    progress: &mut impl FnMut(usize, usize),
) -> Result<States, SimError> {
    let dt = 1.0 / cfg.rate_hz;
    let state = |t: f64| (cfg.trajectory.state(start + t)).ok_or(SimError::Workspace { t });
    let rows = || Samples::with_capacity(model.dof(), samples);
    let mut s = States {
        t: Vec::with_capacity(samples),
        exact: [rows(), rows(), rows()],
        delayed: [rows(), rows(), rows()],
    };
    for k in 0..samples {
        let t = (first + k as isize) as f64 * dt;
        let (q, qd, qdd) = state(t)?;
        let (qx, qdx, qddx) = if delay > 0.0 {
            state(t - delay)?
        } else {
            (q.clone(), qd.clone(), qdd.clone())
        };
        if !q.iter().chain(&qd).chain(&qdd).all(|v| v.is_finite()) {
            return Err(SimError::NonFinite { t });
        }
        for (i, j) in model.joints.iter().enumerate() {
            if q[i] < j.limits.0 || q[i] > j.limits.1 {
                return Err(SimError::Limits {
                    joint: j.name.clone(),
                    t,
                    q: q[i],
                });
            }
        }
        s.t.push(t);
        for (v, x) in s.exact.iter_mut().zip([q, qd, qdd]) {
            v.push(&x);
        }
        for (v, x) in s.delayed.iter_mut().zip([qx, qdx, qddx]) {
            v.push(&x);
        }
        if k % 1000 == 999 {
            progress(k + 1, samples);
        }
    }
    Ok(s)
}

/// With a compliant transmission, the links' rigid torque at the
/// motor-side state is replaced by the spring torque that actually drives them.
fn add_compliance(
    robot: &TrueRobot,
    cfg: &SimConfig,
    (s, start): (&States, f64),
    tau: &mut Samples,
) -> Result<(), SimError> {
    let Some(c) = robot.compliance() else {
        return Ok(());
    };
    let links = robot.links_model();
    let nj = links.dof();
    let [qs, qds, qdds] = &s.delayed;
    let rigid = predict_torques(&links, &Friction::zeros(nj), qs, qds, qdds)?;
    let times: Vec<f64> = s.t.iter().map(|t| start + t - robot.delay()).collect();
    let link_side = super::compliance::simulate_link_side(&links, &cfg.trajectory, &times, &c)?;
    let gain = robot.gain();
    for (k, row) in tau.iter_mut().enumerate() {
        for i in 0..nj {
            row[i] += gain * (link_side[k].2[i] - rigid[k][i]);
        }
    }
    Ok(())
}

fn add_noise(cfg: &SimConfig, tau: &mut Samples) {
    let mut rng = rand::rngs::StdRng::seed_from_u64(cfg.seed);
    if cfg.noise_sigma > 0.0 {
        let normal = Normal::new(0.0, cfg.noise_sigma).expect("σ checked by validate");
        for row in tau.iter_mut() {
            for v in row.iter_mut() {
                *v += normal.sample(&mut rng);
            }
        }
    }
}

/// Encoder quantisation ([`SimConfig::encoder`]), then the offline
/// processing: q and q̇ from the zero-phase filtered positions and their
/// derivative, q̈ from q̇.
fn process(model: &Model, cfg: &SimConfig, d: &mut Dataset) {
    for j in 0..model.dof() {
        let (res, _) = cfg.encoder(model, j);
        let raw: Vec<f64> =
            d.q.iter()
                .map(|q| {
                    if res > 0.0 {
                        (q[j] / res).round() * res
                    } else {
                        q[j]
                    }
                })
                .collect();
        let qf = filtfilt(&raw, cfg.cutoff_hz, cfg.rate_hz);
        let qd = filtfilt(&differentiate(&raw, &d.t), cfg.cutoff_hz, cfg.rate_hz);
        for k in 0..d.len() {
            d.q[k][j] = qf[k];
            d.qd[k][j] = qd[k];
        }
    }
    d.qdd = estimate_qdd(&d.t, &d.qd, cfg.cutoff_hz);
}

/// Simulates `truth`, the true robot of `robot` built with the effects
/// `cfg.effects` records (an effect library builds it:
/// [`crate::effects::Library::simulate`] does both); `progress(done,
/// total)` is called every 1000 samples simulated (the total includes the
/// dropped edges).
pub fn simulate_with(
    robot: &RobotDescription,
    truth: &TrueRobot,
    cfg: &SimConfig,
    mut progress: impl FnMut(usize, usize),
) -> Result<Dataset, SimError> {
    let model = &robot.model;
    let samples = cfg.validate(model)?;
    if truth.effects() != &cfg.effects {
        return Err(SimError::EffectsRecord {
            truth: truth.effects().on.clone(),
            config: cfg.effects.on.clone(),
        });
    }
    let edge = if cfg.processed { cfg.edge_samples() } else { 0 };
    let span = (-(edge as isize), samples + 2 * edge);
    let start = trajectory_start(cfg, truth, samples)?;
    let states = sample_states(model, cfg, span, (truth.delay(), start), &mut progress)?;
    let [qs, qds, qdds] = &states.delayed;
    let mut tau = truth.torques_at(&states.t, qs, qds, qdds)?;
    add_compliance(truth, cfg, (&states, start), &mut tau)?;
    add_noise(cfg, &mut tau);
    let [q, qd, qdd] = states.exact;
    let mut d = Dataset {
        joints: model.joint_names().iter().map(|s| s.to_string()).collect(),
        t: states.t,
        q,
        qd,
        qdd,
        tau,
        segments: vec![],
        base: None,
        contacts: vec![],
    };
    if cfg.processed {
        process(model, cfg, &mut d);
    }
    d.keep(edge..edge + samples);
    // the kept samples' times, exactly k / rate from 0
    d.t = (0..samples).map(|k| k as f64 / cfg.rate_hz).collect();
    within_reader_limits(&d)?;
    // the total counts the dropped edges too
    progress(span.1, span.1);
    Ok(d)
}

/// Where the data's time 0 is on the trajectory's clock: the trajectory is
/// needed from the dropped edge before it, less the delay and the compliant
/// link side's pre-roll, to the edge after the data.
fn trajectory_start(cfg: &SimConfig, truth: &TrueRobot, samples: usize) -> Result<f64, SimError> {
    let (mut before, mut after) = cfg.time_around(samples);
    let delay = truth.delay();
    before += delay.max(0.0);
    after += (-delay).max(0.0);
    if truth.compliance().is_some() {
        before += super::compliance::PRE_ROLL_S;
    }
    cfg.trajectory_start(before, after)
}

/// The default cut-off of the offline filter for `trajectory` (Hz).
fn default_cutoff(trajectory: &Trajectory) -> f64 {
    trajectory
        .top_hz()
        .map_or(30.0, |f| (10.0 * f).clamp(5.0, 30.0))
}

/// The data must be readable back: every value finite and within the CSV
/// readers' bounds (an extreme gravity, pose or effect can push torques or
/// positions beyond them).
fn within_reader_limits(d: &Dataset) -> Result<(), SimError> {
    use crate::data::csv::MAX_ABS_VALUE;
    for (what, v) in [("q", &d.q), ("qd", &d.qd), ("qdd", &d.qdd), ("tau", &d.tau)] {
        for (k, row) in v.iter().enumerate() {
            if let Some((j, x)) = row
                .iter()
                .enumerate()
                .find(|(_, x)| !(x.is_finite() && x.abs() <= MAX_ABS_VALUE))
            {
                return Err(SimError::OutOfRange {
                    what: format!("{what}_{}", d.joints[j]),
                    t: d.t[k],
                    value: *x,
                });
            }
        }
    }
    Ok(())
}
