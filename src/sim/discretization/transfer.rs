//! State transfer when the EIL assignment changes (docs/MODEL.md,
//! "State transfer").
//!
//! A contact's two yarn points share one node while both are real. When one
//! of them becomes EIL its `x` is no longer a DOF but the interpolation on
//! its yarn's chord, and the soft constraint `kc |x_eil(u) - x_partner|^2`
//! takes over with `kc = 1000 ks / du`. Left where it was, the shared node
//! sits at the old vertex of the bent yarn, off the new chord by the
//! sagitta. The same holds when an EIL point's chord changes because a
//! neighbour turned EIL. On an 8x8 linen stitch that is ~0.1 mm, an energy jump of about
//! 0.5 J against an equilibrium energy of 7.5e-3 J, which the next Newton
//! solve spent its whole iteration budget undoing (measured: every step at
//! the 20-iteration cap). So every transition puts the constraint at rest:
//!
//! - **one point becomes EIL, the partner is real**: the node (now the
//!   partner's alone) moves onto the EIL point's interpolated position. The
//!   partner yarn bends by the sagitta, at its own (soft) stretch and bending
//!   cost.
//! - **both points EIL**: both `u` move to the closest points of the two
//!   chords (what remains is the chords' distance, which only the real
//!   nodes can close).
//! - **an EIL point returns to real** (EIL to EoL): if its partner
//!   was real the node is already where the constraint held it; if both
//!   were EIL the node goes on the front yarn's new chord at its `u`.

use super::assignment::Assignment;
use super::dofs::DofLayout;
use super::interpolated;
use crate::topology::{Fabric, PointRef};

/// Updates `q` for the change of assignment `old -> new`. A contact is
/// touched when its points' kinds changed or an EIL point's interpolation
/// neighbours did (a neighbour turning EIL widens the chord it lies on).
pub fn transfer(f: &Fabric, l: &DofLayout, old: &Assignment, new: &Assignment, q: &mut [f64]) {
    let kind = |a: &Assignment, p: PointRef| a.is_eil(l, p).then(|| a.interpolation_neighbours(l, p));
    // A node whose points are all EIL is no unknown, so its stored `x` is
    // stale: wherever a step that last had it real left it. Other contacts'
    // chords end at this node as soon as one of its points turns real, so
    // it must first go where its points are (its front point's
    // interpolation; the both-EIL case below keeps the two together).
    // Measured (stockinette 12x12, 60 steps): a node 2.6 mm from where
    // its points were became the end of a neighbouring contact's chord,
    // and that re-assignment raised the energy 58-fold (1.9e-2 -> 1.1 J).
    for c in &f.contacts {
        if old.is_eil(l, c.front) && old.is_eil(l, c.back) {
            let at = interpolated(f, l, old, q, c.front);
            let x = l.x(c.node);
            q[x..x + 3].copy_from_slice(at.as_slice());
        }
    }
    for c in &f.contacts {
        let was = (old.is_eil(l, c.front), old.is_eil(l, c.back));
        let now = (new.is_eil(l, c.front), new.is_eil(l, c.back));
        let changed = was != now || kind(old, c.front) != kind(new, c.front) || kind(old, c.back) != kind(new, c.back);
        if !changed {
            continue;
        }
        let x = l.x(c.node);
        match now {
            (true, false) | (false, true) => {
                let eil = if now.0 { c.front } else { c.back };
                let at = interpolated(f, l, new, q, eil);
                q[x..x + 3].copy_from_slice(at.as_slice());
            }
            (true, true) => {
                // Alternating projections converge to the closest points of
                // the two chords; a few sweeps are plenty at chord scale.
                for _ in 0..4 {
                    let target = interpolated(f, l, new, q, c.back);
                    project_u(f, l, new, q, c.front, &target);
                    let target = interpolated(f, l, new, q, c.front);
                    project_u(f, l, new, q, c.back, &target);
                }
            }
            (false, false) => {
                // Both real again. With one of them real before, the node is
                // that point's and stays. With both EIL before, the node goes
                // on the front yarn's new chord at the front's `u`: the old
                // interpolation would clamp a point that slid past a real
                // neighbour onto that neighbour (a zero-length segment).
                if was == (true, true) {
                    if let Some(at) = on_new_chord(f, l, new, q, c.front) {
                        q[x..x + 3].copy_from_slice(at.as_slice());
                    }
                }
            }
        }
    }
}

/// Position of real point `p` interpolated at its `u` between the real
/// points of its yarn that bracket it in the new order (`p` excluded).
fn on_new_chord(f: &Fabric, l: &DofLayout, a: &Assignment, q: &[f64], p: PointRef) -> Option<nalgebra::Vector3<f64>> {
    let ord = &a.orders()[p.yarn];
    let k = a.rank(p);
    let real = |i: &&usize| {
        !a.is_eil(
            l,
            PointRef {
                yarn: p.yarn,
                point: **i,
            },
        )
    };
    let prev = *ord[..k].iter().rev().find(real)?;
    let next = *ord[k + 1..].iter().find(real)?;
    let y = &f.yarns[p.yarn];
    let u = |i: usize| q[l.u(PointRef { yarn: p.yarn, point: i })];
    let (ua, uc) = (u(prev), u(next));
    let s = if uc > ua {
        ((u(p.point) - ua) / (uc - ua)).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let (xa, xc) = (l.node_x(q, y.points[prev].node), l.node_x(q, y.points[next].node));
    Some(xa * (1.0 - s) + xc * s)
}

/// Moves the `u` of EIL point `p` to the point of its interpolation chord
/// closest to `target`.
fn project_u(f: &Fabric, l: &DofLayout, a: &Assignment, q: &mut [f64], p: PointRef, target: &nalgebra::Vector3<f64>) {
    let Some((pa, pc)) = a.interpolation_neighbours(l, p) else {
        return;
    };
    let y = &f.yarns[p.yarn];
    let (xa, xc) = (l.node_x(q, y.points[pa].node), l.node_x(q, y.points[pc].node));
    let ua = q[l.u(PointRef {
        yarn: p.yarn,
        point: pa,
    })];
    let uc = q[l.u(PointRef {
        yarn: p.yarn,
        point: pc,
    })];
    let d = xc - xa;
    let len2 = d.norm_squared();
    if len2 <= 0.0 || uc <= ua {
        return;
    }
    // Stay strictly inside the interval so the sorted order is unchanged.
    let s = ((target - xa).dot(&d) / len2).clamp(1e-3, 1.0 - 1e-3);
    q[l.u(p)] = ua + s * (uc - ua);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::discretization::assignment::{assign, rest_segment_lengths, tests::crossing_fabric};
    use crate::sim::params::AssignParams;

    /// Yarn A bends at the contact node (vertex at z = 0.1 above its chord);
    /// yarn B passes straight through the node along y.
    fn bent_crossing() -> Fabric {
        crossing_fabric(
            &[
                [0.5, 0.0, 0.1],
                [0.0, 0.0, 0.0],
                [0.49, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.5, -0.5, 0.1],
                [0.5, 0.5, 0.1],
            ],
            [
                &[(1, 0.0, true), (2, 0.49, true), (0, 0.5, false), (3, 1.0, true)],
                &[(4, 0.0, true), (0, 0.5, false), (5, 1.0, true)],
            ],
            1.0,
            2,
            1,
        )
    }

    #[test]
    fn a_point_turning_eil_moves_the_shared_node_onto_its_chord() {
        let f = bent_crossing();
        let l = DofLayout::new(&f);
        let mut q = l.gather(&f);
        // All real: the 0.01 gap to the fixed point at 0.49 is under the
        // safety distance only once the assignment runs.
        let old = Assignment::new(vec![vec![0, 1, 2, 3], vec![0, 1, 2]], vec![false; l.n_points()]);
        let new = assign(&f, &l, &q, &rest_segment_lengths(&f), AssignParams::default());
        let a_contact = PointRef { yarn: 0, point: 2 };
        assert!(new.is_eil(&l, a_contact));
        let before = (l.node_x(&q, 0) - interpolated(&f, &l, &new, &q, a_contact)).norm();
        transfer(&f, &l, &old, &new, &mut q);
        let after = (l.node_x(&q, 0) - interpolated(&f, &l, &new, &q, a_contact)).norm();
        assert!(before > 0.09, "the vertex sat off the chord: {before}");
        assert!(after < 1e-12, "the constraint starts at rest: {after}");
        // Nothing changes on a second call with the same assignment.
        let q1 = q.clone();
        transfer(&f, &l, &new, &new, &mut q);
        assert_eq!(q, q1);
    }

    /// Contact 1 (node 2) has both points EIL and a stale node far away;
    /// contact 0 (node 3) has its yarn-0 point EIL on a chord that, once
    /// contact 1's yarn-0 point turns real, ends at node 2. Contact 0 is
    /// transferred first, so it must not see the stale position.
    #[test]
    fn a_released_all_eil_node_leaves_its_stale_position_before_other_chords_use_it() {
        use crate::sim::discretization::assignment::tests::test_yarn;
        use crate::topology::{Contact, ContactKind};
        let mut f = crossing_fabric(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [10.0, 10.0, 10.0],
                [0.7, 0.0, 0.0],
                [0.4, -0.5, 0.0],
                [0.4, 0.5, 0.0],
                [0.7, -0.5, 0.0],
                [0.7, 0.5, 0.0],
            ],
            [
                &[(0, 0.0, true), (2, 0.4, false), (3, 0.7, false), (1, 1.0, true)],
                &[(4, 0.0, true), (2, 0.5, false), (5, 1.0, true)],
            ],
            1.0,
            1,
            1,
        );
        f.yarns
            .push(test_yarn(&[(6, 0.0, true), (3, 0.5, false), (7, 1.0, true)], 1.0));
        let contact = |node, front, back| Contact {
            node,
            front,
            back,
            kind: ContactKind::Float,
            partner: None,
        };
        let p = |yarn, point| PointRef { yarn, point };
        f.contacts = vec![contact(3, p(0, 2), p(2, 1)), contact(2, p(0, 1), p(1, 1))];
        let l = DofLayout::new(&f);
        let mut q = l.gather(&f);
        let order = vec![vec![0, 1, 2, 3], vec![0, 1, 2], vec![0, 1, 2]];
        let flags = |eil: &[PointRef]| {
            let mut v = vec![false; l.n_points()];
            for &e in eil {
                v[l.point(e)] = true;
            }
            v
        };
        let old = Assignment::new(order.clone(), flags(&[p(0, 1), p(1, 1), p(0, 2)]));
        let new = Assignment::new(order, flags(&[p(1, 1), p(0, 2)]));
        // Where contact 1's points were: u 0.4 on yarn 0's chord (0,0,0)-(1,0,0).
        let was_at = interpolated(&f, &l, &old, &q, p(0, 1));
        assert!((was_at - nalgebra::Vector3::new(0.4, 0.0, 0.0)).norm() < 1e-12);
        transfer(&f, &l, &old, &new, &mut q);
        for node in [2, 3] {
            let x = l.node_x(&q, node);
            assert!(x.norm() < 2.0, "node {node} took the stale position: {x:?}");
        }
        // Contact 0's constraint starts at rest on its new chord (node 2 to node 1).
        let gap = (l.node_x(&q, 3) - interpolated(&f, &l, &new, &q, p(0, 2))).norm();
        assert!(gap < 1e-12, "{gap}");
    }
}
