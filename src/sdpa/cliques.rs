//! What Clarabel's chordal decomposition will make of a PSD block, estimated
//! from the block's aggregate sparsity pattern before anything is solved, for
//! the memory estimate ([`super::MemoryEstimate`]).
//!
//! The pattern (every off-diagonal entry of F₀ … F_m in the block) is
//! extended to a chordal graph by minimum-degree elimination; its maximal
//! cliques C₁ … C_k are the cones of a decomposition before merging.
//! Clarabel's default merge (`clique_graph`) joins two cliques only when
//! |C₁|³ + |C₂|³ ≥ |C₁ ∪ C₂|³, so Σ|C|³ never grows and no merged clique is
//! larger than S^{1/3}, S = Σᵢ |Cᵢ|³. A cone of side c has t = c(c+1)/2 ≤ c²
//! rows, so after any such merging
//!
//! ```text
//! Σ t² ≤ Σ c⁴ ≤ min(n, S^{1/3}) · S
//! ```
//!
//! which is the estimate (of the `t²` sum that the memory estimate charges
//! [`BYTES_PER_DENSE`](super::BYTES_PER_DENSE) for). It is an estimate, not a
//! bound: Clarabel orders by AMD, not minimum degree, so its cliques can
//! differ. A block whose pattern has a single maximal clique stays whole.

use std::cmp::Reverse;
use std::collections::{BTreeSet, BinaryHeap};

/// Largest block side analysed; a larger block counts as dense (its n × n
/// expression alone is 64 n² bytes: 256 GiB at this side).
pub const MAX_ANALYSED_SIDE: usize = 1 << 16;
/// Most edges (pattern plus fill) the elimination may hold; past it the
/// block counts as dense, so the analysis itself stays below ~0.5 GiB.
pub const MAX_ANALYSED_EDGES: usize = 1 << 22;
/// Most pairs of neighbours the elimination may visit (its time: well under
/// a second here); past it the block counts as dense.
pub const MAX_ANALYSED_PAIRS: usize = 1 << 22;

/// The estimated Σ t² of the cones Clarabel decomposes a block of side `n`
/// with off-diagonal pattern `edges` into (0-based (i, j), i ≠ j, in any
/// order, repeats allowed); `None` if the block stays one cone (one maximal
/// clique) or is too large to analyse.
pub fn decomposed_t2(n: usize, edges: impl Iterator<Item = (usize, usize)>) -> Option<f64> {
    if n > MAX_ANALYSED_SIDE {
        return None;
    }
    let mut adj = vec![BTreeSet::new(); n];
    let mut count = 0usize;
    for (i, j) in edges.filter(|(i, j)| i != j && *i < n && *j < n) {
        count += usize::from(adj[i].insert(j));
        adj[j].insert(i);
        if count > MAX_ANALYSED_EDGES {
            return None;
        }
    }
    if count == n * n.saturating_sub(1) / 2 {
        return None; // complete: one clique
    }
    let (order, later) = eliminate(adj, count)?;
    let sizes = maximal_clique_sizes(&order, &later);
    if sizes.len() <= 1 {
        return None;
    }
    let s: f64 = sizes.iter().map(|&c| (c as f64).powi(3)).sum();
    Some((n as f64).min(s.cbrt()) * s)
}

/// Minimum-degree elimination: the order, and for each vertex its
/// neighbours when it was eliminated (the clique it closes, less itself).
/// Once the vertex of least degree is tied to all others left, they are one
/// clique and are ordered as they are. `None` once the fill passes
/// [`MAX_ANALYSED_EDGES`] or the work [`MAX_ANALYSED_PAIRS`].
fn eliminate(
    mut adj: Vec<BTreeSet<usize>>,
    mut edges: usize,
) -> Option<(Vec<usize>, Vec<Vec<usize>>)> {
    let n = adj.len();
    let mut heap: BinaryHeap<_> = (0..n).map(|v| Reverse((adj[v].len(), v))).collect();
    let (mut done, mut order) = (vec![false; n], Vec::with_capacity(n));
    let (mut later, mut pairs) = (vec![Vec::new(); n], 0usize);
    while let Some(Reverse((deg, v))) = heap.pop() {
        if done[v] || deg != adj[v].len() {
            continue;
        }
        if deg + 1 == n - order.len() {
            close_clique(v, &adj, &mut order, &mut later);
            break;
        }
        pairs += deg * deg / 2;
        if pairs > MAX_ANALYSED_PAIRS {
            return None;
        }
        let nb: Vec<usize> = std::mem::take(&mut adj[v]).into_iter().collect();
        for (k, &a) in nb.iter().enumerate() {
            adj[a].remove(&v);
            for &b in &nb[k + 1..] {
                if adj[a].insert(b) {
                    adj[b].insert(a);
                    edges += 1;
                }
            }
        }
        if edges > MAX_ANALYSED_EDGES {
            return None;
        }
        for &a in &nb {
            heap.push(Reverse((adj[a].len(), a)));
        }
        done[v] = true;
        order.push(v);
        later[v] = nb;
    }
    Some((order, later))
}

/// Ends the elimination when `v` and its neighbours are all that is left
/// (one clique): they follow in that order, each with the ones after it.
fn close_clique(
    v: usize,
    adj: &[BTreeSet<usize>],
    order: &mut Vec<usize>,
    later: &mut [Vec<usize>],
) {
    let rest: Vec<usize> = std::iter::once(v).chain(adj[v].iter().copied()).collect();
    for (k, &u) in rest.iter().enumerate() {
        order.push(u);
        later[u] = rest[k + 1..].to_vec();
    }
}

/// Sizes of the maximal cliques of the elimination: v's clique {v} ∪ later(v)
/// is not maximal exactly when a vertex u eliminated before it has v as its
/// first-eliminated later neighbour (its parent) and one more neighbour.
fn maximal_clique_sizes(order: &[usize], later: &[Vec<usize>]) -> Vec<usize> {
    let mut pos = vec![0usize; order.len()];
    for (k, &v) in order.iter().enumerate() {
        pos[v] = k;
    }
    let mut absorbs = vec![false; order.len()];
    for nb in later {
        if let Some(&p) = nb.iter().min_by_key(|&&w| pos[w]) {
            absorbs[p] |= nb.len() == later[p].len() + 1;
        }
    }
    (0..order.len())
        .filter(|&v| !absorbs[v])
        .map(|v| later[v].len() + 1)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(n: usize) -> impl Iterator<Item = (usize, usize)> {
        (1..n).map(|i| (i - 1, i))
    }

    #[test]
    fn a_dense_block_stays_whole() {
        let n = 12;
        let all = (0..n).flat_map(|i| (0..i).map(move |j| (i, j)));
        assert_eq!(decomposed_t2(n, all), None);
    }

    #[test]
    fn a_path_is_edges_and_an_arrow_is_triangles() {
        // a path of n vertices: n − 1 cliques of 2, S = 8 (n − 1)
        let s: f64 = 8.0 * 99.0;
        assert_eq!(decomposed_t2(100, path(100)), Some(s.cbrt() * s));
        // an arrow (vertex 0 tied to all) over a path: n − 2 triangles
        let arrow = path(50).chain((2..50).map(|i| (0, i)));
        let s: f64 = 27.0 * 48.0;
        assert_eq!(decomposed_t2(50, arrow), Some(s.cbrt() * s));
    }

    #[test]
    fn a_cycle_is_filled_to_triangles() {
        // a cycle of n ≥ 4 has no chordal pattern: min-degree fill makes
        // n − 2 triangles
        let n = 30;
        let cycle = path(n).chain(std::iter::once((n - 1, 0)));
        let s = 27.0 * (n - 2) as f64;
        assert_eq!(decomposed_t2(n, cycle), Some(s.cbrt() * s));
    }

    #[test]
    fn two_dense_blocks_sharing_one_vertex_are_two_cliques() {
        // {0..9} and {9..19}: cliques of 10 and 11
        let a = (0..10).flat_map(|i| (0..i).map(move |j| (i, j)));
        let b = (9..20).flat_map(|i| (9..i).map(move |j| (i, j)));
        let s: f64 = 1000.0 + 1331.0;
        assert_eq!(decomposed_t2(20, a.chain(b)), Some(20f64.min(s.cbrt()) * s));
    }

    #[test]
    fn the_control_pattern_is_a_clique_per_leaf() {
        // SDPLIB control1's block: a dense core of 5 with 5 leaves tied to
        // all of it and not to each other: 5 cliques of 6
        let core = (0..5).flat_map(|i| (0..i).map(move |j| (i, j)));
        let leaves = (5..10).flat_map(|l| (0..5).map(move |c| (l, c)));
        let s: f64 = 5.0 * 216.0;
        assert_eq!(
            decomposed_t2(10, core.chain(leaves)),
            Some(10f64.min(s.cbrt()) * s)
        );
    }

    /// Sizes of the maximal cliques of a graph of ≤ 12 vertices, by trying
    /// every vertex subset.
    fn brute_force_maximal(n: usize, edge: impl Fn(usize, usize) -> bool) -> Vec<usize> {
        let is_clique = |m: u32| {
            (0..n).all(|i| (0..i).all(|j| m >> i & 1 == 0 || m >> j & 1 == 0 || edge(i, j)))
        };
        let cliques: Vec<u32> = (1u32..1 << n).filter(|&m| is_clique(m)).collect();
        let mut sizes: Vec<usize> = cliques
            .iter()
            .filter(|&&m| !cliques.iter().any(|&o| o != m && o & m == m))
            .map(|m| m.count_ones() as usize)
            .collect();
        sizes.sort_unstable();
        sizes
    }

    #[test]
    fn maximal_cliques_match_brute_force_on_the_filled_graph() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for trial in 0..200 {
            let n = 3 + trial % 10;
            let mut edges = Vec::new();
            for i in 0..n {
                for j in 0..i {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    if state % 100 < 25 + (trial % 4) as u64 * 15 {
                        edges.push((i, j));
                    }
                }
            }
            let mut adj = vec![BTreeSet::new(); n];
            for &(i, j) in &edges {
                adj[i].insert(j);
                adj[j].insert(i);
            }
            let (order, later) = eliminate(adj, edges.len()).unwrap();
            assert_eq!(order.len(), n, "trial {trial}: every vertex eliminated");
            let filled = |i: usize, j: usize| later[i].contains(&j) || later[j].contains(&i);
            // the filled graph contains the pattern
            assert!(edges.iter().all(|&(i, j)| filled(i, j)), "trial {trial}");
            let mut ours = maximal_clique_sizes(&order, &later);
            ours.sort_unstable();
            assert_eq!(
                ours,
                brute_force_maximal(n, filled),
                "trial {trial}: {edges:?}"
            );
        }
    }

    #[test]
    fn too_large_a_block_counts_as_dense() {
        assert_eq!(decomposed_t2(MAX_ANALYSED_SIDE + 1, path(3)), None);
        // a random graph of 3000 vertices and mean degree 20 has cliques of
        // hundreds after fill: the work budget ends the analysis
        let mut state = 88172645463325252u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % 3000) as usize
        };
        let random: Vec<(usize, usize)> = (0..30000).map(|_| (next(), next())).collect();
        assert_eq!(decomposed_t2(3000, random.into_iter()), None);
    }
}
