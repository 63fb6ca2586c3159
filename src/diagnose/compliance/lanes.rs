//! The integrator of the linearised transmission dynamics, for L
//! hypotheses with the same axial shift in lock-step on one set of nodes:
//! each node is read once for all lanes and the per-lane arithmetic
//! vectorises. One hypothesis is the one-lane case
//! ([`Linearisation::integrate`]); every lane does the same operations in
//! the same order, so a hypothesis gives the same numbers to the last bit
//! in any group (a test below holds it to that). [`LANES`] at a time is
//! what measured fastest (8 lanes ran out of registers).

use super::{
    Compliance, Dim, Dynamic, Fixed, Linearisation, Nodes, REFINED, Sink, Trace, Transmission,
    node_len, start_state,
};
use rayon::prelude::*;

/// Hypotheses simulated together.
pub(super) const LANES: usize = 4;

impl Linearisation {
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
        let run = |at: &Nodes| by_dim!(self.n, d => self.integrate_lanes(d, at, ps, to, sinks));
        match self.with_nodes(&group[0].axial_shift, to, run) {
            Some(out) => out.into_iter().take(group.len()).collect(),
            None => (0..group.len()).map(|_| None).collect(),
        }
    }

    /// RK4 for L hypotheses at once, one step per sample interval, each
    /// output `τ_s − τ_L` (sample by sample, joint by joint) into its lane's
    /// sink; a step across a dead band's edge (the spring force has a kink
    /// there) is redone for that lane in [`REFINED`] substeps, its nodes
    /// interpolated; a lane that diverges gives `None`.
    ///
    /// On an x86-64 processor with AVX2 the same code is compiled for it
    /// (four lanes in one register instead of two); without FMA, so every
    /// operation rounds as in the baseline build and the numbers are the
    /// same to the last bit.
    pub(super) fn integrate_lanes<D: Dim, S: Sink, const L: usize>(
        &self,
        d: D,
        at: &Nodes,
        ps: [&Transmission; L],
        to: usize,
        out: [S; L],
    ) -> [Option<S::Out>; L] {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, checked just above.
            return unsafe { self.integrate_lanes_avx2(d, at, ps, to, out) };
        }
        self.integrate_lanes_any(d, at, ps, to, out)
    }

    /// [`Self::integrate_lanes`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn integrate_lanes_avx2<D: Dim, S: Sink, const L: usize>(
        &self,
        d: D,
        at: &Nodes,
        ps: [&Transmission; L],
        to: usize,
        out: [S; L],
    ) -> [Option<S::Out>; L] {
        self.integrate_lanes_any(d, at, ps, to, out)
    }

    /// The body of [`Self::integrate_lanes`], inlined into each build of it.
    #[inline(always)]
    fn integrate_lanes_any<D: Dim, S: Sink, const L: usize>(
        &self,
        d: D,
        at: &Nodes,
        ps: [&Transmission; L],
        to: usize,
        mut out: [S; L],
    ) -> [Option<S::Out>; L] {
        let n = d.n();
        let len = node_len(n);
        let to = to.min(at.last + 1);
        let sp: Vec<[Compliance; L]> = (0..n)
            .map(|i| std::array::from_fn(|l| ps[l].spring(i)))
            .collect();
        let starts: [Vec<f64>; L] = std::array::from_fn(|l| start_state(at, ps[l], n));
        let mut x: Vec<[f64; L]> = (0..2 * n)
            .map(|k| std::array::from_fn(|l| starts[l][k]))
            .collect();
        let mut alive = [true; L];
        let dead_band: [bool; L] = std::array::from_fn(|l| ps[l].backlash.iter().any(|&b| b > 0.0));
        let mut x0 = x.clone();
        let mut work = vec![[0.0; L]; 5 * 2 * n + n];
        // one lane's scalar state, substeps and buffers, for a refined step
        let mut xl = vec![[0.0]; 2 * n];
        let mut step = vec![0.0; 3 * len];
        let mut mid = vec![0.0; len];
        let mut swork = vec![[0.0]; 11 * n];
        let lane_sp: [Vec<[Compliance; 1]>; L] =
            std::array::from_fn(|l| (0..n).map(|i| [sp[i][l]]).collect());
        for s in 0..to {
            for (l, o) in out.iter_mut().enumerate() {
                for i in 0..n {
                    o.push(
                        s * n + i,
                        torque(&sp[i][l], x[i][l], x[n + i][l]) - at.tau[s * n + i],
                    );
                }
            }
            if s + 1 >= to {
                break;
            }
            let dt = self.t[s + 1] - self.t[s];
            x0.copy_from_slice(&x);
            let ends = &at.nodes[s * len..(s + 2) * len];
            let (n0, n1) = ends.split_at(len);
            for j in 0..len {
                mid[j] = 0.5 * (n0[j] + n1[j]);
            }
            rk4_lanes(d, [n0, &mid, n1], &sp, dt, &mut x, &mut work);
            for l in 0..L {
                if !alive[l] {
                    continue;
                }
                if dead_band[l] && crossed_lane(ps[l], &x0, &x, l, n) {
                    for k in 0..2 * n {
                        xl[k] = [x0[k][l]];
                    }
                    let buffers = (&mut xl[..], &mut step[..], &mut swork[..]);
                    refine(d, (n0, n1), &lane_sp[l], dt, buffers);
                    for k in 0..2 * n {
                        x[k][l] = xl[k][0];
                    }
                }
                alive[l] = x[..2 * n]
                    .iter()
                    .all(|v| v[l].is_finite() && v[l].abs() < 1e3);
            }
            if !alive.iter().any(|&a| a) {
                break;
            }
        }
        let mut alive = alive.into_iter();
        out.map(|o| alive.next().is_some_and(|a| a).then(|| o.finish()))
    }
}

/// The indices of `ps` in groups of at most [`LANES`] with one axial shift
/// each: the shifts in order of first appearance, each one's hypotheses in
/// order.
fn by_shift(ps: &[Transmission]) -> Vec<Vec<usize>> {
    let mut shifts: Vec<(&[f64], Vec<usize>)> = vec![];
    for (j, p) in ps.iter().enumerate() {
        match shifts
            .iter_mut()
            .find(|(s, _)| *s == p.axial_shift.as_slice())
        {
            Some((_, members)) => members.push(j),
            None => shifts.push((&p.axial_shift, vec![j])),
        }
    }
    shifts
        .into_iter()
        .flat_map(|(_, members)| {
            members
                .chunks(LANES)
                .map(<[usize]>::to_vec)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// [`Compliance::torque`] without a branch (a select), so that the lanes
/// vectorise; the same value.
#[inline(always)]
fn torque(c: &Compliance, x: f64, xd: f64) -> f64 {
    let v = c.stiffness * (x - c.backlash * x.signum()) + c.damping * xd;
    if x.abs() <= c.backlash { 0.0 } else { v }
}

/// Whether lane `l`'s step from `x0` to `x` entered or left a joint's dead band.
#[inline(always)]
fn crossed_lane<const L: usize>(
    p: &Transmission,
    x0: &[[f64; L]],
    x: &[[f64; L]],
    l: usize,
    n: usize,
) -> bool {
    let in_contact = |x: &[[f64; L]], i: usize| x[i][l].abs() > p.backlash[i];
    (0..n).any(|i| p.backlash[i] > 0.0 && in_contact(x, i) != in_contact(x0, i))
}

/// One lane's step of length `dt` from `x` in [`REFINED`] RK4 substeps on
/// nodes interpolated between its ends `(n0, n1)`; `step` holds 3 nodes,
/// `work` 11 n values.
#[inline(always)]
fn refine<D: Dim>(
    d: D,
    (n0, n1): (&[f64], &[f64]),
    sp: &[[Compliance; 1]],
    dt: f64,
    (x, step, work): (&mut [[f64; 1]], &mut [f64], &mut [[f64; 1]]),
) {
    let len = n0.len();
    let r = REFINED as f64;
    for sub in 0..REFINED {
        for e in 0..3 {
            let a = (sub as f64 + 0.5 * e as f64) / r;
            for j in 0..len {
                step[e * len + j] = n0[j] + a * (n1[j] - n0[j]);
            }
        }
        let (s0, rest) = step.split_at(len);
        let (sh, s1) = rest.split_at(len);
        rk4_lanes(d, [s0, sh, &s1[..len]], sp, dt / r, x, work);
    }
}

/// `ẋ = b − P x − Q ẋ − A τ_s(x, ẋ)` for L states `(x, ẋ)` at a node of
/// [`super::solve_node`], the same operations per lane.
#[inline(always)]
fn rhs_lanes<D: Dim, const L: usize>(
    d: D,
    node: &[f64],
    sp: &[[Compliance; L]],
    x: &[[f64; L]],
    dx: &mut [[f64; L]],
    ts: &mut [[f64; L]],
) {
    let n = d.n();
    let (sp, x, dx, ts) = (&sp[..n], &x[..2 * n], &mut dx[..2 * n], &mut ts[..n]);
    let node = &node[..3 * n * n + n];
    for i in 0..n {
        for l in 0..L {
            ts[i][l] = torque(&sp[i][l], x[i][l], x[n + i][l]);
        }
    }
    let (b, rest) = node.split_at(n);
    let (pm, rest) = rest.split_at(n * n);
    let (qm, am) = rest.split_at(n * n);
    for i in 0..n {
        let (pr, qr, ar) = (
            &pm[i * n..(i + 1) * n],
            &qm[i * n..(i + 1) * n],
            &am[i * n..(i + 1) * n],
        );
        let mut s = [b[i]; L];
        for j in 0..n {
            for l in 0..L {
                s[l] -= pr[j] * x[j][l] + qr[j] * x[n + j][l] + ar[j] * ts[j][l];
            }
        }
        dx[n + i] = s;
    }
    dx[..n].copy_from_slice(&x[n..]);
}

/// One RK4 step of length `h` for L states on the nodes at its start,
/// middle and end; `work` holds 11 n values per lane.
#[inline(always)]
fn rk4_lanes<D: Dim, const L: usize>(
    d: D,
    nodes: [&[f64]; 3],
    sp: &[[Compliance; L]],
    h: f64,
    x: &mut [[f64; L]],
    work: &mut [[f64; L]],
) {
    let m = 2 * d.n();
    let (x, work) = (&mut x[..m], &mut work[..5 * m + d.n()]);
    let (k, rest) = work.split_at_mut(4 * m);
    let (y, ts) = rest.split_at_mut(m);
    let (k0, rest) = k.split_at_mut(m);
    let (k1, rest) = rest.split_at_mut(m);
    let (k2, k3) = rest.split_at_mut(m);
    let axpy = |y: &mut [[f64; L]], x: &[[f64; L]], a: f64, k: &[[f64; L]]| {
        for i in 0..m {
            for l in 0..L {
                y[i][l] = x[i][l] + a * k[i][l];
            }
        }
    };
    rhs_lanes(d, nodes[0], sp, x, k0, ts);
    axpy(y, x, 0.5 * h, k0);
    rhs_lanes(d, nodes[1], sp, y, k1, ts);
    axpy(y, x, 0.5 * h, k1);
    rhs_lanes(d, nodes[1], sp, y, k2, ts);
    axpy(y, x, h, k2);
    rhs_lanes(d, nodes[2], sp, y, k3, ts);
    for i in 0..m {
        for l in 0..L {
            x[i][l] += h / 6.0 * (k0[i][l] + 2.0 * k1[i][l] + 2.0 * k2[i][l] + k3[i][l]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::leg_linearisation;
    use super::*;

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
        let costs = lin.run_all(&ps, to, || super::super::Cost {
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
        let proj = lin.run_all(&ps, to, || super::super::Projection {
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
        use super::super::{Fixed, Trace};
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
        let picked = lin.integrate_lanes(Fixed::<3>, at, refs, 2000, sinks());
        let baseline = lin.integrate_lanes_any(Fixed::<3>, at, refs, 2000, sinks());
        assert!(picked.iter().all(Option::is_some));
        assert_eq!(picked, baseline);
        let [picked] = lin.integrate_lanes(Fixed::<3>, at, [&ps[1]], 2000, [Trace(vec![])]);
        let [baseline] = lin.integrate_lanes_any(Fixed::<3>, at, [&ps[1]], 2000, [Trace(vec![])]);
        assert_eq!(picked, baseline);
    }
}
