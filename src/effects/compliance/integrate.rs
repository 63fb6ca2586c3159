//! The integrator of the linearised transmission dynamics, for L
//! hypotheses with the same axial shift in lock-step on one set of nodes:
//! each node is read once for all lanes and the per-lane arithmetic
//! vectorises. One hypothesis is the one-lane case; every lane does the
//! same operations in the same order, so a hypothesis gives the same
//! numbers to the last bit in any group (a test holds it to that).
//! [`LANES`] at a time is what measured fastest (8 lanes ran out of
//! registers).

use super::nodes::{Dim, Nodes, node_len};
use super::sinks::Sink;
use super::transmission::Transmission;
use crate::sim::compliance::Compliance;

/// Hypotheses simulated together.
pub(super) const LANES: usize = 4;

/// Substeps for a sample interval in which a joint enters or leaves its dead
/// band.
const REFINED: usize = 16;

/// The quasi-static start `x_i = τ_i / K_i + b_i sign(τ_i)`, `ẋ = 0`.
pub(super) fn start_state(at: &Nodes, p: &Transmission, n: usize) -> Vec<f64> {
    let mut x = vec![0.0; 2 * n];
    for i in 0..n {
        let t = at.tau[i];
        x[i] = t / p.stiffness[i].max(1e-9) + p.backlash[i] * t.signum();
    }
    x
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
    d: D,
    t: &[f64],
    at: &Nodes,
    ps: [&Transmission; L],
    to: usize,
    out: [S; L],
) -> [Option<S::Out>; L] {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, checked just above.
        return unsafe { integrate_lanes_avx2(d, t, at, ps, to, out) };
    }
    integrate_lanes_any(d, t, at, ps, to, out)
}

/// [`integrate_lanes`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn integrate_lanes_avx2<D: Dim, S: Sink, const L: usize>(
    d: D,
    t: &[f64],
    at: &Nodes,
    ps: [&Transmission; L],
    to: usize,
    out: [S; L],
) -> [Option<S::Out>; L] {
    integrate_lanes_any(d, t, at, ps, to, out)
}

/// The body of [`integrate_lanes`], inlined into each build of it.
#[inline(always)]
pub(super) fn integrate_lanes_any<D: Dim, S: Sink, const L: usize>(
    d: D,
    t: &[f64],
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
        let dt = t[s + 1] - t[s];
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

/// The indices of `ps` in groups of at most [`LANES`] with one axial shift
/// each: the shifts in order of first appearance, each one's hypotheses in
/// order.
pub(super) fn by_shift(ps: &[Transmission]) -> Vec<Vec<usize>> {
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
/// [`super::nodes::solve_node`], the same operations per lane.
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
