//! Per-step EoL/EIL node assignment (docs/MODEL.md, "Node assignment").
//!
//! Each step, before the first Newton iteration, every yarn's points are
//! sorted by their current `u` and walked in order. A point closer in `u`
//! than the safety distance to the previous non-EIL point becomes EIL: its
//! `x` is then interpolated, so the degenerate segment never enters stretch,
//! bending or mass terms. If that point has a fixed `u` (yarn end, resolution
//! node) it must stay a real node, so the previous non-EIL point is demoted
//! instead. Storage order of points never changes (dof indices are stable);
//! the sorted order lives here.

use super::dofs::DofLayout;
use crate::sim::params::AssignParams;
use crate::topology::{Fabric, PointRef};

/// The discretization of one step.
#[derive(Clone, Debug, PartialEq)]
pub struct Assignment {
    /// Per yarn, its point indices sorted by current `u` (private so that
    /// it cannot drift from `rank`).
    order: Vec<Vec<usize>>,
    /// Per global point number (see [`DofLayout::point`]): is it EIL?
    pub eil: Vec<bool>,
    /// Per yarn, each point's place in `order` (the inverse permutation),
    /// so a point's sorted neighbours are found without a scan: a flat
    /// fabric is one yarn, and a scan per point made every step's set-up
    /// quadratic in the fabric size.
    rank: Vec<Vec<usize>>,
}

impl Assignment {
    pub fn new(order: Vec<Vec<usize>>, eil: Vec<bool>) -> Self {
        let rank = order
            .iter()
            .map(|ord| {
                let mut r = vec![0; ord.len()];
                for (k, &pi) in ord.iter().enumerate() {
                    r[pi] = k;
                }
                r
            })
            .collect();
        Assignment { order, eil, rank }
    }

    /// Per yarn, its point indices sorted by current `u`.
    pub fn orders(&self) -> &[Vec<usize>] {
        &self.order
    }

    /// Place of point `p` in its yarn's `u` order.
    pub fn rank(&self, p: PointRef) -> usize {
        self.rank[p.yarn][p.point]
    }

    pub fn is_eil(&self, layout: &DofLayout, p: PointRef) -> bool {
        self.eil[layout.point(p)]
    }

    pub fn eil_count(&self) -> usize {
        self.eil.iter().filter(|&&e| e).count()
    }

    /// Sorted non-EIL point indices of a yarn: the rod's discretization.
    pub fn real_points<'a>(&'a self, layout: &'a DofLayout, yarn: usize) -> impl Iterator<Item = usize> + 'a {
        self.order[yarn]
            .iter()
            .copied()
            .filter(move |&pi| !self.eil[layout.yarn_offsets[yarn] + pi])
    }

    /// The non-EIL neighbours (previous, next) in `u` order of an EIL point.
    pub fn interpolation_neighbours(&self, layout: &DofLayout, p: PointRef) -> Option<(usize, usize)> {
        let ord = &self.order[p.yarn];
        let k = self.rank(p);
        let off = layout.yarn_offsets[p.yarn];
        let prev = ord[..k].iter().rev().copied().find(|&i| !self.eil[off + i])?;
        let next = ord[k + 1..].iter().copied().find(|&i| !self.eil[off + i])?;
        Some((prev, next))
    }
}

/// Mean rest segment length of each yarn, in the compiled (rest) fabric.
pub fn rest_segment_lengths(f: &Fabric) -> Vec<f64> {
    f.yarns
        .iter()
        .map(|y| y.rest_length / (y.points.len().max(2) - 1) as f64)
        .collect()
}

/// Assigns EIL points for the coordinates `q`.
pub fn assign(f: &Fabric, layout: &DofLayout, q: &[f64], rest_seg: &[f64], p: AssignParams) -> Assignment {
    assign_after(f, layout, q, rest_seg, p, None)
}

/// [`assign`] with memory: points EIL in `prev` use the release distance.
pub fn assign_after(
    f: &Fabric,
    layout: &DofLayout,
    q: &[f64],
    rest_seg: &[f64],
    p: AssignParams,
    prev: Option<&Assignment>,
) -> Assignment {
    let mut order = Vec::with_capacity(f.yarns.len());
    let mut eil = vec![false; layout.n_points()];
    for (yi, y) in f.yarns.iter().enumerate() {
        let off = layout.yarn_offsets[yi];
        let u = |pi: usize| q[3 * layout.n_nodes + off + pi];
        let mut ord: Vec<usize> = (0..y.points.len()).collect();
        // Ties keep storage order, so the assignment is deterministic.
        ord.sort_by(|&a, &b| u(a).total_cmp(&u(b)).then(a.cmp(&b)));
        if p.enable_eil {
            let d = p.safety_fraction * rest_seg[yi];
            let d_release = p.release_fraction.max(p.safety_fraction) * rest_seg[yi];
            let was_eil = |pi: usize| prev.is_some_and(|a| a.eil[off + pi]);
            // Per sorted position, the `u` of the next point that stays a
            // node for sure (real before, or fixed): an EIL point is released
            // only with room on both sides, otherwise releasing it would
            // demote its next neighbour in the same pass (two transitions,
            // and a new segment of near-zero length in between).
            let mut next_anchor = vec![f64::INFINITY; ord.len()];
            for k in (0..ord.len().saturating_sub(1)).rev() {
                let n = ord[k + 1];
                next_anchor[k] = if y.points[n].fixed_u || !was_eil(n) {
                    u(n)
                } else {
                    next_anchor[k + 1]
                };
            }
            let mut last: Option<usize> = None;
            for (k, &pi) in ord.iter().enumerate() {
                let Some(l) = last else {
                    last = Some(pi);
                    continue;
                };
                let room = if was_eil(pi) {
                    u(pi) - u(l) >= d_release && next_anchor[k] - u(pi) >= d_release
                } else {
                    u(pi) - u(l) >= d
                };
                if room {
                    last = Some(pi);
                } else if !y.points[pi].fixed_u {
                    eil[off + pi] = true;
                } else if !y.points[l].fixed_u {
                    // A fixed-u point must stay a node: demote the previous one.
                    eil[off + l] = true;
                    last = Some(pi);
                } else {
                    // Two fixed points closer than d: the rest discretization
                    // itself; both stay real.
                    last = Some(pi);
                }
            }
        }
        order.push(ord);
    }
    Assignment::new(order, eil)
}

/// Which coordinates are unknowns this step: not pinned, not a fixed `u`,
/// and for a node, at least one of its yarn points is non-EIL.
pub fn free_mask(f: &Fabric, layout: &DofLayout, a: &Assignment) -> Vec<bool> {
    let mut free = vec![false; layout.len()];
    for (yi, y) in f.yarns.iter().enumerate() {
        for (pi, pt) in y.points.iter().enumerate() {
            let r = PointRef { yarn: yi, point: pi };
            if !pt.fixed_u {
                free[layout.u(r)] = true;
            }
            if !a.is_eil(layout, r) && !f.nodes[pt.node].pinned {
                let x = layout.x(pt.node);
                free[x..x + 3].iter_mut().for_each(|v| *v = true);
            }
        }
    }
    free
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::pattern::{Construction, Gauge, Meta, YarnSpec};
    use crate::topology::{Node, Vec3, Yarn, YarnPoint};

    /// One red yarn of radius 0.5 mm; the sim tests' fabric metadata.
    pub(crate) fn meta() -> Meta {
        Meta {
            name: "t".into(),
            gauge: Gauge {
                stitches_per_10cm: 20.0,
                rows_per_10cm: 28.0,
            },
            yarns: vec![YarnSpec {
                name: "a".into(),
                color: [200, 0, 0],
                radius: 5e-4,
                material: None,
            }],
            construction: Construction::Flat,
            width: 1,
            height: 1,
            looseness: 1.0,
        }
    }

    /// Two yarns of rest length `rest_length` through `nodes`, each point
    /// given as `(node, u, fixed_u)`, crossing at node 0: one float contact
    /// between point `front` of yarn 0 and point `back` of yarn 1.
    /// A yarn of spec 0 through `(node, u, fixed_u)` points, none EIL.
    pub(crate) fn test_yarn(points: &[(usize, f64, bool)], rest_length: f64) -> Yarn {
        Yarn {
            layer: 0,
            spec: 0,
            rest_length,
            points: points
                .iter()
                .map(|&(node, u, fixed_u)| YarnPoint {
                    node,
                    u,
                    fixed_u,
                    eil: false,
                })
                .collect(),
        }
    }

    pub(crate) fn crossing_fabric(
        nodes: &[[f64; 3]],
        yarns: [&[(usize, f64, bool)]; 2],
        rest_length: f64,
        front: usize,
        back: usize,
    ) -> Fabric {
        use crate::topology::{Contact, ContactKind};
        Fabric {
            meta: meta(),
            nodes: nodes
                .iter()
                .map(|&[x, y, z]| Node {
                    x: Vec3::new(x, y, z),
                    pinned: false,
                })
                .collect(),
            yarns: yarns.iter().map(|pts| test_yarn(pts, rest_length)).collect(),
            contacts: vec![Contact {
                node: 0,
                front: PointRef { yarn: 0, point: front },
                back: PointRef { yarn: 1, point: back },
                kind: ContactKind::Float,
                partner: None,
            }],
            sim: None,
        }
    }

    /// One straight yarn with points at the given u's; `fixed` marks fixed-u points.
    fn yarn(us: &[(f64, bool)]) -> Fabric {
        let nodes = us
            .iter()
            .map(|&(u, _)| Node {
                x: Vec3::new(u, 0.0, 0.0),
                pinned: false,
            })
            .collect();
        let points = us
            .iter()
            .enumerate()
            .map(|(i, &(u, fixed_u))| YarnPoint {
                node: i,
                u,
                fixed_u,
                eil: false,
            })
            .collect();
        Fabric {
            meta: meta(),
            nodes,
            yarns: vec![Yarn {
                layer: 0,
                spec: 0,
                rest_length: 1.0,
                points,
            }],
            contacts: vec![],
            sim: None,
        }
    }

    #[test]
    fn close_sliding_point_becomes_eil_and_fixed_point_demotes_previous() {
        // Rest segment 0.25 -> safety distance 0.025.
        let f = yarn(&[(0.0, true), (0.5, false), (0.51, false), (0.99, false), (1.0, true)]);
        let l = DofLayout::new(&f);
        let q = l.gather(&f);
        let a = assign(&f, &l, &q, &rest_segment_lengths(&f), AssignParams::default());
        assert_eq!(a.eil, vec![false, false, true, true, false]);
        assert_eq!(a.eil_count(), 2);
        assert_eq!(
            a.interpolation_neighbours(&l, PointRef { yarn: 0, point: 2 }),
            Some((1, 4))
        );
        let free = free_mask(&f, &l, &a);
        // EIL points keep a free u but their node x is cancelled.
        assert!(free[l.u(PointRef { yarn: 0, point: 2 })]);
        assert!(!free[l.x(2)] && !free[l.x(3)] && free[l.x(1)]);
        // Fixed-u ends are not unknowns in u.
        assert!(!free[l.u(PointRef { yarn: 0, point: 0 })]);
    }

    #[test]
    fn crossing_points_are_resorted_and_eil_can_be_disabled() {
        let f = yarn(&[(0.0, true), (0.6, false), (0.4, false), (1.0, true)]);
        let l = DofLayout::new(&f);
        let q = l.gather(&f);
        let a = assign(&f, &l, &q, &rest_segment_lengths(&f), AssignParams::default());
        assert_eq!(a.order[0], vec![0, 2, 1, 3]);
        assert_eq!(a.eil_count(), 0);
        let mut q2 = q.clone();
        q2[l.u(PointRef { yarn: 0, point: 2 })] = 0.6 - 1e-9;
        let on = assign(&f, &l, &q2, &rest_segment_lengths(&f), AssignParams::default());
        assert_eq!(on.eil_count(), 1);
        let off = assign(
            &f,
            &l,
            &q2,
            &rest_segment_lengths(&f),
            AssignParams {
                enable_eil: false,
                ..Default::default()
            },
        );
        assert_eq!(off.eil_count(), 0);
    }

    #[test]
    fn an_eil_point_turns_real_only_past_the_release_distance() {
        // Rest segment 1/3: safety 0.033, release 0.067.
        let f = yarn(&[(0.0, true), (0.5, false), (0.51, false), (1.0, true)]);
        let l = DofLayout::new(&f);
        let rs = rest_segment_lengths(&f);
        let p = AssignParams::default();
        let mut q = l.gather(&f);
        let first = assign(&f, &l, &q, &rs, p);
        assert_eq!(first.eil_count(), 1);
        let u2 = l.u(PointRef { yarn: 0, point: 2 });
        // Between the safety and the release distance: stays EIL with
        // memory, is real without.
        q[u2] = 0.5 + 0.05;
        assert_eq!(assign_after(&f, &l, &q, &rs, p, Some(&first)).eil_count(), 1);
        assert_eq!(assign(&f, &l, &q, &rs, p).eil_count(), 0);
        // Past the release distance: real again.
        q[u2] = 0.5 + 0.08;
        assert_eq!(assign_after(&f, &l, &q, &rs, p, Some(&first)).eil_count(), 0);
        // An infinite release distance (`RelaxOptions::keep_eil`)
        // keeps it EIL however far it slides from both neighbours.
        let keep = AssignParams {
            release_fraction: f64::INFINITY,
            ..p
        };
        q[u2] = 0.75;
        assert_eq!(assign_after(&f, &l, &q, &rs, p, Some(&first)).eil_count(), 0);
        assert_eq!(assign_after(&f, &l, &q, &rs, keep, Some(&first)).eil, first.eil);
    }

    #[test]
    fn an_eil_point_is_not_released_onto_its_next_neighbour() {
        // Rest segment 0.25: safety 0.025, release 0.05. Point 2 is EIL
        // (0.01 past point 1); point 3 is a real neighbour ahead.
        let f = yarn(&[(0.0, true), (0.5, false), (0.51, false), (0.62, false), (1.0, true)]);
        let l = DofLayout::new(&f);
        let rs = rest_segment_lengths(&f);
        let p = AssignParams::default();
        let mut q = l.gather(&f);
        let first = assign(&f, &l, &q, &rs, p);
        assert_eq!(first.eil, vec![false, false, true, false, false]);
        // Slid to 0.6: room behind (0.1), none ahead (0.02). Releasing it
        // would demote point 3 in the same pass; it stays EIL instead.
        let u2 = l.u(PointRef { yarn: 0, point: 2 });
        q[u2] = 0.6;
        let next = assign_after(&f, &l, &q, &rs, p, Some(&first));
        assert_eq!(next.eil, vec![false, false, true, false, false]);
        // With room on both sides it is released.
        q[u2] = 0.56;
        let next = assign_after(&f, &l, &q, &rs, p, Some(&first));
        assert_eq!(next.eil_count(), 0);
    }
}
