//! Reference (rest) distances between contact segments, `dbar_ij` of docs/MODEL.md,
//! "Thickness contact".
//!
//! The filter measures `dbar_ij` in the undeformed mesh. For a rod that is the
//! distance *along* the rod: the rest arc length between two segments (in
//! `u`), not their Euclidean distance in the initial shape. Yarns are joined
//! by persistent EoL contact nodes (one `x` shared by two yarns), so two
//! segments of different yarns near the same crossing are close in the rest
//! structure too.
//!
//! **Our approximation:** one weighted graph whose vertices are the spatial
//! nodes and whose edges are the segments, weighted by their rest length
//! `|u_b - u_a|`. A contact node is a single vertex, so paths may change yarn
//! there at no cost. `dbar_ij` is the shortest path between the closer
//! endpoints of the two segments (0 when they share a node). Along one yarn
//! without crossings it is exactly the `u` gap between the segments. Only
//! whether `dbar < h` matters to the filter, so Dijkstra stops at the
//! thickness `h` and anything farther reads as infinity: the search visits
//! the handful of segments within `h`, not the whole fabric.
//!
//! `dbar_min` (docs/MODEL.md, "Thickness contact") is the smallest positive `dbar` over all
//! pairs. A path between two segments that share no node contains at least
//! one whole segment, and a segment `m` with other segments attached at both
//! ends realises its own length (the two neighbours are `m` apart). So
//! `dbar_min` is the shortest segment with neighbours at both ends (ignoring
//! three-segment cycles, which yarns do not form).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Contact segments with their rest data.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactSegments {
    /// Node indices (into the position array) of each segment's ends.
    pub nodes: Vec<[usize; 2]>,
    /// Yarn of each segment.
    pub yarn: Vec<u32>,
    /// Index of the segment along its yarn (0, 1, 2, ...), for culling windows.
    pub index_in_yarn: Vec<u32>,
    /// Rest length `|u_b - u_a|` of each segment.
    pub rest_length: Vec<f64>,
}

impl ContactSegments {
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Largest node index + 1.
    pub fn node_count(&self) -> usize {
        self.nodes.iter().flatten().map(|&n| n + 1).max().unwrap_or(0)
    }
}

/// The rest-length graph over nodes (CSR adjacency).
#[derive(Clone, Debug)]
pub struct RestGraph {
    starts: Vec<usize>,
    /// `(neighbour node, rest length)`.
    adjacency: Vec<(usize, f64)>,
    min_reference: f64,
}

impl RestGraph {
    pub fn new(segments: &ContactSegments) -> Self {
        let n = segments.node_count();
        let mut degree = vec![0usize; n + 1];
        for s in &segments.nodes {
            degree[s[0]] += 1;
            degree[s[1]] += 1;
        }
        let mut starts = vec![0usize; n + 1];
        for v in 0..n {
            starts[v + 1] = starts[v] + degree[v];
        }
        let mut fill = starts.clone();
        let mut adjacency = vec![(0, 0.0); starts[n]];
        for (s, &len) in segments.nodes.iter().zip(&segments.rest_length) {
            for (a, b) in [(s[0], s[1]), (s[1], s[0])] {
                adjacency[fill[a]] = (b, len);
                fill[a] += 1;
            }
        }
        let min_reference = segments
            .nodes
            .iter()
            .zip(&segments.rest_length)
            .filter(|(s, &len)| len > 0.0 && degree[s[0]] > 1 && degree[s[1]] > 1)
            .map(|(_, &len)| len)
            .fold(f64::INFINITY, f64::min);
        Self {
            starts,
            adjacency,
            min_reference,
        }
    }

    /// `dbar_min`: the smallest positive reference distance (infinite if no
    /// two segments are separated by a third).
    pub fn min_reference_distance(&self) -> f64 {
        self.min_reference
    }

    fn neighbours(&self, v: usize) -> &[(usize, f64)] {
        &self.adjacency[self.starts[v]..self.starts[v + 1]]
    }

    /// `dbar` from segment `from` to each of `targets` (segment node pairs),
    /// or infinity when it is at least `cutoff`.
    pub fn reference_distances(&self, from: [usize; 2], targets: &[[usize; 2]], cutoff: f64) -> Vec<f64> {
        let mut search = Search::default();
        search.run(self, from, cutoff);
        targets.iter().map(|t| search.get(t[0]).min(search.get(t[1]))).collect()
    }

    /// `dbar` between two segments, or infinity when at least `cutoff`.
    pub fn reference_distance(&self, a: [usize; 2], b: [usize; 2], cutoff: f64) -> f64 {
        self.reference_distances(a, &[b], cutoff)[0]
    }
}

/// A truncated multi-source Dijkstra; the sparse map keeps it proportional
/// to the visited neighbourhood, not to the graph.
#[derive(Default)]
struct Search {
    dist: std::collections::HashMap<usize, f64>,
}

impl Search {
    fn run(&mut self, graph: &RestGraph, sources: [usize; 2], cutoff: f64) {
        self.dist.clear();
        // Non-negative f64 order like their bit patterns.
        let mut heap = BinaryHeap::new();
        for s in sources {
            self.dist.insert(s, 0.0);
            heap.push(Reverse((0u64, s)));
        }
        while let Some(Reverse((bits, v))) = heap.pop() {
            let d = f64::from_bits(bits);
            if d > self.get(v) {
                continue;
            }
            for &(w, len) in graph.neighbours(v) {
                let nd = d + len;
                if nd < cutoff && nd < self.get(w) {
                    self.dist.insert(w, nd);
                    heap.push(Reverse((nd.to_bits(), w)));
                }
            }
        }
    }

    fn get(&self, v: usize) -> f64 {
        self.dist.get(&v).copied().unwrap_or(f64::INFINITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two straight yarns of 6 segments (lengths 1, 2, 1, 0.5, 1, 1) crossing
    /// at a shared contact node: yarn 0 is nodes 0..=6, yarn 1 is 7, 8, 3, 9.
    fn fabric() -> ContactSegments {
        let lens = [1.0, 2.0, 1.0, 0.5, 1.0, 1.0];
        let mut s = ContactSegments::default();
        for (k, &len) in lens.iter().enumerate() {
            s.nodes.push([k, k + 1]);
            s.yarn.push(0);
            s.index_in_yarn.push(k as u32);
            s.rest_length.push(len);
        }
        for (k, (a, b, len)) in [(7, 8, 0.3), (8, 3, 0.4), (3, 9, 0.7)].into_iter().enumerate() {
            s.nodes.push([a, b]);
            s.yarn.push(1);
            s.index_in_yarn.push(k as u32);
            s.rest_length.push(len);
        }
        s
    }

    #[test]
    fn along_one_yarn_is_the_u_gap() {
        let g = RestGraph::new(&fabric());
        // Segments 0 [0,1] and 2 [2,3]: the middle segment, length 2.
        assert_eq!(g.reference_distance([0, 1], [2, 3], 10.0), 2.0);
        // Segments 0 and 5: 2 + 1 + 0.5 + 1 by hand.
        assert_eq!(g.reference_distance([0, 1], [5, 6], 10.0), 4.5);
        // Sharing a node: 0. Beyond the cutoff: infinity.
        assert_eq!(g.reference_distance([0, 1], [1, 2], 10.0), 0.0);
        assert_eq!(g.reference_distance([0, 1], [5, 6], 4.0), f64::INFINITY);
    }

    #[test]
    fn across_yarns_through_the_contact_node() {
        let s = fabric();
        let g = RestGraph::new(&s);
        // Yarn 1's first segment [7,8] to yarn 0's segment [4,5]:
        // 8 -> 3 (0.4) -> 4 (0.5) = 0.9.
        assert!((g.reference_distance([7, 8], [4, 5], 10.0) - 0.9).abs() < 1e-15);
        // dbar_min: the shortest segment with neighbours at both ends is
        // 8-3 (0.4); 7-8 (0.3) is a yarn end.
        assert_eq!(g.min_reference_distance(), 0.4);
    }
}
