//! The search for a compliance hypothesis that explains a residual: a grid
//! start, coordinate descent, then Levenberg–Marquardt (the stages are in
//! the module docs of [`super`]).

use super::linearisation::Linearisation;
use super::sinks::{Cost, Projection};
use super::transmission::Transmission;
use nalgebra::DMatrix;

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

/// The fitted hypothesis.
#[derive(Clone, Debug)]
pub struct ComplianceFit {
    /// Per-joint stiffness, damping and dead band.
    pub transmission: Transmission,
    /// Training residual sum of squares with the hypothesis (coefficient 1).
    pub rss: f64,
}

/// Samples within the warm-up from the first sample.
pub(super) fn warm_up(t: &[f64]) -> usize {
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
    /// [`Projection`]): `p` with each joint's parameters taken from its
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

#[cfg(test)]
mod tests {
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
}
