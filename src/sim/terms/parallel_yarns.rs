//! Parallel-yarn contact (docs/MODEL.md, "Parallel-yarn contact"): two
//! consecutive contact points on a yarn whose crossing yarns lie side by side
//! keep those yarns' centre lines the sum of their radii apart along this
//! one.

use super::{set, TermInputs};
use crate::rod::parallel_contact::{parallel_enabled, CrossingSide, ParallelContact};
use crate::sim::discretization::Discretization;
use crate::sim::params::SimParams;
use crate::solver::assembly::AnyStencilSet;
use crate::topology::{ContactKind, PointRef};

/// The `parallel` set (none while the term is off).
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    if !t.params.terms.parallel {
        return Vec::new();
    }
    let (pt, pd) = parallel_terms(t.disc, t.q, t.params, &t.radii);
    vec![set("parallel", pt, pd)]
}

/// Parallel-yarn contact between consecutive contact points on a yarn,
/// with the enable rules of docs/MODEL.md, "Parallel-yarn contact". The two crossing yarns keep
/// their centre lines the sum of their radii apart along this one.
pub(super) fn parallel_terms(
    disc: &Discretization,
    q: &[f64],
    p: &SimParams,
    radii: &[f64],
) -> (Vec<ParallelContact>, Vec<[u32; 2]>) {
    let (f, l) = (disc.f, disc.l);
    // For each point, the contact it belongs to and the other yarn point.
    let mut other: Vec<Option<(usize, PointRef)>> = vec![None; l.n_points()];
    for (ci, c) in f.contacts.iter().enumerate() {
        other[l.point(c.front)] = Some((ci, c.back));
        other[l.point(c.back)] = Some((ci, c.front));
    }
    let x = |n: usize| l.node_x(q, n);
    let side = |me: PointRef, ci: usize, o: PointRef| -> Option<CrossingSide> {
        let c = &f.contacts[ci];
        let (op, on) = disc.real_neighbours(o)?;
        let (mp, mn) = disc.real_neighbours(me)?;
        // Normal from the crossing yarn toward this yarn: front/back order.
        let my_axis = x(disc.node(me.yarn, mn)) - x(disc.node(me.yarn, mp));
        let their_axis = x(disc.node(o.yarn, on)) - x(disc.node(o.yarn, op));
        let mut n = my_axis.cross(&their_axis).try_normalize(1e-300)?;
        if (c.front == me) != (n.z > 0.0) {
            n = -n;
        }
        Some(CrossingSide::from_nodes(
            matches!(c.kind, ContactKind::Layer | ContactKind::Seam),
            n,
            &x(c.node),
            &x(disc.node(o.yarn, op)),
            &x(disc.node(o.yarn, on)),
        ))
    };
    let (mut t, mut d) = (vec![], vec![]);
    for (y, ord) in disc.a.orders().iter().enumerate() {
        let contacts: Vec<usize> = ord
            .iter()
            .copied()
            .filter(|&pi| other[l.point(PointRef { yarn: y, point: pi })].is_some())
            .collect();
        for w in contacts.windows(2) {
            let (p1, p2) = (PointRef { yarn: y, point: w[0] }, PointRef { yarn: y, point: w[1] });
            if disc.is_eil(p1) || disc.is_eil(p2) {
                continue;
            }
            let (Some((c1, o1)), Some((c2, o2))) = (other[l.point(p1)], other[l.point(p2)]) else {
                continue;
            };
            // The two nodes of one stitch contact are one crossing, not two parallel yarns.
            if f.contacts[c1].partner == Some(f.contacts[c2].node) {
                continue;
            }
            let (Some(s1), Some(s2)) = (side(p1, c1, o1), side(p2, c2, o2)) else {
                continue;
            };
            if parallel_enabled(&s1, &s2) {
                t.push(ParallelContact::new(p.rod.kp, radii[o1.yarn] + radii[o2.yarn]));
                d.push([l.u(p1) as u32, l.u(p2) as u32]);
            }
        }
    }
    (t, d)
}
