//! The compliance hypotheses (`elasticity`, `backlash`): the links driven
//! from the measured motor side θ(t) through a spring–damper per joint
//! (stiffness `K_i` N·m/rad, damping `D_i` N·m·s/rad, dead-band half-width
//! `b_i` rad; `b = 0` for elasticity), fitted on the training part.
//!
//! The link side is the current model's [`Model::link_side`] (rotor housings
//! welded to their mounts, rotor spin on the motor side). Its deflection
//! `x = θ − q_L` is small, so the link dynamics are linearised along the
//! measured motion (precomputed once per data set, [`Linearisation`]):
//!
//! ```text
//! M(θ) ẍ = τ_L(θ, θ̇, θ̈) − G x − C ẋ − τ_s(x, ẋ)
//! τ_s,i = K_i dz(x_i, b_i) + D_i ẋ_i [|x_i| > b_i]
//! G = ∂τ_L/∂q,  C = ∂τ_L/∂q̇  (at the measured state)
//! ```
//!
//! which is ~100× cheaper to integrate than the full link dynamics (RK4,
//! one step per sample, the mass matrix factored once per step's middle and
//! end and shared by the four stages; a step in which a joint enters or leaves its dead
//! band is redone in 16 substeps, since the spring force has a kink there),
//! so the hypothesis can be searched:
//!
//! 1. a grid shared by every joint over K (15 values, 150 … 8,000 N·m/rad),
//!    damping ratio ζ (0.05, 0.15, 0.4) and, for backlash, b (13 values,
//!    0.001 … 0.023 rad), on the first 3 s of the training part; each joint
//!    takes the grid point that explains its own residual best (scaled by
//!    its best coefficient, so the grid judges timing, not amplitude);
//! 2. coordinate descent over the whole training part (one sweep for
//!    elasticity, two for backlash): per joint a local (K_i, D_i, b_i) grid
//!    (3 × 3 for elasticity, 5 × 5 × 3 for backlash), then the axial split
//!    s_i at a fixed ringing frequency K_i / (M_ii + s_i);
//! 3. Levenberg–Marquardt on (ln K_i, ln D_i, b_i, s_i).
//!
//! The damping matters as much as K: the spring–damper's torque jumps by
//! D ẋ at each impact. The candidate's columns are, per joint, the torque
//! the hypothesis changes: `τ_s − τ_L(θ)`. A rigid model cannot tell how the
//! inertia about a joint axis is shared between the link and the rotor (the
//! rotor's `N² I_zz` and the link's axial inertia enter rigid torques as one
//! sum), but the link's ringing depends on it, hence the fitted shift s_i.

use super::candidates::{Candidate, Columns};
use crate::data::Dataset;
use crate::dynamics::{DynamicsError, Model};
use crate::sim::compliance::Compliance;
use nalgebra::DMatrix;
use rayon::prelude::*;

/// Integration substeps per sample interval (RK4).
const SUBSTEPS: usize = 1;
/// Substeps for a sample interval in which a joint enters or leaves its dead
/// band.
const REFINED: usize = 16;
/// The hypothesis starts in quasi-static deflection at the first sample;
/// its start-up transient is left out of the fit and the columns for this
/// long (s).
pub const WARM_UP: f64 = 0.3;
/// The grid search uses this much of the training part after the warm-up (s).
const SEARCH_WINDOW: f64 = 3.0;
/// The stage-1 grid: stiffness 150 · K_STEPʲ N·m/rad (j < GRID_K, up to
/// about 8,000), dead band 0.001 · B_STEPʲ rad (j < GRID_B, up to 0.023).
const GRID_K: usize = 15;
const K_STEP: f64 = 1.33;
const GRID_B: usize = 13;
/// Sweeps of the coordinate descent (stage 2): the dead band's rougher cost
/// needs two.
const SWEEPS: [usize; 2] = [1, 2];
const B_STEP: f64 = 1.3;

/// Per-joint transmission parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Transmission {
    /// Stiffness K_i (N·m/rad).
    pub stiffness: Vec<f64>,
    /// Damping D_i (N·m·s/rad).
    pub damping: Vec<f64>,
    /// Dead-band half-width b_i (rad).
    pub backlash: Vec<f64>,
    /// Axial inertia moved from the rotor to link i (kg·m²).
    pub axial_shift: Vec<f64>,
}

impl Transmission {
    /// The transmitted torque of joint i at deflection x and rate xd.
    #[inline]
    pub fn torque(&self, i: usize, x: f64, xd: f64) -> f64 {
        Compliance {
            stiffness: self.stiffness[i],
            damping: self.damping[i],
            backlash: self.backlash[i],
        }
        .torque(x, xd)
    }
}

/// The link dynamics linearised along the measured motion, per sample.
pub struct Linearisation {
    n: usize,
    t: Vec<f64>,
    /// `M(θ)`, row-major n×n per sample.
    m: Vec<Vec<f64>>,
    /// `τ_L(θ, θ̇, θ̈)` per sample.
    tau: Vec<Vec<f64>>,
    /// `∂τ_L/∂q`, row-major.
    g: Vec<Vec<f64>>,
    /// `∂τ_L/∂q̇`, row-major.
    c: Vec<Vec<f64>>,
    /// Per joint i: `∂M/∂s_i` (row-major) and `∂τ_L/∂s_i` per sample, for a
    /// unit axial inertia `a_i a_iᵀ` added to link i.
    dm: Vec<Vec<Vec<f64>>>,
    dtau: Vec<Vec<Vec<f64>>>,
    /// Link-side `M_ii` averaged over the motion (kg·m²).
    pub axial: Vec<f64>,
}

/// The Cholesky factor of the small SPD matrix `a` in place (row-major,
/// lower triangle); `false` if it is not positive definite.
fn cholesky(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    true
}

/// Solves `L Lᵀ y = f` in place with the factor of [`cholesky`].
fn cholesky_solve(l: &[f64], f: &mut [f64], n: usize) {
    for i in 0..n {
        let mut s = f[i];
        for k in 0..i {
            s -= l[i * n + k] * f[k];
        }
        f[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = f[i];
        for k in i + 1..n {
            s -= l[k * n + i] * f[k];
        }
        f[i] = s / l[i * n + i];
    }
}

/// The linearised dynamics at one instant: the factored mass matrix, G, C
/// and τ_L, interpolated between two samples.
#[derive(Clone)]
struct Node {
    chol: Vec<f64>,
    g: Vec<f64>,
    c: Vec<f64>,
    tau: Vec<f64>,
}

impl Node {
    fn new(n: usize) -> Self {
        Self {
            chol: vec![0.0; n * n],
            g: vec![0.0; n * n],
            c: vec![0.0; n * n],
            tau: vec![0.0; n],
        }
    }

    /// `ẋ` for the state `x = (x, ẋ)`: `M ẍ = τ_L − G x − C ẋ − τ_s`.
    fn rhs(&self, p: &Transmission, x: &[f64], dx: &mut [f64]) {
        let n = self.tau.len();
        for i in 0..n {
            let mut s = self.tau[i] - p.torque(i, x[i], x[n + i]);
            let (g, c) = (&self.g[i * n..(i + 1) * n], &self.c[i * n..(i + 1) * n]);
            for j in 0..n {
                s -= g[j] * x[j] + c[j] * x[n + j];
            }
            dx[n + i] = s;
        }
        cholesky_solve(&self.chol, &mut dx[n..], n);
        dx[..n].copy_from_slice(&x[n..]);
    }
}

impl Linearisation {
    /// Precomputes along the data (the link side of `model`).
    pub fn new(model: &Model, d: &Dataset) -> Result<Self, DynamicsError> {
        use crate::dynamics::{Data, crba, rnea};
        let links = model.link_side();
        let n = links.dof();
        // unit axial inertia on link i only
        let units: Vec<Model> = (0..n)
            .map(|i| {
                let mut u = links.clone();
                for (j, joint) in u.joints.iter_mut().enumerate() {
                    joint.inertia = if i == j {
                        let a = joint.axis;
                        crate::moments::InertialParams::from_mass_h_inertia(
                            0.0,
                            nalgebra::Vector3::zeros(),
                            a * a.transpose(),
                        )
                    } else {
                        crate::moments::InertialParams([0.0; 10])
                    };
                }
                u
            })
            .collect();
        type Row = (
            Vec<f64>,
            Vec<f64>,
            Vec<f64>,
            Vec<f64>,
            Vec<Vec<f64>>,
            Vec<Vec<f64>>,
        );
        let per_sample: Vec<Row> = (0..d.len())
            .into_par_iter()
            .map(|k| -> Result<Row, DynamicsError> {
                let mut data = Data::new(&links);
                let tau_at = |m: &Model, q: &[f64], qd: &[f64], data: &mut Data| {
                    rnea(m, data, q, qd, &d.qdd[k]).map(|t| t.iter().copied().collect::<Vec<f64>>())
                };
                let mass = |m: &Model, data: &mut Data| -> Result<Vec<f64>, DynamicsError> {
                    crba(m, data, &d.q[k])?;
                    Ok((0..n * n)
                        .map(|e| data.mass_matrix[(e / n, e % n)])
                        .collect())
                };
                let tau = tau_at(&links, &d.q[k], &d.qd[k], &mut data)?;
                let m = mass(&links, &mut data)?;
                let (mut g, mut c) = (vec![0.0; n * n], vec![0.0; n * n]);
                let eps = 1e-6;
                for j in 0..n {
                    let shifted = |v: &[f64], s: f64| {
                        let mut w = v.to_vec();
                        w[j] += s;
                        w
                    };
                    let tp = tau_at(&links, &shifted(&d.q[k], eps), &d.qd[k], &mut data)?;
                    let tm = tau_at(&links, &shifted(&d.q[k], -eps), &d.qd[k], &mut data)?;
                    let up = tau_at(&links, &d.q[k], &shifted(&d.qd[k], eps), &mut data)?;
                    let um = tau_at(&links, &d.q[k], &shifted(&d.qd[k], -eps), &mut data)?;
                    for i in 0..n {
                        g[i * n + j] = (tp[i] - tm[i]) / (2.0 * eps);
                        c[i * n + j] = (up[i] - um[i]) / (2.0 * eps);
                    }
                }
                let mut dm = vec![];
                let mut dtau = vec![];
                for u in &units {
                    dm.push(mass(u, &mut data)?);
                    dtau.push(tau_at(u, &d.q[k], &d.qd[k], &mut data)?);
                }
                Ok((m, tau, g, c, dm, dtau))
            })
            .collect::<Result<_, DynamicsError>>()?;
        let ns = d.len().max(1) as f64;
        let mut lin = Self {
            n,
            t: d.t.clone(),
            m: vec![],
            tau: vec![],
            g: vec![],
            c: vec![],
            dm: vec![vec![]; n],
            dtau: vec![vec![]; n],
            axial: vec![0.0; n],
        };
        for (m, tau, g, c, dm, dtau) in per_sample {
            for i in 0..n {
                lin.axial[i] += m[i * n + i] / ns;
            }
            lin.m.push(m);
            lin.tau.push(tau);
            lin.g.push(g);
            lin.c.push(c);
            for (i, (a, b)) in dm.into_iter().zip(dtau).enumerate() {
                lin.dm[i].push(a);
                lin.dtau[i].push(b);
            }
        }
        Ok(lin)
    }

    /// `τ_L(θ) + Σ s_i ∂τ_L/∂s_i` at sample k.
    fn tau_shifted(&self, p: &Transmission, k: usize, i: usize) -> f64 {
        self.tau[k][i]
            + (0..self.n)
                .map(|j| p.axial_shift[j] * self.dtau[j][k][i])
                .sum::<f64>()
    }

    /// `τ_s − τ_L(θ)` per sample (sample-major, n per sample) for samples
    /// `from..to`, starting in quasi-static deflection at `from`; `None` if
    /// the integration diverges.
    pub fn simulate(&self, p: &Transmission, from: usize, to: usize) -> Option<Vec<f64>> {
        let n = self.n;
        let mut x = vec![0.0; 2 * n];
        for i in 0..n {
            let k = p.stiffness[i].max(1e-9);
            let t = self.tau_shifted(p, from, i);
            x[i] = t / k + p.backlash[i] * t.signum();
        }
        let mut out = Vec::with_capacity((to - from) * n);
        // the shifted mass matrix and torque at the samples used
        let last = to.min(self.t.len() - 1);
        let shifted = p.axial_shift.iter().any(|s| *s != 0.0);
        // (flat: n×n and n per sample from `from`)
        let (mut ms, mut ts) = (
            Vec::with_capacity((last + 1 - from) * n * n),
            Vec::with_capacity((last + 1 - from) * n),
        );
        for k in from..=last {
            let start = ms.len();
            ms.extend_from_slice(&self.m[k]);
            if shifted {
                for (l, sl) in p.axial_shift.iter().enumerate() {
                    for (e, d) in ms[start..].iter_mut().zip(&self.dm[l][k]) {
                        *e += sl * d;
                    }
                }
            }
            ts.extend((0..n).map(|i| self.tau_shifted(p, k, i)));
        }
        // the dynamics at k + a (a ∈ [0, 1]) between samples k and k + 1
        let node_at = |k: usize, a: f64, out: &mut Node| -> bool {
            let k1 = (k + 1).min(last);
            let (r0, r1) = (k - from, k1 - from);
            let lerp = |u: &[f64], v: &[f64], dst: &mut [f64]| {
                for ((d, u), v) in dst.iter_mut().zip(u).zip(v) {
                    *d = u + a * (v - u);
                }
            };
            lerp(
                &ts[r0 * n..(r0 + 1) * n],
                &ts[r1 * n..(r1 + 1) * n],
                &mut out.tau,
            );
            lerp(&self.g[k], &self.g[k1], &mut out.g);
            lerp(&self.c[k], &self.c[k1], &mut out.c);
            let (m0, m1) = (
                &ms[r0 * n * n..(r0 + 1) * n * n],
                &ms[r1 * n * n..(r1 + 1) * n * n],
            );
            lerp(m0, m1, &mut out.chol);
            cholesky(&mut out.chol, n)
        };
        let (mut k1, mut k2, mut k3, mut k4, mut y) = (
            vec![0.0; 2 * n],
            vec![0.0; 2 * n],
            vec![0.0; 2 * n],
            vec![0.0; 2 * n],
            vec![0.0; 2 * n],
        );
        let mut x0 = vec![0.0; 2 * n];
        let in_contact = |x: &[f64], i: usize| x[i].abs() > p.backlash[i];
        // nodes at the step's start, middle and end; the end of one step is
        // the start of the next
        let (mut n0, mut nh, mut n1) = (Node::new(n), Node::new(n), Node::new(n));
        if !node_at(from, 0.0, &mut n0) {
            return None;
        }
        for k in from..to {
            for i in 0..n {
                out.push(p.torque(i, x[i], x[n + i]) - ts[(k - from) * n + i]);
            }
            if k + 1 >= to {
                break;
            }
            let dt = self.t[k + 1] - self.t[k];
            x0.copy_from_slice(&x);
            // one step per sample; a step across a dead band's edge (the
            // spring force has a kink there) is redone in finer substeps
            for substeps in [SUBSTEPS, REFINED] {
                let h = dt / substeps as f64;
                x.copy_from_slice(&x0);
                for s in 0..substeps {
                    let a0 = s as f64 / substeps as f64;
                    let ah = (s as f64 + 0.5) / substeps as f64;
                    let a1 = (s as f64 + 1.0) / substeps as f64;
                    if substeps > 1 && !node_at(k, a0, &mut n0) {
                        return None;
                    }
                    if !(node_at(k, ah, &mut nh) && node_at(k, a1, &mut n1)) {
                        return None;
                    }
                    n0.rhs(p, &x, &mut k1);
                    for i in 0..2 * n {
                        y[i] = x[i] + 0.5 * h * k1[i];
                    }
                    nh.rhs(p, &y, &mut k2);
                    for i in 0..2 * n {
                        y[i] = x[i] + 0.5 * h * k2[i];
                    }
                    nh.rhs(p, &y, &mut k3);
                    for i in 0..2 * n {
                        y[i] = x[i] + h * k3[i];
                    }
                    n1.rhs(p, &y, &mut k4);
                    for i in 0..2 * n {
                        x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                    }
                    if substeps > 1 && s + 1 < substeps {
                        std::mem::swap(&mut n0, &mut n1);
                    }
                }
                let crossed =
                    (0..n).any(|i| p.backlash[i] > 0.0 && in_contact(&x, i) != in_contact(&x0, i));
                if !crossed {
                    break;
                }
            }
            // the end node of this step starts the next (k + 1 at a = 0)
            std::mem::swap(&mut n0, &mut n1);
            if !x.iter().all(|v| v.is_finite() && v.abs() < 1e3) {
                return None;
            }
        }
        Some(out)
    }
}

/// The fitted hypothesis.
#[derive(Clone, Debug)]
pub struct ComplianceFit {
    /// Per-joint stiffness, damping and dead band.
    pub transmission: Transmission,
    /// Training residual sum of squares with the hypothesis (coefficient 1).
    pub rss: f64,
}

/// Samples within the warm-up from the first sample.
fn warm_up(t: &[f64]) -> usize {
    let t0 = t.first().copied().unwrap_or(0.0);
    t.partition_point(|&s| s < t0 + WARM_UP)
}

/// The search over transmissions for one residual: what every stage shares.
struct Search<'a> {
    lin: &'a Linearisation,
    r: &'a [f64],
    /// First sample fitted (after the warm-up).
    warm: usize,
    /// Samples `0..upto` are the training part.
    upto: usize,
    backlash: bool,
}

impl Search<'_> {
    /// The training cost `Σ (r − h)²` of a hypothesis simulated to `to`, and
    /// its error vector; `None` if it does not simulate.
    fn cost_on(&self, p: &Transmission, to: usize) -> Option<(f64, Vec<f64>)> {
        let n = self.lin.n;
        let h = self.lin.simulate(p, 0, to)?;
        let e: Vec<f64> = (self.warm * n..to * n).map(|k| self.r[k] - h[k]).collect();
        let v = e.iter().map(|x| x * x).sum::<f64>();
        v.is_finite().then_some((v, e))
    }

    /// Damping for a damping ratio ζ at stiffness k on joint i.
    fn damping_for(&self, k: f64, i: usize, zeta: f64) -> f64 {
        2.0 * zeta * (k * self.lin.axial[i].max(1e-6)).sqrt()
    }

    /// A stiff transmission (the start of every search).
    fn rigid(&self) -> Transmission {
        let n = self.lin.n;
        Transmission {
            stiffness: vec![1e5; n],
            damping: (0..n).map(|i| self.damping_for(1e5, i, 0.15)).collect(),
            backlash: vec![0.0; n],
            axial_shift: vec![0.0; n],
        }
    }

    /// The cheapest of `trials` on the whole training part.
    fn best_of(&self, trials: Vec<Transmission>) -> Option<(f64, Transmission)> {
        trials
            .into_par_iter()
            .filter_map(|q| self.cost_on(&q, self.upto).map(|c| (c.0, q)))
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// Per joint, the cost on the search window with the hypothesis scaled
    /// by its best β ≥ 0 (the candidate's coefficient), so that the grid
    /// judges timing, not amplitude.
    fn projected(&self, p: &Transmission, window: usize) -> Option<Vec<f64>> {
        let n = self.lin.n;
        let h = self.lin.simulate(p, 0, window)?;
        Some(
            (0..n)
                .map(|i| {
                    let (mut rh, mut hh, mut rr) = (0.0, 0.0, 0.0);
                    for k in self.warm..window {
                        let (a, b) = (self.r[k * n + i], h[k * n + i]);
                        rh += a * b;
                        hh += b * b;
                        rr += a * a;
                    }
                    let beta = if hh > 0.0 { (rh / hh).max(0.0) } else { 0.0 };
                    rr - 2.0 * beta * rh + beta * beta * hh
                })
                .collect(),
        )
    }

    /// Stage 1: one transmission shared by every joint over a K × ζ × b grid
    /// on the search window; each joint takes the grid point that explains
    /// its own residual best.
    fn grid_start(&self) -> Transmission {
        let n = self.lin.n;
        let t = &self.lin.t;
        let window = t
            .partition_point(|&s| s < t[self.warm.min(t.len() - 1)] + SEARCH_WINDOW)
            .min(self.upto);
        let ks: Vec<f64> = (0..GRID_K).map(|j| 150.0 * K_STEP.powi(j as i32)).collect();
        let zetas = [0.05, 0.15, 0.4];
        let bs: Vec<f64> = if self.backlash {
            (0..GRID_B).map(|j| 0.001 * B_STEP.powi(j as i32)).collect()
        } else {
            vec![0.0]
        };
        let grid: Vec<(f64, f64, f64)> = ks
            .iter()
            .flat_map(|&k| zetas.iter().map(move |&z| (k, z)))
            .flat_map(|(k, z)| bs.iter().map(move |&b| (k, z, b)))
            .collect();
        let rigid = self.rigid();
        let at = |&(k, z, b): &(f64, f64, f64)| {
            (0..n).fold(rigid.clone(), |q, i| {
                with(&q, i, k, self.damping_for(k, i, z), b)
            })
        };
        let costs: Vec<Option<Vec<f64>>> = grid
            .par_iter()
            .map(|g| self.projected(&at(g), window))
            .collect();
        let mut p = rigid.clone();
        for i in 0..n {
            let pick = costs
                .iter()
                .zip(&grid)
                .filter_map(|(c, g)| c.as_ref().map(|c| (c[i], *g)))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, g)| g);
            if let Some((k, z, b)) = pick {
                p = with(&p, i, k, self.damping_for(k, i, z), b);
            }
        }
        p
    }

    /// Stage 2, one joint: a local (K_i, D_i, b_i) grid on the whole
    /// training part, then the rotor/link axial split s_i at the same
    /// ringing frequency K_i / (M_ii + s_i).
    fn descend(&self, p: &mut Transmission, best: &mut f64, i: usize) {
        let (k0, d0, b0) = (p.stiffness[i], p.damping[i], p.backlash[i]);
        let hs = if self.backlash {
            vec![0.85, 1.0, 1.15]
        } else {
            vec![1.0]
        };
        let mut trials = vec![];
        // a finer local grid where the dead band makes the cost rougher
        let (fs, gs): (&[f64], &[f64]) = if self.backlash {
            (&[0.85, 0.93, 1.0, 1.07, 1.15], &[0.7, 0.85, 1.0, 1.2, 1.4])
        } else {
            (&[0.88, 1.0, 1.13], &[0.75, 1.0, 1.3])
        };
        for &f in fs {
            for &g in gs {
                for &h in &hs {
                    trials.push(with(p, i, k0 * f, d0 * g, b0 * h));
                }
            }
        }
        if let Some((c, q)) = self.best_of(trials)
            && c < *best
        {
            *best = c;
            *p = q;
        }
        let (k0, s0, mi) = (p.stiffness[i], p.axial_shift[i], self.lin.axial[i]);
        let trials: Vec<Transmission> = [-0.08, -0.05, -0.03, -0.015, 0.015, 0.03, 0.05, 0.08]
            .iter()
            .map(|f| {
                let s = s0 + f * mi;
                let mut q = p.clone();
                q.axial_shift[i] = s;
                q.stiffness[i] = k0 * (mi + s) / (mi + s0);
                q
            })
            .collect();
        if let Some((c, q)) = self.best_of(trials)
            && c < *best
        {
            *best = c;
            *p = q;
        }
    }

    /// The LM parameter vector (ln K_i, ln D_i, b_i, s_i).
    fn pack(&self, p: &Transmission) -> Vec<f64> {
        let mut v: Vec<f64> = p.stiffness.iter().map(|k| k.ln()).collect();
        v.extend(p.damping.iter().map(|d| d.ln()));
        if self.backlash {
            v.extend(p.backlash.iter().copied());
        }
        v.extend(p.axial_shift.iter().copied());
        v
    }

    fn unpack(&self, v: &[f64]) -> Transmission {
        let n = self.lin.n;
        Transmission {
            stiffness: v[..n].iter().map(|x| x.exp()).collect(),
            damping: v[n..2 * n].iter().map(|x| x.exp()).collect(),
            backlash: if self.backlash {
                v[2 * n..3 * n].iter().map(|b| b.max(0.0)).collect()
            } else {
                vec![0.0; n]
            },
            axial_shift: v[v.len() - n..].to_vec(),
        }
    }

    /// Forward-difference steps of the LM parameters.
    fn steps(&self, np: usize) -> Vec<f64> {
        let n = self.lin.n;
        let nb = if self.backlash { 3 * n } else { 2 * n };
        (0..np)
            .map(|j| {
                if j < 2 * n {
                    0.01
                } else if j < nb {
                    2e-5
                } else {
                    1e-3 * self.lin.axial[j - nb]
                }
            })
            .collect()
    }

    /// `(JᵀJ, Jᵀe)` of the forward-difference Jacobian at `v` (error `e`).
    fn normal_equations(
        &self,
        v: &[f64],
        e: &[f64],
        steps: &[f64],
    ) -> Option<(DMatrix<f64>, nalgebra::DVector<f64>)> {
        let np = v.len();
        let jac: Vec<Vec<f64>> = (0..np)
            .into_par_iter()
            .map(|j| {
                let mut w = v.to_vec();
                w[j] += steps[j];
                let (_, ej) = self.cost_on(&self.unpack(&w), self.upto)?;
                Some(e.iter().zip(&ej).map(|(a, b)| (a - b) / steps[j]).collect())
            })
            .collect::<Option<_>>()?;
        let mut jtj = DMatrix::<f64>::zeros(np, np);
        let mut jte = nalgebra::DVector::<f64>::zeros(np);
        for a in 0..np {
            for b in a..np {
                let s: f64 = jac[a].iter().zip(&jac[b]).map(|(x, y)| x * y).sum();
                jtj[(a, b)] = s;
                jtj[(b, a)] = s;
            }
            jte[a] = jac[a].iter().zip(e).map(|(x, y)| x * y).sum();
        }
        Some((jtj, jte))
    }

    /// Stage 3: Levenberg–Marquardt on (ln K_i, ln D_i, b_i, s_i) over the
    /// whole training part, from `p`.
    fn levenberg_marquardt(&self, p: &Transmission) -> Option<(Transmission, f64)> {
        let mut v = self.pack(p);
        let (mut best, mut e) = self.cost_on(p, self.upto)?;
        let steps = self.steps(v.len());
        let mut lambda = 1e-3;
        for _ in 0..12 {
            let Some((jtj, jte)) = self.normal_equations(&v, &e, &steps) else {
                break;
            };
            let mut improved = false;
            for _ in 0..8 {
                let mut m = jtj.clone();
                for a in 0..v.len() {
                    m[(a, a)] += lambda * jtj[(a, a)].max(1e-12);
                }
                let Some(step) = m.cholesky().map(|c| c.solve(&jte)) else {
                    lambda *= 10.0;
                    continue;
                };
                let w: Vec<f64> = v.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
                match self.cost_on(&self.unpack(&w), self.upto) {
                    Some((c, ew)) if c < best => {
                        improved = (best - c) / best > 1e-5;
                        v = w;
                        best = c;
                        e = ew;
                        lambda = (lambda / 5.0).max(1e-7);
                        break;
                    }
                    _ => lambda *= 8.0,
                }
            }
            if !improved {
                break;
            }
        }
        Some((self.unpack(&v), best))
    }
}

/// `p` with joint i's stiffness, damping and dead band replaced.
fn with(p: &Transmission, i: usize, k: f64, d: f64, b: f64) -> Transmission {
    let mut q = p.clone();
    q.stiffness[i] = k;
    q.damping[i] = d;
    q.backlash[i] = b;
    q
}

/// Fits the hypothesis to the residual `r` (sample-major, n per sample) on
/// samples `0..upto`: a grid start, two sweeps of coordinate descent, then
/// Levenberg–Marquardt (see the module docs); `None` when nothing simulates.
pub fn fit(lin: &Linearisation, r: &[f64], upto: usize, backlash: bool) -> Option<ComplianceFit> {
    let search = Search {
        lin,
        r,
        warm: warm_up(&lin.t).min(upto),
        upto,
        backlash,
    };
    let mut p = search.grid_start();
    let mut best = search.cost_on(&p, upto)?.0;
    for _ in 0..SWEEPS[usize::from(backlash)] {
        for i in 0..lin.n {
            search.descend(&mut p, &mut best, i);
        }
    }
    let (transmission, rss) = search.levenberg_marquardt(&p)?;
    Some(ComplianceFit { transmission, rss })
}

/// Stiffness range (N·m/rad) a robot joint's transmission is taken to have:
/// below it the joint would sag visibly under its own weight, above it the
/// spring is too stiff to ring within the data's bandwidth.
const PLAUSIBLE_STIFFNESS: (f64, f64) = (50.0, 1e5);

/// Why a fitted transmission is physically doubtful, if it is.
fn doubtful(p: &Transmission) -> Option<String> {
    let (lo, hi) = PLAUSIBLE_STIFFNESS;
    let (i, k) = p
        .stiffness
        .iter()
        .enumerate()
        .find(|(_, k)| !(lo..=hi).contains(*k))?;
    Some(format!(
        "joint {}'s fitted stiffness {k:.0} N·m/rad is outside {lo}–{hi:.0} N·m/rad",
        i + 1
    ))
}

/// The candidate's columns on all samples (one per joint) for a fitted
/// hypothesis (zero during the warm-up).
pub fn columns(candidate: Candidate, lin: &Linearisation, fit: &ComplianceFit) -> Option<Columns> {
    let n = lin.n;
    let ns = lin.t.len();
    let h = lin.simulate(&fit.transmission, 0, ns)?;
    let mut cols = vec![vec![0.0; ns * n]; n];
    for s in warm_up(&lin.t)..ns {
        for i in 0..n {
            cols[i][s * n + i] = h[s * n + i];
        }
    }
    let p = &fit.transmission;
    let list = |v: &[f64], digits: usize| {
        v.iter()
            .map(|x| format!("{x:.digits$}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut detail = format!(
        "K = ({}) N·m/rad, D = ({}) N·m·s/rad",
        list(&p.stiffness, 0),
        list(&p.damping, 2)
    );
    if p.backlash.iter().any(|&b| b > 0.0) {
        detail = format!("dead band ±({}) rad, {detail}", list(&p.backlash, 4));
    }
    Some(Columns {
        candidate,
        detail,
        doubt: doubtful(p),
        cols,
        bodies: vec![],
        nonneg: false,
        // K, D and the axial split per joint, and the dead band for backlash
        nonlinear: if candidate == Candidate::Effect(crate::dynamics::Effect::Backlash) {
            4 * n
        } else {
            3 * n
        },
    })
}

#[cfg(test)]
mod tests {
    use super::{Transmission, doubtful};

    #[test]
    fn a_fitted_stiffness_outside_a_joints_range_is_doubtful() {
        let t = |k: f64| Transmission {
            stiffness: vec![2000.0, k],
            damping: vec![5.0; 2],
            backlash: vec![0.0; 2],
            axial_shift: vec![0.0; 2],
        };
        assert!(doubtful(&t(800.0)).is_none());
        let why = doubtful(&t(4.0)).unwrap();
        assert!(
            why.contains("joint 2") && why.contains("4 N·m/rad"),
            "{why}"
        );
        assert!(doubtful(&t(3e6)).is_some());
    }
}
