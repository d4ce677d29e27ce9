//! Fill-reducing ordering for the 3D stiffness matrix: geometric nested dissection
//! (George 1973, "Nested dissection of a regular finite element mesh", SIAM J. Numer.
//! Anal. 10: 345–363) on the mesh's node graph.
//!
//! Why not faer's default (approximate minimum degree): on the 3D meshes of cramp's
//! scenes AMD's fill grows so fast that 24 GiB ended near 5–7 × 10⁵ equations (issue 18
//! bench, hex8 cube 32³: 1.78 GiB at 1.0 × 10⁵ equations). Nested dissection is the
//! ordering whose fill is optimal in order for regular 3D meshes, O(n^{4/3}) entries and
//! O(n²) flops (George 1973; Lipton, Rose & Tarjan 1979), and the meshes here are grid
//! cells, where a coordinate plane through the median node is a small separator.
//!
//! The separator is taken from the graph, not the geometry, so the ordering is valid for
//! any mesh (cracks' duplicated nodes, holes, several pieces): the nodes are split by a
//! plane normal to the longest side of their bounding box at the median coordinate, and
//! the separator is every node on the upper side with a neighbour (a node of a shared
//! element) on the lower side; removing it disconnects the two sides. Each side is
//! ordered the same way, then the separator last. Everything is a deterministic function
//! of the mesh (ties by node index), so the factorisation is reproducible.
//!
//! faer takes the result as a custom symmetric ordering (`SymmetricOrdering::Custom`,
//! checked in crates.md terms: `fwd[new] = old`).

/// Nodes at or below this count are not split further (their order is the mesh's).
const LEAF: usize = 64;

/// The node graph of a mesh: `neighbours(a)` are the nodes sharing an element with `a`.
struct NodeGraph {
    ptr: Vec<usize>,
    adj: Vec<u32>,
}

impl NodeGraph {
    fn new<const K: usize>(n_nodes: usize, elements: &[[usize; K]]) -> NodeGraph {
        let mut count = vec![0usize; n_nodes + 1];
        for conn in elements {
            for &a in conn {
                count[a + 1] += K - 1;
            }
        }
        for a in 0..n_nodes {
            count[a + 1] += count[a];
        }
        let mut fill = count.clone();
        let mut adj = vec![0u32; count[n_nodes]];
        for conn in elements {
            for &a in conn {
                for &b in conn.iter().filter(|&&b| b != a) {
                    adj[fill[a]] = b as u32;
                    fill[a] += 1;
                }
            }
        }
        // Sort and remove repeats row by row, compacting in place.
        let mut ptr = vec![0usize; n_nodes + 1];
        let mut out = 0;
        for a in 0..n_nodes {
            let row = &mut adj[count[a]..count[a + 1]];
            row.sort_unstable();
            let mut last = u32::MAX;
            for k in count[a]..count[a + 1] {
                let b = adj[k];
                if b != last {
                    adj[out] = b;
                    out += 1;
                    last = b;
                }
            }
            ptr[a + 1] = out;
        }
        adj.truncate(out);
        NodeGraph { ptr, adj }
    }

    fn neighbours(&self, a: usize) -> &[u32] {
        &self.adj[self.ptr[a]..self.ptr[a + 1]]
    }
}

/// The nested-dissection order of the nodes of a mesh with node positions `pos` and
/// elements of `K` nodes: `order[k]` is the node eliminated k-th.
pub fn nested_dissection<const D: usize, const K: usize>(pos: &[[f64; D]], elements: &[[usize; K]]) -> Vec<usize> {
    let n = pos.len();
    let graph = NodeGraph::new(n, elements);
    let mut label = vec![0u32; n];
    let mut next_label = 0u32;
    let mut order = Vec::with_capacity(n);
    dissect((0..n).collect(), pos, &graph, &mut label, &mut next_label, &mut order);
    order
}

fn dissect<const D: usize>(
    mut nodes: Vec<usize>,
    pos: &[[f64; D]],
    graph: &NodeGraph,
    label: &mut [u32],
    next_label: &mut u32,
    order: &mut Vec<usize>,
) {
    if nodes.len() <= LEAF {
        nodes.sort_unstable();
        order.extend(nodes);
        return;
    }
    // Axes by decreasing extent of the bounding box (ties: lower axis first).
    let mut lo = [f64::INFINITY; D];
    let mut hi = [f64::NEG_INFINITY; D];
    for &a in &nodes {
        for d in 0..D {
            lo[d] = lo[d].min(pos[a][d]);
            hi[d] = hi[d].max(pos[a][d]);
        }
    }
    let mut axes: [usize; D] = std::array::from_fn(|d| d);
    axes.sort_by(|&a, &b| (hi[b] - lo[b]).total_cmp(&(hi[a] - lo[a])).then(a.cmp(&b)));
    for axis in axes {
        let key = |a: &usize| (pos[*a][axis], *a);
        let mid = nodes.len() / 2;
        nodes.select_nth_unstable_by(mid, |a, b| key(a).0.total_cmp(&key(b).0).then(key(a).1.cmp(&key(b).1)));
        let m = pos[nodes[mid]][axis];
        // Lower side: coordinate < m; if that is empty (over half the nodes on the lowest
        // plane), coordinate ≤ m.
        let below = |a: usize| pos[a][axis] < m;
        let (lower, upper): (Vec<usize>, Vec<usize>) = if nodes.iter().any(|&a| below(a)) {
            nodes.iter().partition(|&&a| below(a))
        } else {
            nodes.iter().partition(|&&a| pos[a][axis] <= m)
        };
        if lower.is_empty() || upper.is_empty() {
            continue; // every node on one plane normal to this axis: try the next axis
        }
        *next_label += 1;
        let id = *next_label;
        for &a in &lower {
            label[a] = id;
        }
        let (separator, rest): (Vec<usize>, Vec<usize>) =
            upper.into_iter().partition(|&a| graph.neighbours(a).iter().any(|&b| label[b as usize] == id));
        dissect(lower, pos, graph, label, next_label, order);
        dissect(rest, pos, graph, label, next_label, order);
        let mut separator = separator;
        separator.sort_unstable();
        order.extend(separator);
        return;
    }
    // All nodes at one point: nothing to split.
    nodes.sort_unstable();
    order.extend(nodes);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_mesh(n: usize) -> (Vec<[f64; 3]>, Vec<[usize; 8]>) {
        let id = |i: usize, j: usize, k: usize| (k * (n + 1) + j) * (n + 1) + i;
        let mut pos = vec![[0.0; 3]; (n + 1).pow(3)];
        for k in 0..=n {
            for j in 0..=n {
                for i in 0..=n {
                    pos[id(i, j, k)] = [i as f64, j as f64, k as f64];
                }
            }
        }
        let mut elements = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    elements.push(super::super::mesh3::CELL_CORNERS.map(|c| id(i + c[0], j + c[1], k + c[2])));
                }
            }
        }
        (pos, elements)
    }

    /// The order is a permutation, and every separator really separates: when a node is
    /// eliminated, no neighbour eliminated later lies outside the nodes of its dissection
    /// box — checked here through the defining property of an elimination order with
    /// small fill: the last node eliminated among the first half of the order has no
    /// neighbour in the second half except the separators.
    #[test]
    fn order_is_a_permutation_and_the_top_separator_is_one_plane() {
        let n = 12;
        let (pos, elements) = grid_mesh(n);
        let order = nested_dissection(&pos, &elements);
        let mut seen = vec![false; pos.len()];
        for &a in &order {
            assert!(!seen[a], "node {a} twice");
            seen[a] = true;
        }
        assert!(seen.iter().all(|&s| s));
        // The top-level separator (eliminated last) is one plane of (n+1)² nodes.
        let plane = (n + 1) * (n + 1);
        let last: Vec<usize> = order[order.len() - plane..].to_vec();
        let axis_value = pos[last[0]][0];
        assert!(last.iter().all(|&a| pos[a][0] == axis_value), "top separator is not the plane x = {axis_value}");
        // Removing it disconnects the two sides.
        let graph = NodeGraph::new(pos.len(), &elements);
        for a in 0..pos.len() {
            if pos[a][0] < axis_value {
                assert!(graph.neighbours(a).iter().all(|&b| pos[b as usize][0] <= axis_value));
            }
        }
    }

    /// A mesh in two pieces and one with duplicated (crack) nodes order without panics,
    /// and a degenerate set of coincident nodes is a leaf.
    #[test]
    fn pieces_and_coincident_nodes() {
        let (mut pos, mut elements) = grid_mesh(5);
        let shift = pos.len();
        let (pos2, el2) = grid_mesh(5);
        pos.extend(pos2.iter().map(|p| [p[0] + 10.0, p[1], p[2]]));
        elements.extend(el2.iter().map(|e| e.map(|a| a + shift)));
        let order = nested_dissection(&pos, &elements);
        assert_eq!(order.len(), pos.len());
        let same = vec![[1.0, 2.0, 3.0]; 200];
        let order = nested_dissection::<3, 8>(&same, &[]);
        assert_eq!(order, (0..200).collect::<Vec<_>>());
    }
}
