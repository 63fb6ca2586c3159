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
//! which is ~100× cheaper to integrate than the full link dynamics. The
//! coefficients are solved for the acceleration once per data set and axial
//! shift, at every sample ([`Nodes`]: `ẍ = b − P x − Q ẋ − A τ_s`, `A = M⁻¹`;
//! the shifts of recent simulations are cached), so a step is four
//! matrix–vector products: RK4, one step per sample, its middle node the
//! mean of its ends; a step in which a joint enters or leaves its dead band
//! is redone in 16 substeps on interpolated nodes, since the spring force
//! has a kink there. The loops are compiled for each joint count up to 7.
//! The hypothesis is searched in three stages:
//!
//! 1. a grid shared by every joint over K (150 … 8,000 N·m/rad: 15 values
//!    for elasticity; 8 for backlash, with 7 dead bands 0.001 … 0.023 rad,
//!    each joint's pick then refined on a 3 × 3 (K, b) grid), damping ratio
//!    ζ (0.05, 0.15, 0.4), on the first 3 s of the training part; each
//!    joint takes the grid point that explains its own residual best
//!    (scaled by its best coefficient, so the grid judges timing, not
//!    amplitude);
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
use std::sync::{Arc, Mutex};

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
const GRID_B: usize = 7;
/// For backlash the stiffness grid is coarser (and the dead band's step
/// [`B_STEP`] too), each joint's pick then refined by these steps.
const GRID_K_COARSE: usize = 8;
const K_STEP_COARSE: f64 = 1.75;
const K_STEP_FINE: f64 = 1.32;
const B_STEP_FINE: f64 = 1.3;
/// Sweeps of the coordinate descent (stage 2): the dead band's rougher cost
/// needs two.
const SWEEPS: [usize; 2] = [1, 2];
const B_STEP: f64 = 1.68;

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
    /// Joint i's spring–damper and dead band.
    pub fn spring(&self, i: usize) -> Compliance {
        Compliance {
            stiffness: self.stiffness[i],
            damping: self.damping[i],
            backlash: self.backlash[i],
        }
    }

    /// The transmitted torque of joint i at deflection x and rate xd.
    #[inline]
    pub fn torque(&self, i: usize, x: f64, xd: f64) -> f64 {
        self.spring(i).torque(x, xd)
    }
}

/// The link dynamics linearised along the measured motion, per sample.
pub struct Linearisation {
    n: usize,
    t: Vec<f64>,
    /// `M(θ)`, row-major n×n per sample, the samples one after the other
    /// (as every per-sample array here).
    m: Vec<f64>,
    /// `τ_L(θ, θ̇, θ̈)`, n per sample.
    tau: Vec<f64>,
    /// `∂τ_L/∂q`, row-major n×n per sample.
    g: Vec<f64>,
    /// `∂τ_L/∂q̇`, row-major n×n per sample.
    c: Vec<f64>,
    /// Per joint i: `∂M/∂s_i` (row-major n×n per sample) and `∂τ_L/∂s_i`
    /// (n per sample), for a unit axial inertia `a_i a_iᵀ` added to link i.
    dm: Vec<Vec<f64>>,
    dtau: Vec<Vec<f64>>,
    /// Link-side `M_ii` averaged over the motion (kg·m²).
    pub axial: Vec<f64>,
    /// The nodes without axial shift, on every sample (`None` if a mass
    /// matrix is not positive definite: nothing simulates).
    rigid: Option<Nodes>,
    /// The nodes of recently simulated axial shifts, most recent first (at
    /// most [`CACHED_SHIFTS`]): a search varies K, D and b far more often
    /// than the shift.
    cache: Mutex<Vec<Arc<Nodes>>>,
    /// Node sets evicted from the cache, their buffers reused by the next
    /// ones solved (at most [`SPARE_SETS`]): fresh buffers (~2.4 MB a set on
    /// the leg) cost as much in page faults as solving the set.
    spare: Mutex<Vec<Nodes>>,
}

/// Evicted node sets kept for their buffers.
const SPARE_SETS: usize = 2;

/// Axial shifts whose nodes [`Linearisation`] keeps.
const CACHED_SHIFTS: usize = 4;

/// The node sets a compliance search holds at once, at most: the unshifted
/// one, the cached shifts, the spare ones, and one being solved per
/// hypothesis searched in parallel (elasticity and backlash, each with a
/// simulation per thread; counted as four).
pub const NODE_SETS: u64 = 1 + CACHED_SHIFTS as u64 + SPARE_SETS as u64 + 4;

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

/// The values of a node, the linearised dynamics at one sample solved for
/// the acceleration, `ẍ = b − P x − Q ẋ − A τ_s` with `A = M⁻¹`, `P = A G`,
/// `Q = A C` and `b = A τ_L`, stored flat as `[b (n), P (n×n), Q (n×n),
/// A (n×n)]`, row-major.
fn node_len(n: usize) -> usize {
    3 * n * n + n
}

/// Fills `node` ([`node_len`]) from `M` (in `s.m`, overwritten by its
/// Cholesky factor), `G`, `C` and `τ_L`: `A = M⁻¹ = L⁻ᵀ L⁻¹` from the
/// factor's inverse, then `P = A G`, `Q = A C`, `b = A τ_L`; `false` if `M`
/// is not positive definite.
fn solve_node<D: Dim>(
    d: D,
    s: &mut Scratch,
    g: &[f64],
    c: &[f64],
    tau: &[f64],
    node: &mut [f64],
) -> bool {
    let n = d.n();
    let nn = n * n;
    let (l, li) = (&mut s.m[..nn], &mut s.li[..nn]);
    if !cholesky(l, n) {
        return false;
    }
    // L⁻¹, lower triangular
    for j in 0..n {
        li[j * n + j] = 1.0 / l[j * n + j];
        for i in j + 1..n {
            let mut v = 0.0;
            for k in j..i {
                v += l[i * n + k] * li[k * n + j];
            }
            li[i * n + j] = -v / l[i * n + i];
        }
    }
    let (b, rest) = node[..3 * nn + n].split_at_mut(n);
    let (p, rest) = rest.split_at_mut(nn);
    let (q, a) = rest.split_at_mut(nn);
    for i in 0..n {
        for j in 0..=i {
            let mut v = 0.0;
            for k in i..n {
                v += li[k * n + i] * li[k * n + j];
            }
            a[i * n + j] = v;
            a[j * n + i] = v;
        }
    }
    let (g, c, tau) = (&g[..nn], &c[..nn], &tau[..n]);
    for i in 0..n {
        let ar = &a[i * n..(i + 1) * n];
        b[i] = (0..n).map(|k| ar[k] * tau[k]).sum();
        for j in 0..n {
            let (mut vp, mut vq) = (0.0, 0.0);
            for k in 0..n {
                vp += ar[k] * g[k * n + j];
                vq += ar[k] * c[k * n + j];
            }
            p[i * n + j] = vp;
            q[i * n + j] = vq;
        }
    }
    true
}

/// The joint count of an integration: fixed at compile time for the common
/// sizes (the loops unroll), or known only at run time.
trait Dim: Copy + Send + Sync {
    fn n(self) -> usize;
}

#[derive(Clone, Copy)]
struct Fixed<const N: usize>;

impl<const N: usize> Dim for Fixed<N> {
    #[inline(always)]
    fn n(self) -> usize {
        N
    }
}

#[derive(Clone, Copy)]
struct Dynamic(usize);

impl Dim for Dynamic {
    #[inline(always)]
    fn n(self) -> usize {
        self.0
    }
}

/// `$body` with `$d` the [`Dim`] of `$n` joints: [`Fixed`] up to 7,
/// [`Dynamic`] above.
macro_rules! by_dim {
    ($n:expr, $d:ident => $body:expr) => {
        match $n {
            1 => {
                let $d = Fixed::<1>;
                $body
            }
            2 => {
                let $d = Fixed::<2>;
                $body
            }
            3 => {
                let $d = Fixed::<3>;
                $body
            }
            4 => {
                let $d = Fixed::<4>;
                $body
            }
            5 => {
                let $d = Fixed::<5>;
                $body
            }
            6 => {
                let $d = Fixed::<6>;
                $body
            }
            7 => {
                let $d = Fixed::<7>;
                $body
            }
            n => {
                let $d = Dynamic(n);
                $body
            }
        }
    };
}

/// Values per sample of one node set ([`Nodes`]) for `n` joints: the node
/// and the shifted τ_L.
pub fn node_values(n: usize) -> u64 {
    (node_len(n) + n) as u64
}

/// The nodes of one axial shift at every sample `0..=last`. A step's
/// middle node is the mean of its ends (the coefficients change by ~0.1 %
/// per sample, so this differs from solving the interpolated M at the
/// middle by far less than the data's noise), computed by the integrator:
/// storing it cost more in memory traffic than it saved.
pub struct Nodes {
    shift: Vec<f64>,
    /// The last sample covered.
    last: usize,
    /// Shifted `τ_L` per sample (n per sample).
    tau: Vec<f64>,
    /// [`node_len`] values per node.
    nodes: Vec<f64>,
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
        let (nn, k) = (n * n, d.len());
        let mut lin = Self {
            n,
            t: d.t.clone(),
            m: Vec::with_capacity(k * nn),
            tau: Vec::with_capacity(k * n),
            g: Vec::with_capacity(k * nn),
            c: Vec::with_capacity(k * nn),
            dm: (0..n).map(|_| Vec::with_capacity(k * nn)).collect(),
            dtau: (0..n).map(|_| Vec::with_capacity(k * n)).collect(),
            axial: vec![0.0; n],
            rigid: None,
            cache: Mutex::new(vec![]),
            spare: Mutex::new(vec![]),
        };
        for (m, tau, g, c, dm, dtau) in per_sample {
            for i in 0..n {
                lin.axial[i] += m[i * n + i] / ns;
            }
            lin.m.extend(m);
            lin.tau.extend(tau);
            lin.g.extend(g);
            lin.c.extend(c);
            for (i, (a, b)) in dm.into_iter().zip(dtau).enumerate() {
                lin.dm[i].extend(a);
                lin.dtau[i].extend(b);
            }
        }
        lin.rigid = lin.nodes(&vec![0.0; n], usize::MAX);
        Ok(lin)
    }

    /// The nodes of the axial shift `shift` (kg·m² per joint) for samples
    /// `0..=last`; `None` if a mass matrix is not positive definite.
    pub fn nodes(&self, shift: &[f64], last: usize) -> Option<Nodes> {
        by_dim!(self.n, d => self.nodes_of(d, shift, last))
    }

    fn nodes_of<D: Dim>(&self, d: D, shift: &[f64], last: usize) -> Option<Nodes> {
        let (n, nn) = (d.n(), d.n() * d.n());
        let last = last.min(self.t.len().checked_sub(1)?);
        let len = node_len(n);
        let (mut tau, mut nodes) = self.take_buffers();
        set_len(&mut tau, (last + 1) * n);
        set_len(&mut nodes, (last + 1) * len);
        let ok = nodes
            .par_chunks_mut(len * CHUNK)
            .zip(tau.par_chunks_mut(n * CHUNK))
            .enumerate()
            .all(|(c, (nodes, tau))| {
                let mut s = Scratch::new(n);
                nodes
                    .chunks_mut(len)
                    .zip(tau.chunks_mut(n))
                    .enumerate()
                    .all(|(j, (node, t))| {
                        let k = c * CHUNK + j;
                        let (kn, kt) = (k * nn..(k + 1) * nn, k * n..(k + 1) * n);
                        s.m.copy_from_slice(&self.m[kn.clone()]);
                        t.copy_from_slice(&self.tau[kt.clone()]);
                        for (l, &sl) in shift.iter().enumerate().filter(|(_, s)| **s != 0.0) {
                            for (e, d) in s.m.iter_mut().zip(&self.dm[l][kn.clone()]) {
                                *e += sl * d;
                            }
                            for (e, d) in t.iter_mut().zip(&self.dtau[l][kt.clone()]) {
                                *e += sl * d;
                            }
                        }
                        solve_node(d, &mut s, &self.g[kn.clone()], &self.c[kn], t, node)
                    })
            });
        let at = Nodes {
            shift: shift.to_vec(),
            last,
            tau,
            nodes,
        };
        if !ok {
            self.keep_spare(vec![Arc::new(at)]);
            return None;
        }
        Some(at)
    }

    /// The buffers (τ, nodes) of a spare node set, or new empty ones with
    /// room for every sample (a set solved for a short window is later
    /// reused for a longer one).
    fn take_buffers(&self) -> (Vec<f64>, Vec<f64>) {
        match self.spare.lock().ok().and_then(|mut s| s.pop()) {
            Some(s) => (s.tau, s.nodes),
            None => {
                let (k, len) = (self.t.len(), node_len(self.n));
                let room = |per: usize| Vec::with_capacity(k * per);
                (room(self.n), room(len))
            }
        }
    }

    /// `τ_s − τ_L(θ)` per sample (sample-major, n per sample) for samples
    /// `0..to`, starting in quasi-static deflection at the first sample;
    /// `None` if the integration diverges.
    pub fn simulate(&self, p: &Transmission, to: usize) -> Option<Vec<f64>> {
        self.with_nodes(&p.axial_shift, to, |at| self.simulate_on(at, p, to))?
    }

    /// `f` on the nodes of the axial shift `shift` covering `0..to` (the
    /// unshifted set, a cached one, or one solved now and cached); `None`
    /// if they cannot be solved.
    fn with_nodes<R>(&self, shift: &[f64], to: usize, f: impl FnOnce(&Nodes) -> R) -> Option<R> {
        let rigid = self.rigid.as_ref()?;
        if shift == rigid.shift.as_slice() {
            return Some(f(rigid));
        }
        let cached = |c: &mut Vec<Arc<Nodes>>| {
            let j = c
                .iter()
                .position(|e| e.shift == shift && e.last + 1 >= to)?;
            let e = c.remove(j);
            c.insert(0, e.clone());
            Some(e)
        };
        let hit = cached(&mut *self.cache.lock().ok()?);
        let at = match hit {
            Some(at) => at,
            None => {
                let at = Arc::new(self.nodes(shift, to)?);
                let mut c = self.cache.lock().ok()?;
                c.insert(0, at.clone());
                let keep = CACHED_SHIFTS.min(c.len());
                let evicted: Vec<Arc<Nodes>> = c.drain(keep..).collect();
                drop(c);
                self.keep_spare(evicted);
                at
            }
        };
        let out = f(&at);
        // evicted by another simulation while this one read it
        self.keep_spare(vec![at]);
        Some(out)
    }

    /// The buffers of evicted node sets no simulation still reads, for
    /// the next sets solved (at most [`SPARE_SETS`] kept).
    fn keep_spare(&self, evicted: Vec<Arc<Nodes>>) {
        let Ok(mut spare) = self.spare.lock() else {
            return;
        };
        for e in evicted {
            if spare.len() < SPARE_SETS
                && let Ok(e) = Arc::try_unwrap(e)
            {
                spare.push(e);
            }
        }
    }

    /// [`Self::simulate`] on the nodes of `p`'s axial shift.
    fn simulate_on(&self, at: &Nodes, p: &Transmission, to: usize) -> Option<Vec<f64>> {
        let sink = Trace(Vec::with_capacity(to.min(at.last + 1) * self.n));
        by_dim!(self.n, d => self.integrate(d, at, p, to, sink))
    }

    /// RK4, one step per sample interval, each output `τ_s − τ_L` (sample
    /// by sample, joint by joint) into `out`: the one-lane case of the
    /// lock-step integrator ([`lanes`]).
    fn integrate<D: Dim, S: Sink>(
        &self,
        d: D,
        at: &Nodes,
        p: &Transmission,
        to: usize,
        out: S,
    ) -> Option<S::Out> {
        let [h] = self.integrate_lanes(d, at, [p], to, [out]);
        h
    }
}

/// Where an integration's outputs go, in order (flat index `s·n + i`).
trait Sink {
    type Out;
    fn push(&mut self, k: usize, v: f64);
    fn finish(self) -> Self::Out;
}

/// Every output: the simulated trace.
struct Trace(Vec<f64>);

impl Sink for Trace {
    type Out = Vec<f64>;
    #[inline(always)]
    fn push(&mut self, _: usize, v: f64) {
        self.0.push(v);
    }
    fn finish(self) -> Vec<f64> {
        self.0
    }
}

/// Per joint, the cost on the search window of a hypothesis scaled by its
/// best β ≥ 0 (the candidate's coefficient), so that the grid judges
/// timing, not amplitude: from the sums `Σ r h, Σ h², Σ r²` over the
/// samples from `from / n` on, accumulated in sample order (no trace kept).
struct Projection<'a> {
    r: &'a [f64],
    n: usize,
    from: usize,
    sums: Vec<[f64; 3]>,
}

impl Sink for Projection<'_> {
    type Out = Vec<f64>;
    #[inline(always)]
    fn push(&mut self, k: usize, h: f64) {
        if k >= self.from {
            let a = self.r[k];
            let s = &mut self.sums[k % self.n];
            s[0] += a * h;
            s[1] += h * h;
            s[2] += a * a;
        }
    }
    fn finish(self) -> Vec<f64> {
        self.sums
            .iter()
            .map(|&[rh, hh, rr]| {
                let beta = if hh > 0.0 { (rh / hh).max(0.0) } else { 0.0 };
                rr - 2.0 * beta * rh + beta * beta * hh
            })
            .collect()
    }
}

/// Only `Σ_{k ≥ from} (r_k − h_k)²`, summed in the order a trace would be
/// (so the same number to the last bit), with no trace kept.
struct Cost<'a> {
    r: &'a [f64],
    from: usize,
    acc: f64,
}

impl Sink for Cost<'_> {
    type Out = f64;
    #[inline(always)]
    fn push(&mut self, k: usize, v: f64) {
        if k >= self.from {
            self.acc += (self.r[k] - v).powi(2);
        }
    }
    fn finish(self) -> f64 {
        self.acc
    }
}

/// The quasi-static start `x_i = τ_i / K_i + b_i sign(τ_i)`, `ẋ = 0`.
fn start_state(at: &Nodes, p: &Transmission, n: usize) -> Vec<f64> {
    let mut x = vec![0.0; 2 * n];
    for i in 0..n {
        let t = at.tau[i];
        x[i] = t / p.stiffness[i].max(1e-9) + p.backlash[i] * t.signum();
    }
    x
}

/// Buffers for [`solve_node`]: `M` (then its factor) and the factor's
/// inverse.
struct Scratch {
    m: Vec<f64>,
    li: Vec<f64>,
}

impl Scratch {
    fn new(n: usize) -> Self {
        Self {
            m: vec![0.0; n * n],
            li: vec![0.0; n * n],
        }
    }
}

/// `v` resized to `len`, its old values kept and new ones zero: the node
/// buffers are overwritten whole, so a reused one is not cleared first.
fn set_len(v: &mut Vec<f64>, len: usize) {
    if v.len() < len {
        v.resize(len, 0.0);
    } else {
        v.truncate(len);
    }
}

/// Samples per parallel task when nodes are solved.
const CHUNK: usize = 1024;

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
        self.error_of(&self.lin.simulate(p, to)?, to)
    }

    /// The cost and error vector `r − h` of a simulation `h` to `to`.
    fn error_of(&self, h: &[f64], to: usize) -> Option<(f64, Vec<f64>)> {
        let n = self.lin.n;
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

    /// The cheapest of `trials` on the whole training part (simulated in
    /// lock-step groups; the first of equal costs, as a scan would pick).
    fn best_of(&self, trials: Vec<Transmission>) -> Option<(f64, Transmission)> {
        let from = self.warm * self.lin.n;
        let costs = self.lin.run_all(&trials, self.upto, || Cost {
            r: self.r,
            from,
            acc: 0.0,
        });
        costs
            .into_iter()
            .zip(trials)
            .filter_map(|(c, q)| c.filter(|c| c.is_finite()).map(|c| (c, q)))
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// Stage 1: one transmission shared by every joint over a K × ζ × b grid
    /// on the search window; each joint takes the grid point that explains
    /// its own residual best; for backlash the grid is coarse and each
    /// joint's pick is then refined on a 3 × 3 (K, b) grid around it.
    fn grid_start(&self) -> Transmission {
        let t = &self.lin.t;
        let window = t
            .partition_point(|&s| s < t[self.warm.min(t.len() - 1)] + SEARCH_WINDOW)
            .min(self.upto);
        let geometric = |x0: f64, step: f64, len: usize| -> Vec<f64> {
            (0..len).map(|j| x0 * step.powi(j as i32)).collect()
        };
        let (ks, bs) = if self.backlash {
            (
                geometric(150.0, K_STEP_COARSE, GRID_K_COARSE),
                geometric(0.001, B_STEP, GRID_B),
            )
        } else {
            (geometric(150.0, K_STEP, GRID_K), vec![0.0])
        };
        let rigid = self.rigid();
        let mut trials = vec![];
        for &k in &ks {
            for z in [0.05, 0.15, 0.4] {
                for &b in &bs {
                    trials.push((0..self.lin.n).fold(rigid.clone(), |q, i| {
                        with(&q, i, k, self.damping_for(k, i, z), b)
                    }));
                }
            }
        }
        let p = self.pick_per_joint(&rigid, &trials, window);
        if !self.backlash {
            return p;
        }
        let mut trials = vec![];
        for f in [1.0 / K_STEP_FINE, 1.0, K_STEP_FINE] {
            for h in [1.0 / B_STEP_FINE, 1.0, B_STEP_FINE] {
                let mut q = p.clone();
                for i in 0..self.lin.n {
                    q = with(
                        &q,
                        i,
                        p.stiffness[i] * f,
                        p.damping[i] * f.sqrt(),
                        p.backlash[i] * h,
                    );
                }
                trials.push(q);
            }
        }
        self.pick_per_joint(&p, &trials, window)
    }

    /// Per joint, the trial whose simulation explains that joint's residual
    /// best on samples up to `window` (scaled by its best coefficient, see
    /// [`Self::projected`]): `p` with each joint's parameters taken from its
    /// pick (`p` for a joint that no trial simulates).
    fn pick_per_joint(
        &self,
        p: &Transmission,
        trials: &[Transmission],
        window: usize,
    ) -> Transmission {
        let costs: Vec<Option<Vec<f64>>> = self.lin.run_all(trials, window, || Projection {
            r: self.r,
            n: self.lin.n,
            from: self.warm * self.lin.n,
            sums: vec![[0.0; 3]; self.lin.n],
        });
        let mut out = p.clone();
        for i in 0..self.lin.n {
            let pick = costs
                .iter()
                .zip(trials)
                .filter_map(|(c, q)| c.as_ref().map(|c| (c[i], q)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((_, q)) = pick {
                copy_joint(q, &mut out, i);
            }
        }
        out
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
        let trials: Vec<Transmission> = (0..np)
            .map(|j| {
                let mut w = v.to_vec();
                w[j] += steps[j];
                self.unpack(&w)
            })
            .collect();
        let jac: Vec<Vec<f64>> = self
            .lin
            .simulate_all(&trials, self.upto)
            .iter()
            .zip(steps)
            .map(|(h, step)| {
                let (_, ej) = self.error_of(h.as_deref()?, self.upto)?;
                Some(e.iter().zip(&ej).map(|(a, b)| (a - b) / step).collect())
            })
            .collect::<Option<_>>()?;
        let mut jtj = DMatrix::<f64>::zeros(np, np);
        let mut jte = nalgebra::DVector::<f64>::zeros(np);
        for a in 0..np {
            let sums = dots(&jac[a], jac[a..].iter().map(Vec::as_slice).chain([e]));
            for (b, &s) in (a..np).zip(&sums) {
                jtj[(a, b)] = s;
                jtj[(b, a)] = s;
            }
            jte[a] = sums[np - a];
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

/// `x · y` for every `y` of `ys` (over their common length), each summed
/// in index order as `Iterator::sum` would (from −0), all in one pass over
/// the rows: the independent sums hide each other's addition latency.
fn dots<'a>(x: &[f64], ys: impl Iterator<Item = &'a [f64]>) -> Vec<f64> {
    let ys: Vec<&[f64]> = ys.collect();
    let len = ys.iter().map(|y| y.len()).fold(x.len(), usize::min);
    let ys: Vec<&[f64]> = ys.into_iter().map(|y| &y[..len]).collect();
    let mut acc = vec![-0.0; ys.len()];
    for (k, &xk) in x[..len].iter().enumerate() {
        for (s, y) in acc.iter_mut().zip(&ys) {
            *s += xk * y[k];
        }
    }
    acc
}

/// `p` with joint i's stiffness, damping and dead band replaced.
fn with(p: &Transmission, i: usize, k: f64, d: f64, b: f64) -> Transmission {
    let mut q = p.clone();
    q.stiffness[i] = k;
    q.damping[i] = d;
    q.backlash[i] = b;
    q
}

/// Joint i's stiffness, damping, dead band and axial shift from `q` into `p`.
fn copy_joint(q: &Transmission, p: &mut Transmission, i: usize) {
    p.stiffness[i] = q.stiffness[i];
    p.damping[i] = q.damping[i];
    p.backlash[i] = q.backlash[i];
    p.axial_shift[i] = q.axial_shift[i];
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
    let h = lin.simulate(&fit.transmission, ns)?;
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
        gram: std::sync::OnceLock::new(),
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

// after `by_dim!`, which it uses
mod lanes;

#[cfg(test)]
mod tests {
    use super::{Dynamic, Fixed, Linearisation, Trace, Transmission, doubtful};

    /// The leg's linearisation along 1 s of data with rotors and backlash.
    pub(super) fn leg_linearisation() -> Linearisation {
        use crate::dynamics::cheetah3;
        use crate::sim::{Effects, SimConfig, simulate};
        let leg = cheetah3::description();
        let fx = Effects::parse("rotor_inertia,backlash", &[]).unwrap();
        let d = simulate(&leg, &SimConfig::for_robot(&leg, 1.0, fx, 3), |_, _| {}).unwrap();
        Linearisation::new(&leg.model, &d).unwrap()
    }

    /// The integrator compiled for three joints and the run-time one agree,
    /// and a shift's cached nodes give what freshly solved ones give.
    #[test]
    fn fixed_and_dynamic_integrators_and_the_node_cache_agree() {
        use crate::dynamics::cheetah3;
        use crate::sim::{Effects, SimConfig, simulate};
        let leg = cheetah3::description();
        let fx = Effects::parse("rotor_inertia,backlash", &[]).unwrap();
        let d = simulate(&leg, &SimConfig::for_robot(&leg, 1.0, fx, 3), |_, _| {}).unwrap();
        let lin = Linearisation::new(&leg.model, &d).unwrap();
        let p = Transmission {
            stiffness: vec![2000.0, 1500.0, 2500.0],
            damping: vec![5.0, 4.0, 6.0],
            backlash: vec![0.005, 0.004, 0.006],
            axial_shift: vec![0.001, -0.002, 0.0005],
        };
        let to = d.len();
        let fresh = lin.nodes(&p.axial_shift, to).unwrap();
        let a = lin
            .integrate(Fixed::<3>, &fresh, &p, to, Trace(vec![]))
            .unwrap();
        let b = lin
            .integrate(Dynamic(3), &fresh, &p, to, Trace(vec![]))
            .unwrap();
        assert_eq!(a.len(), to * 3);
        let max = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(max < 1e-12, "{max}");
        // the effect is there (the dead band rings), not a zero trace
        assert!(a.iter().map(|x| x.abs()).fold(0.0, f64::max) > 0.1);
        let first = lin.simulate(&p, to).unwrap();
        let cached = lin.simulate(&p, to).unwrap();
        assert_eq!(first, a);
        assert_eq!(cached, a);
        // a shorter run is the start of the longer one
        assert_eq!(lin.simulate(&p, 100).unwrap(), a[..300].to_vec());
    }

    /// Node sets solved into the buffers of evicted ones (longer and
    /// shorter runs mixed) simulate exactly as freshly solved ones.
    #[test]
    fn reused_node_buffers_give_the_fresh_nodes_simulation() {
        use super::{CACHED_SHIFTS, Fixed, SPARE_SETS};
        // the reference solved on its own linearisation (no spare buffers)
        let (lin, other) = (leg_linearisation(), leg_linearisation());
        let all = lin.t.len();
        let p = |j: usize| Transmission {
            stiffness: vec![2000.0, 1500.0, 2500.0],
            damping: vec![5.0, 4.0, 6.0],
            backlash: vec![0.005, 0.004, 0.006],
            axial_shift: vec![1e-4 * j as f64, -2e-4, 5e-5 * j as f64],
        };
        let fresh = |j: usize, to: usize| {
            let at = other.nodes(&p(j).axial_shift, to).unwrap();
            other
                .integrate(Fixed::<3>, &at, &p(j), to, Trace(vec![]))
                .unwrap()
        };
        let runs = 3 * (CACHED_SHIFTS + SPARE_SETS);
        for j in 0..runs {
            let to = if j % 2 == 0 { all } else { all / 3 };
            assert_eq!(lin.simulate(&p(j), to).unwrap(), fresh(j, to), "shift {j}");
        }
        // each set solved took the spare one evicted before it (without
        // reuse they would pile up to SPARE_SETS)
        assert_eq!(lin.spare.lock().unwrap().len(), 1, "no buffer was reused");
    }

    /// The one-pass dot products equal `Iterator::sum`'s to the last bit,
    /// over the common length when the lengths differ.
    #[test]
    fn one_pass_dots_equal_the_iterator_sums() {
        let v = |m: f64, len: usize| -> Vec<f64> {
            (0..len)
                .map(|k| (k as f64 * m).sin() * 1e3f64.powf((k % 7) as f64 - 3.0))
                .collect()
        };
        let (x, y0, y1, short) = (v(0.37, 500), v(1.3, 500), v(2.9, 500), v(0.5, 300));
        let got = super::dots(&x, [&y0[..], &y1, &x].into_iter());
        let want: Vec<f64> = [&y0, &y1, &x]
            .iter()
            .map(|y| x.iter().zip(y.iter()).map(|(a, b)| a * b).sum())
            .collect();
        assert_eq!(got, want);
        let got = super::dots(&x, [&y0[..], &short].into_iter());
        let s: f64 = x.iter().zip(&short).map(|(a, b)| a * b).sum();
        let s0: f64 = x[..300].iter().zip(&y0).map(|(a, b)| a * b).sum();
        assert_eq!(got, vec![s0, s]);
        assert_eq!(super::dots(&[], [&y0[..]].into_iter()), vec![-0.0]);
    }

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
