//! The link dynamics linearised along the measured motion ([`Linearisation`]):
//! precomputed once per data set, its nodes solved per axial shift and
//! cached, and the simulations of hypotheses on them.

use super::integrate::{LANES, by_shift, integrate_lanes};
use super::nodes::{
    CHUNK, Dim, Dynamic, Fixed, Nodes, Scratch, by_dim, node_len, set_len, solve_node,
};
use super::sinks::{Sink, Trace};
use super::transmission::Transmission;
use crate::data::Dataset;
use crate::dynamics::{DynamicsError, Model};
use rayon::prelude::*;
use std::sync::{Arc, Mutex};

/// The link dynamics linearised along the measured motion, per sample.
pub struct Linearisation {
    pub(super) n: usize,
    pub(super) t: Vec<f64>,
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
    pub(super) rigid: Option<Nodes>,
    /// The nodes of recently simulated axial shifts, most recent first (at
    /// most [`CACHED_SHIFTS`]): a search varies K, D and b far more often
    /// than the shift.
    cache: Mutex<Vec<Arc<Nodes>>>,
    /// Node sets evicted from the cache, their buffers reused by the next
    /// ones solved (at most [`SPARE_SETS`]): fresh buffers (~2.4 MB a set on
    /// the leg) cost as much in page faults as solving the set.
    pub(super) spare: Mutex<Vec<Nodes>>,
}

/// Evicted node sets kept for their buffers.
pub(super) const SPARE_SETS: usize = 2;

/// Axial shifts whose nodes [`Linearisation`] keeps.
pub(super) const CACHED_SHIFTS: usize = 4;

/// The node sets a compliance search holds at once, at most: the unshifted
/// one, the cached shifts, the spare ones, and one being solved per
/// hypothesis searched in parallel (elasticity and backlash, each with a
/// simulation per thread; counted as four).
pub(crate) const NODE_SETS: u64 = 1 + CACHED_SHIFTS as u64 + SPARE_SETS as u64 + 4;

impl Linearisation {
    /// Precomputes along the data (the link side of `model`).
    pub fn new(model: &Model, d: &Dataset) -> Result<Self, DynamicsError> {
        let links = model.link_side();
        let n = links.dof();
        let units = unit_axial_models(&links);
        let per_sample: Vec<Sample> = (0..d.len())
            .into_par_iter()
            .map(|k| sample(&links, &units, d, k))
            .collect::<Result<_, DynamicsError>>()?;
        Ok(Self::assemble(n, d, per_sample))
    }

    /// The per-sample values laid out one sample after the other, the mean
    /// axial inertias, and the unshifted nodes.
    fn assemble(n: usize, d: &Dataset, per_sample: Vec<Sample>) -> Self {
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
        lin
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
    /// lock-step integrator ([`super::integrate`]).
    pub(super) fn integrate<D: Dim, S: Sink>(
        &self,
        d: D,
        at: &Nodes,
        p: &Transmission,
        to: usize,
        out: S,
    ) -> Option<S::Out> {
        let [h] = integrate_lanes(d, &self.t, at, [p], to, [out]);
        h
    }

    /// [`Linearisation::simulate`] of every hypothesis in `ps`, those with a
    /// common axial shift [`LANES`] at a time (in parallel over groups).
    pub(super) fn simulate_all(&self, ps: &[Transmission], to: usize) -> Vec<Option<Vec<f64>>> {
        let len = to * self.n;
        self.run_all(ps, to, || Trace(Vec::with_capacity(len)))
    }

    /// Every hypothesis in `ps` simulated into a sink of `make`'s (what
    /// [`Linearisation::simulate`] would feed it), [`LANES`] at a time
    /// where they share an axial shift (grouped by shift, in order within
    /// a shift); `None` where one does not simulate. Returned in `ps`'s order.
    pub(super) fn run_all<S, F>(
        &self,
        ps: &[Transmission],
        to: usize,
        make: F,
    ) -> Vec<Option<S::Out>>
    where
        S: Sink,
        S::Out: Send,
        F: Fn() -> S + Sync,
    {
        let groups = by_shift(ps);
        let done: Vec<Vec<Option<S::Out>>> = groups
            .par_iter()
            .map(|group| {
                let members: Vec<&Transmission> = group.iter().map(|&j| &ps[j]).collect();
                if members.len() > 1 {
                    self.run_group(&members, to, &make)
                } else {
                    vec![self.run_one(members[0], to, make())]
                }
            })
            .collect();
        let mut out: Vec<Option<S::Out>> = (0..ps.len()).map(|_| None).collect();
        for (group, results) in groups.iter().zip(done) {
            for (&j, r) in group.iter().zip(results) {
                out[j] = r;
            }
        }
        out
    }

    /// One hypothesis into `sink`.
    fn run_one<S: Sink>(&self, p: &Transmission, to: usize, sink: S) -> Option<S::Out> {
        let run = |at: &Nodes| by_dim!(self.n, d => self.integrate(d, at, p, to, sink));
        self.with_nodes(&p.axial_shift, to, run)?
    }

    /// One group (≤ [`LANES`], one axial shift); missing lanes repeat the
    /// first hypothesis and are dropped.
    fn run_group<S: Sink>(
        &self,
        group: &[&Transmission],
        to: usize,
        make: &impl Fn() -> S,
    ) -> Vec<Option<S::Out>> {
        let ps: [&Transmission; LANES] =
            std::array::from_fn(|l| *group.get(l).unwrap_or(&group[0]));
        let sinks: [S; LANES] = std::array::from_fn(|_| make());
        let run = |at: &Nodes| by_dim!(self.n, d => integrate_lanes(d, &self.t, at, ps, to, sinks));
        match self.with_nodes(&group[0].axial_shift, to, run) {
            Some(out) => out.into_iter().take(group.len()).collect(),
            None => (0..group.len()).map(|_| None).collect(),
        }
    }
}

/// One sample's link-side values: `M`, `τ_L`, `∂τ_L/∂q`, `∂τ_L/∂q̇`, and per
/// joint `∂M/∂s_i`, `∂τ_L/∂s_i`.
type Sample = (
    Vec<f64>,
    Vec<f64>,
    Vec<f64>,
    Vec<f64>,
    Vec<Vec<f64>>,
    Vec<Vec<f64>>,
);

/// Per joint i, `links` with only a unit axial inertia `a_i a_iᵀ` on link i.
fn unit_axial_models(links: &Model) -> Vec<Model> {
    (0..links.dof())
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
        .collect()
}

/// [`Sample`] k: the derivatives by central differences (ε = 10⁻⁶).
fn sample(links: &Model, units: &[Model], d: &Dataset, k: usize) -> Result<Sample, DynamicsError> {
    use crate::dynamics::{Data, crba, rnea};
    let n = links.dof();
    let mut data = Data::new(links);
    let tau_at = |m: &Model, q: &[f64], qd: &[f64], data: &mut Data| {
        rnea(m, data, q, qd, &d.qdd[k]).map(|t| t.iter().copied().collect::<Vec<f64>>())
    };
    let mass = |m: &Model, data: &mut Data| -> Result<Vec<f64>, DynamicsError> {
        crba(m, data, &d.q[k])?;
        Ok((0..n * n)
            .map(|e| data.mass_matrix[(e / n, e % n)])
            .collect())
    };
    let tau = tau_at(links, &d.q[k], &d.qd[k], &mut data)?;
    let m = mass(links, &mut data)?;
    let (mut g, mut c) = (vec![0.0; n * n], vec![0.0; n * n]);
    let eps = 1e-6;
    for j in 0..n {
        let shifted = |v: &[f64], s: f64| {
            let mut w = v.to_vec();
            w[j] += s;
            w
        };
        let tp = tau_at(links, &shifted(&d.q[k], eps), &d.qd[k], &mut data)?;
        let tm = tau_at(links, &shifted(&d.q[k], -eps), &d.qd[k], &mut data)?;
        let up = tau_at(links, &d.q[k], &shifted(&d.qd[k], eps), &mut data)?;
        let um = tau_at(links, &d.q[k], &shifted(&d.qd[k], -eps), &mut data)?;
        for i in 0..n {
            g[i * n + j] = (tp[i] - tm[i]) / (2.0 * eps);
            c[i * n + j] = (up[i] - um[i]) / (2.0 * eps);
        }
    }
    let mut dm = vec![];
    let mut dtau = vec![];
    for u in units {
        dm.push(mass(u, &mut data)?);
        dtau.push(tau_at(u, &d.q[k], &d.qd[k], &mut data)?);
    }
    Ok((m, tau, g, c, dm, dtau))
}

#[cfg(test)]
pub(super) mod tests {
    use super::super::integrate::integrate_lanes_any;
    use super::super::sinks::{Cost, Projection};
    use super::*;

    /// The leg's linearisation along 1 s of data with rotors and backlash.
    pub(super) fn leg_linearisation() -> Linearisation {
        use crate::dynamics::cheetah3;
        use crate::effects::simulate;
        use crate::sim::{Effects, SimConfig};
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
        use crate::effects::simulate;
        use crate::sim::{Effects, SimConfig};
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
        use super::{CACHED_SHIFTS, SPARE_SETS};
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

    /// Groups of four give each hypothesis's one-lane results bit for bit:
    /// elasticity, a dead band that is crossed, a diverging lane, a group
    /// of mixed shifts and a partial group.
    #[test]
    fn lanes_equal_the_scalar_integrator() {
        let lin = leg_linearisation();
        let n = lin.n;
        let base = Transmission {
            stiffness: vec![2000.0; n],
            damping: vec![2.0; n],
            backlash: vec![0.0; n],
            axial_shift: vec![0.0; n],
        };
        let mut ps = vec![];
        for (k, b) in [
            (300.0, 0.0),
            (800.0, 0.004),
            (5e3, 0.0),
            (150.0, 0.01),
            (1.0, 0.0),
        ] {
            let mut p = base.clone();
            p.stiffness = vec![k; n];
            p.backlash = vec![b; n];
            // a nearly undamped, very soft spring diverges
            if k == 1.0 {
                p.damping = vec![-50.0; n];
            }
            ps.push(p);
        }
        let mut shifted = base.clone();
        shifted.axial_shift[0] = 0.01 * lin.axial[0];
        ps.push(shifted);
        let to = 2000;
        let lanes = lin.simulate_all(&ps, to);
        assert_eq!(lanes.len(), ps.len());
        let mut diverged = 0;
        for (p, got) in ps.iter().zip(&lanes) {
            let want = lin.simulate(p, to);
            diverged += usize::from(want.is_none());
            assert_eq!(got, &want, "{p:?}");
        }
        assert!(diverged >= 1, "the diverging lane must be tested");
        // a cost-only sink sums what the trace would give, bit for bit
        let r: Vec<f64> = (0..to * n).map(|k| (k as f64 * 0.37).sin()).collect();
        let from = 100 * n;
        let costs = lin.run_all(&ps, to, || Cost {
            r: &r,
            from,
            acc: 0.0,
        });
        for (h, c) in lanes.iter().zip(&costs) {
            let want = h
                .as_ref()
                .map(|h| (from..h.len()).map(|k| (r[k] - h[k]).powi(2)).sum::<f64>());
            assert_eq!(c, &want);
        }
        // and the per-joint projection sums joint by joint in sample order
        let proj = lin.run_all(&ps, to, || Projection {
            r: &r,
            n,
            from,
            sums: vec![[0.0; 3]; n],
        });
        for (h, c) in lanes.iter().zip(&proj) {
            let want = h.as_ref().map(|h| {
                (0..n)
                    .map(|i| {
                        let (mut rh, mut hh, mut rr) = (0.0, 0.0, 0.0);
                        for k in (from / n)..h.len() / n {
                            let (a, b) = (r[k * n + i], h[k * n + i]);
                            rh += a * b;
                            hh += b * b;
                            rr += a * a;
                        }
                        let beta = if hh > 0.0 { (rh / hh).max(0.0) } else { 0.0 };
                        rr - 2.0 * beta * rh + beta * beta * hh
                    })
                    .collect::<Vec<f64>>()
            });
            assert_eq!(c, &want);
        }
    }

    /// The build picked at run time (AVX2 where the processor has it) and
    /// the baseline build give the same numbers to the last bit, four lanes
    /// and one, with dead bands crossed.
    #[test]
    fn the_run_time_build_equals_the_baseline_build() {
        let lin = leg_linearisation();
        let at = lin.rigid.as_ref().unwrap();
        let p = |k: f64, b: f64| Transmission {
            stiffness: vec![k; 3],
            damping: vec![3.0; 3],
            backlash: vec![b; 3],
            axial_shift: vec![0.0; 3],
        };
        let ps = [
            p(300.0, 0.0),
            p(800.0, 0.004),
            p(2e3, 0.002),
            p(150.0, 0.01),
        ];
        let refs: [&Transmission; 4] = std::array::from_fn(|l| &ps[l]);
        let sinks = || std::array::from_fn(|_| Trace(vec![]));
        let picked = integrate_lanes(Fixed::<3>, &lin.t, at, refs, 2000, sinks());
        let baseline = integrate_lanes_any(Fixed::<3>, &lin.t, at, refs, 2000, sinks());
        assert!(picked.iter().all(Option::is_some));
        assert_eq!(picked, baseline);
        let [picked] = integrate_lanes(Fixed::<3>, &lin.t, at, [&ps[1]], 2000, [Trace(vec![])]);
        let [baseline] =
            integrate_lanes_any(Fixed::<3>, &lin.t, at, [&ps[1]], 2000, [Trace(vec![])]);
        assert_eq!(picked, baseline);
    }
}
