//! A trajectory given as samples: (q, q̇, q̈) of every joint at a uniform
//! rate, read from a data file (`t, q_<joint>…, qd_<joint>…, qdd_<joint>…`,
//! SI units; [`crate::data::csv`]) or taken from a [`Dataset`].
//!
//! Between samples k and k+1 (step h, s = (t − t_k)/h ∈ [0, 1]) each joint
//! follows the quintic Hermite polynomial that matches q, q̇, q̈ at both ends:
//!
//! ```text
//! p(s) = c₀ + c₁s + c₂s² + c₃s³ + c₄s⁴ + c₅s⁵,   Δ = q₁ − q₀, V = q̇h, A = q̈h²
//! c₀ = q₀, c₁ = V₀, c₂ = A₀/2
//! c₃ =  10Δ − 6V₀ − 4V₁ − (3A₀ −  A₁)/2
//! c₄ = −15Δ + 8V₀ + 7V₁ + (3A₀ − 2A₁)/2
//! c₅ =   6Δ − 3V₀ − 3V₁ − ( A₀ −  A₁)/2
//! ```
//!
//! so q(t) = p(s), q̇ = p′(s)/h, q̈ = p″(s)/h² (consistent with each other,
//! continuous to q̈ across samples, exact for quintics).
//!
//! **Periodic** motion (the last sample leads into the first one step later
//! without a jump: the quintic between them stays within [`WRAP_FACTOR`] ×
//! each joint's largest |q̇| and |q̈|) has period N·h for N samples, and time wraps modulo it (a last
//! sample that repeats the first, t = 0 … T inclusive, is dropped and the
//! rest is checked so).
//! Otherwise the trajectory exists only on [t₀, t_{N−1}]: the simulation
//! must fit inside it ([`SampledTrajectory::start_for`]).

use super::error::{SimError, TrajectoryProblem};
use crate::data::{Dataset, ReadOptions, Samples, read_as_csv, read_logs};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// How far (a fraction of the step) a time stamp may be off the uniform
/// grid, and a step off the median step.
pub const UNIFORM_TOLERANCE: f64 = 0.01;

/// How close (a fraction of each quantity's scale: the largest deviation of
/// any joint's q, q̇ or q̈ from that joint's mean) a last sample must come
/// to the first to be taken as its repeat (a file from t = 0 to T
/// inclusive).
pub const PERIODIC_TOLERANCE: f64 = 1e-2;

/// The wrap from the last sample to the first may reach this multiple of a
/// joint's largest |q̇| and |q̈| in the file, no more
/// (`continues_into_first`).
pub const WRAP_FACTOR: f64 = 1.5;

/// (q, q̇, q̈) of every joint at a uniform rate; [`Self::state`] interpolates.
///
/// Serialised (in a simulation's record) as its source, sample count, rate
/// and whether it wraps; the samples themselves are not (a record read
/// back has none: [`Self::state`] is then `None`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SampledTrajectory {
    /// Where the samples came from (the file).
    pub source: String,
    /// Number of samples N.
    pub samples: usize,
    /// Sampling rate 1/h (Hz).
    pub rate_hz: f64,
    /// Whether the motion is periodic (period N·h) and time wraps.
    pub wraps: bool,
    /// The time of the first sample (s, the file's clock).
    #[serde(skip)]
    first_t: f64,
    #[serde(skip)]
    q: Samples,
    #[serde(skip)]
    qd: Samples,
    #[serde(skip)]
    qdd: Samples,
}

impl SampledTrajectory {
    /// Reads a trajectory file for the robot's `joints` (their order): a
    /// CSV (or `.npz`/`.npy`, [`read_logs`]) with `t` and `q_`, `qd_`, `qdd_`
    /// of every joint in the format's own names (any column order; `tau_`
    /// and other columns ignored), uniformly sampled.
    ///
    /// Errors name the file: its reader's (a missing column, a bad value,
    /// time not increasing: row and column), a column of a joint the robot
    /// lacks, no `qdd_` columns, time stamps off the uniform grid (the row).
    pub fn read(path: &Path, joints: &[&str]) -> Result<Self, SimError> {
        let name = path.display().to_string();
        if read_as_csv(path) {
            check_header(path, &name, joints)?;
        }
        let opts = ReadOptions {
            require_tau: false,
            ..ReadOptions::default()
        };
        let reading = read_logs(&[path], joints, &opts)?;
        if !reading.files.iter().all(|f| f.taken_as_prepared) {
            return Err(problem(&name, TrajectoryProblem::NoAccelerations));
        }
        Self::from_dataset(&reading.data, joints, &name)
    }

    /// The samples of `d` (q, q̇, q̈ of each of `joints`, matched by name),
    /// `source` naming them in errors and the record. Times must increase
    /// uniformly (each step within [`UNIFORM_TOLERANCE`] of the median step,
    /// each time within it of the grid from the first to the last).
    pub fn from_dataset(d: &Dataset, joints: &[&str], source: &str) -> Result<Self, SimError> {
        let n = d.len();
        if n < 2 {
            return Err(problem(
                source,
                TrajectoryProblem::TooFewSamples { samples: n },
            ));
        }
        if d.qd.len() != n || d.qdd.len() != n {
            return Err(problem(source, TrajectoryProblem::NoAccelerations));
        }
        let columns = match_joints(&d.joints, joints, source)?;
        let step = uniform_step(&d.t, source)?;
        let pick = |s: &Samples| -> Samples {
            s.iter()
                .map(|row| columns.iter().map(|&c| row[c]).collect())
                .collect()
        };
        let mut out = Self {
            source: source.to_string(),
            samples: n,
            rate_hz: 1.0 / step,
            wraps: false,
            first_t: d.t[0],
            q: pick(&d.q),
            qd: pick(&d.qd),
            qdd: pick(&d.qdd),
        };
        out.wraps = out.continues_into_first();
        if !out.wraps && n > 2 && out.last_repeats_first() {
            // t = 0 … T inclusive: the last sample is the first one period on
            let mut period = out.clone();
            for s in [&mut period.q, &mut period.qd, &mut period.qdd] {
                s.keep(0..n - 1);
            }
            period.samples = n - 1;
            if period.continues_into_first() {
                period.wraps = true;
                return Ok(period);
            }
        }
        Ok(out)
    }

    /// Number of joints.
    pub fn joints(&self) -> usize {
        self.q.width()
    }

    /// The step h (s).
    pub fn step(&self) -> f64 {
        1.0 / self.rate_hz
    }

    /// The time the samples cover (s): (N − 1)·h; a periodic one's period
    /// is N·h.
    pub fn span_s(&self) -> f64 {
        (self.samples.saturating_sub(1)) as f64 * self.step()
    }

    /// (q, q̇, q̈) at `t` s after the first sample (rad, rad/s, rad/s² or
    /// m, m/s, m/s²); `None` outside [0, span] unless it wraps, or when
    /// the samples are absent (a record read back).
    pub fn state(&self, t: f64) -> Option<(Vec<f64>, Vec<f64>, Vec<f64>)> {
        let n = self.q.len();
        if n < 2 || !t.is_finite() {
            return None;
        }
        let x = t * self.rate_hz;
        let (k, s) = if self.wraps {
            let x = x.rem_euclid(n as f64);
            let k = (x.floor() as usize).min(n - 1);
            (k, x - k as f64)
        } else {
            let last = (n - 1) as f64;
            if !(-1e-6..=last + 1e-6).contains(&x) {
                return None;
            }
            let x = x.clamp(0.0, last);
            let k = (x.floor() as usize).min(n - 2);
            (k, x - k as f64)
        };
        Some(self.hermite(k, (k + 1) % n, s))
    }

    /// Where the simulation's time 0 is (s after the first sample) when it
    /// needs the trajectory from `before` s before it to `after` s after:
    /// 0 when it wraps, else `before`, if the samples cover that much.
    pub fn start_for(&self, before: f64, after: f64) -> Result<f64, SimError> {
        let slack = 1e-9 * self.step();
        if self.wraps {
            return Ok(0.0);
        }
        if before + after <= self.span_s() + slack {
            return Ok(before);
        }
        Err(problem(
            &self.source,
            TrajectoryProblem::TooShort {
                first_s: self.first_t,
                last_s: self.first_t + self.span_s(),
                before_s: before,
                after_s: after,
            },
        ))
    }

    /// The quintic from sample `a` to sample `b` at `s` (0 at `a`, 1 at
    /// `b`; beyond 1 it extrapolates).
    fn hermite(&self, a: usize, b: usize, s: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let h = self.step();
        let nj = self.joints();
        let (mut q, mut qd, mut qdd) = (vec![0.0; nj], vec![0.0; nj], vec![0.0; nj]);
        for j in 0..nj {
            let (v0, v1) = (self.qd[a][j] * h, self.qd[b][j] * h);
            let (a0, a1) = (self.qdd[a][j] * h * h, self.qdd[b][j] * h * h);
            let d = self.q[b][j] - self.q[a][j];
            let c = [
                self.q[a][j],
                v0,
                0.5 * a0,
                10.0 * d - 6.0 * v0 - 4.0 * v1 - 0.5 * (3.0 * a0 - a1),
                -15.0 * d + 8.0 * v0 + 7.0 * v1 + 0.5 * (3.0 * a0 - 2.0 * a1),
                6.0 * d - 3.0 * (v0 + v1) - 0.5 * (a0 - a1),
            ];
            q[j] = c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * (c[4] + s * c[5]))));
            let dp = c[1] + s * (2.0 * c[2] + s * (3.0 * c[3] + s * (4.0 * c[4] + s * 5.0 * c[5])));
            let ddp = 2.0 * c[2] + s * (6.0 * c[3] + s * (12.0 * c[4] + s * 20.0 * c[5]));
            qd[j] = dp / h;
            qdd[j] = ddp / (h * h);
        }
        (q, qd, qdd)
    }

    /// Whether the last sample leads into the first one step later without
    /// a jump: on the wrap interval's quintic (from the last sample's q, q̇,
    /// q̈ to the first's) no joint's |q̇| or |q̈| passes [`WRAP_FACTOR`] ×
    /// that joint's largest in the file. A jump of δ in q makes |q̈| ≈ 6δ/h²
    /// there; rounding in the written digits does not.
    fn continues_into_first(&self) -> bool {
        let n = self.q.len();
        let peak = |s: &Samples, j: usize| s.iter().map(|r| r[j].abs()).fold(0.0, f64::max);
        let limits: Vec<(f64, f64)> = (0..self.joints())
            .map(|j| {
                (
                    WRAP_FACTOR * peak(&self.qd, j) + 1e-9,
                    WRAP_FACTOR * peak(&self.qdd, j) + 1e-9,
                )
            })
            .collect();
        (0..=16).all(|i| {
            let (_, qd, qdd) = self.hermite(n - 1, 0, i as f64 / 16.0);
            (qd.iter().zip(&qdd).zip(&limits))
                .all(|((v, a), (lv, la))| v.abs() <= *lv && a.abs() <= *la)
        })
    }

    /// Whether the last sample is the first again (a file from t = 0 to T
    /// inclusive).
    fn last_repeats_first(&self) -> bool {
        let n = self.q.len();
        let last = |s: &Samples| s[n - 1].to_vec();
        self.near_first((last(&self.q), last(&self.qd), last(&self.qdd)))
    }

    /// Whether `x` is the first sample, each of q, q̇, q̈ within
    /// [`PERIODIC_TOLERANCE`] of its scale.
    fn near_first(&self, (q, qd, qdd): (Vec<f64>, Vec<f64>, Vec<f64>)) -> bool {
        [(&self.q, q), (&self.qd, qd), (&self.qdd, qdd)]
            .iter()
            .all(|(series, x)| {
                let tol = PERIODIC_TOLERANCE * scale(series) + 1e-12;
                x.iter()
                    .zip(&series[0])
                    .all(|(x, first)| (x - first).abs() <= tol)
            })
    }
}

fn problem(source: &str, problem: TrajectoryProblem) -> SimError {
    SimError::TrajectoryFile {
        path: source.to_string(),
        problem,
    }
}

/// The largest deviation of any joint's series from its mean.
fn scale(series: &Samples) -> f64 {
    (0..series.width())
        .map(|j| {
            let c = series.column(j);
            let mean = c.iter().sum::<f64>() / c.len() as f64;
            c.iter().map(|x| (x - mean).abs()).fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// Where each of `joints` is among `have` (every one present, nothing else).
fn match_joints(have: &[String], joints: &[&str], source: &str) -> Result<Vec<usize>, SimError> {
    if let Some(extra) = have.iter().find(|h| !joints.contains(&h.as_str())) {
        return Err(problem(
            source,
            TrajectoryProblem::UnknownJoint {
                column: format!("q_{extra}"),
                joints: joints.iter().map(|j| j.to_string()).collect(),
            },
        ));
    }
    joints
        .iter()
        .map(|j| {
            have.iter().position(|h| h == j).ok_or_else(|| {
                problem(
                    source,
                    TrajectoryProblem::MissingJoint {
                        joint: j.to_string(),
                    },
                )
            })
        })
        .collect()
}

/// The uniform step of `t` (s): each step within [`UNIFORM_TOLERANCE`] of
/// the median step, then each time within it of the grid from the first
/// time to the last; the first row off names itself.
fn uniform_step(t: &[f64], source: &str) -> Result<f64, SimError> {
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let median = steps[steps.len() / 2];
    let off = |k: usize, expected: f64, step: f64| {
        problem(
            source,
            TrajectoryProblem::NotUniform {
                row: k + 1,
                t: t[k],
                expected,
                step,
            },
        )
    };
    if let Some(k) = (1..t.len()).find(|&k| {
        let step = t[k] - t[k - 1];
        !(step > 0.0 && (step - median).abs() <= UNIFORM_TOLERANCE * median)
    }) {
        return Err(off(k, t[k - 1] + median, median));
    }
    let step = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let grid = |k: usize| t[0] + k as f64 * step;
    if let Some(k) = (0..t.len()).find(|&k| (t[k] - grid(k)).abs() > UNIFORM_TOLERANCE * step) {
        return Err(off(k, grid(k), step));
    }
    Ok(step)
}

/// A CSV's header: at least one `qdd_` column, and no `q_`, `qd_`, `qdd_`
/// or `tau_` column for a joint the robot lacks (the reader ignores
/// columns it does not need; a trajectory's must all be the robot's). A
/// header that cannot be read is left to the reader to report.
fn check_header(path: &Path, source: &str, joints: &[&str]) -> Result<(), SimError> {
    use std::io::{BufRead, Read};
    let Ok(file) = std::fs::File::open(path) else {
        return Ok(());
    };
    let mut line = vec![];
    let limited = file.take(crate::data::csv::MAX_LINE_BYTES as u64);
    if std::io::BufReader::new(limited)
        .read_until(b'\n', &mut line)
        .is_err()
    {
        return Ok(());
    }
    let mut rdr = ::csv::ReaderBuilder::new()
        .trim(::csv::Trim::All)
        .from_reader(line.as_slice());
    let Ok(header) = rdr.headers() else {
        return Ok(());
    };
    let joint_of = |c: &str| {
        ["qdd_", "qd_", "q_", "tau_"]
            .iter()
            .find_map(|p| c.strip_prefix(p).map(|j| (*p, j.to_string())))
    };
    let mut accelerations = false;
    for c in header.iter() {
        let Some((prefix, joint)) = joint_of(c) else {
            continue;
        };
        if !joints.contains(&joint.as_str()) {
            return Err(problem(
                source,
                TrajectoryProblem::UnknownJoint {
                    column: c.to_string(),
                    joints: joints.iter().map(|j| j.to_string()).collect(),
                },
            ));
        }
        accelerations |= prefix == "qdd_";
    }
    if !accelerations {
        return Err(problem(source, TrajectoryProblem::NoAccelerations));
    }
    Ok(())
}
