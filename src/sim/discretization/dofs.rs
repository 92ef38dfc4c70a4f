//! The global coordinate vector of an EoL fabric.
//!
//! `q = [x_0, x_1, ..., x_{n-1}, u_0, u_1, ..., u_{m-1}]`: three spatial
//! coordinates per node, then one material coordinate per yarn point (points
//! numbered yarn after yarn). Every coordinate has a slot, including those
//! that are not unknowns right now (pinned nodes, fixed `u`, the node of a
//! contact whose both points are EIL): the system keeps its size and sparsity
//! pattern while points switch between EoL and EIL, and those rows are simply
//! cancelled (docs/MODEL.md, "Fixed system size").

use crate::topology::{Fabric, PointRef, Vec3};

#[derive(Clone, Debug, PartialEq)]
pub struct DofLayout {
    pub n_nodes: usize,
    /// First global point number of each yarn; a final entry closes the last.
    pub yarn_offsets: Vec<usize>,
}

impl DofLayout {
    pub fn new(f: &Fabric) -> Self {
        let mut yarn_offsets = Vec::with_capacity(f.yarns.len() + 1);
        let mut acc = 0;
        for y in &f.yarns {
            yarn_offsets.push(acc);
            acc += y.points.len();
        }
        yarn_offsets.push(acc);
        DofLayout {
            n_nodes: f.nodes.len(),
            yarn_offsets,
        }
    }

    pub fn n_points(&self) -> usize {
        *self.yarn_offsets.last().unwrap_or(&0)
    }

    pub fn len(&self) -> usize {
        3 * self.n_nodes + self.n_points()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Index of `x` (first of three) of node `n`.
    pub fn x(&self, node: usize) -> usize {
        3 * node
    }

    /// Global point number of a yarn point.
    pub fn point(&self, p: PointRef) -> usize {
        self.yarn_offsets[p.yarn] + p.point
    }

    /// Index of `u` of a yarn point.
    pub fn u(&self, p: PointRef) -> usize {
        3 * self.n_nodes + self.point(p)
    }

    /// Gathers the fabric's state into `q`.
    pub fn gather(&self, f: &Fabric) -> Vec<f64> {
        let mut q = vec![0.0; self.len()];
        for (i, n) in f.nodes.iter().enumerate() {
            q[3 * i..3 * i + 3].copy_from_slice(n.x.as_slice());
        }
        for (yi, y) in f.yarns.iter().enumerate() {
            for (pi, p) in y.points.iter().enumerate() {
                q[self.u(PointRef { yarn: yi, point: pi })] = p.u;
            }
        }
        q
    }

    /// Writes `q` back into the fabric (positions and material coordinates).
    pub fn scatter(&self, q: &[f64], f: &mut Fabric) {
        for (i, n) in f.nodes.iter_mut().enumerate() {
            n.x = Vec3::new(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
        }
        for (yi, y) in f.yarns.iter_mut().enumerate() {
            let off = self.yarn_offsets[yi];
            for (pi, p) in y.points.iter_mut().enumerate() {
                p.u = q[3 * self.n_nodes + off + pi];
            }
        }
    }

    /// The node each unknown belongs to: `x` coordinates their node, a
    /// `u` the node of its yarn point (a contact node gets both points'
    /// `u`). The direct solver orders by these groups.
    pub fn node_of_dof(&self, f: &Fabric) -> Vec<u32> {
        let mut node = vec![0u32; self.len()];
        for i in 0..self.n_nodes {
            node[self.x(i)..self.x(i) + 3].fill(i as u32);
        }
        for (y, yarn) in f.yarns.iter().enumerate() {
            for (point, p) in yarn.points.iter().enumerate() {
                node[self.u(PointRef { yarn: y, point })] = p.node as u32;
            }
        }
        node
    }

    /// Position of node `n` in `q`.
    pub fn node_x(&self, q: &[f64], node: usize) -> Vec3 {
        Vec3::new(q[3 * node], q[3 * node + 1], q[3 * node + 2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::discretization::assignment::tests::crossing_fabric;

    #[test]
    fn every_unknown_is_grouped_with_its_node_and_a_contact_node_holds_both_points() {
        // Node 0 is the contact; each yarn also has its own end node.
        let nodes = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let f = crossing_fabric(
            &nodes,
            [&[(1, 0.0, true), (0, 0.5, false)], &[(2, 0.0, true), (0, 0.5, false)]],
            1.0,
            1,
            1,
        );
        let l = DofLayout::new(&f);
        let g = l.node_of_dof(&f);
        assert_eq!(g.len(), l.len());
        assert_eq!(&g[..9], &[0, 0, 0, 1, 1, 1, 2, 2, 2]);
        let u = |yarn, point| g[l.u(PointRef { yarn, point })];
        assert_eq!([u(0, 0), u(0, 1), u(1, 0), u(1, 1)], [1, 0, 2, 0]);
    }
}
