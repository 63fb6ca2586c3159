//! The linearised link dynamics solved for the acceleration at every sample
//! ([`Nodes`]), and the joint count an integration is compiled for ([`Dim`]).

/// The values of a node, the linearised dynamics at one sample solved for
/// the acceleration, `ẍ = b − P x − Q ẋ − A τ_s` with `A = M⁻¹`, `P = A G`,
/// `Q = A C` and `b = A τ_L`, stored flat as `[b (n), P (n×n), Q (n×n),
/// A (n×n)]`, row-major.
pub(super) fn node_len(n: usize) -> usize {
    3 * n * n + n
}

/// Fills `node` ([`node_len`]) from `M` (in `s.m`, overwritten by its
/// Cholesky factor), `G`, `C` and `τ_L`: `A = M⁻¹ = L⁻ᵀ L⁻¹` from the
/// factor's inverse, then `P = A G`, `Q = A C`, `b = A τ_L`; `false` if `M`
/// is not positive definite.
pub(super) fn solve_node<D: Dim>(
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
    if !crate::linalg::cholesky_in_place(l, n) {
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
pub(super) trait Dim: Copy + Send + Sync {
    fn n(self) -> usize;
}

#[derive(Clone, Copy)]
pub(super) struct Fixed<const N: usize>;

impl<const N: usize> Dim for Fixed<N> {
    #[inline(always)]
    fn n(self) -> usize {
        N
    }
}

#[derive(Clone, Copy)]
pub(super) struct Dynamic(pub(super) usize);

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
pub(super) use by_dim;

/// Values per sample of one node set ([`Nodes`]) for `n` joints: the node
/// and the shifted τ_L.
pub(crate) fn node_values(n: usize) -> u64 {
    (node_len(n) + n) as u64
}

/// The nodes of one axial shift at every sample `0..=last`. A step's
/// middle node is the mean of its ends (the coefficients change by ~0.1 %
/// per sample, so this differs from solving the interpolated M at the
/// middle by far less than the data's noise), computed by the integrator:
/// storing it cost more in memory traffic than it saved.
pub struct Nodes {
    pub(super) shift: Vec<f64>,
    /// The last sample covered.
    pub(super) last: usize,
    /// Shifted `τ_L` per sample (n per sample).
    pub(super) tau: Vec<f64>,
    /// [`node_len`] values per node.
    pub(super) nodes: Vec<f64>,
}

/// Buffers for [`solve_node`]: `M` (then its factor) and the factor's
/// inverse.
pub(super) struct Scratch {
    pub(super) m: Vec<f64>,
    li: Vec<f64>,
}

impl Scratch {
    pub(super) fn new(n: usize) -> Self {
        Self {
            m: vec![0.0; n * n],
            li: vec![0.0; n * n],
        }
    }
}

/// `v` resized to `len`, its old values kept and new ones zero: the node
/// buffers are overwritten whole, so a reused one is not cleared first.
pub(super) fn set_len(v: &mut Vec<f64>, len: usize) {
    if v.len() < len {
        v.resize(len, 0.0);
    } else {
        v.truncate(len);
    }
}

/// Samples per parallel task when nodes are solved.
pub(super) const CHUNK: usize = 1024;
