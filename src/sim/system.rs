//! The stencils of one step, for the current EoL/EIL discretization.
//!
//! Per yarn, the sorted non-EIL ("real") points define the rod: stretch and
//! inertia per pair, bending per triple (docs/MODEL.md, "Energies": EIL points are
//! skipped, so a degenerate segment never enters an elastic term). Per
//! contact, an EIL point gets the soft constraint to its partner through the
//! interpolation. Wrapping, shear and parallel-contact terms act on
//! real points only; when one of their points is EIL this step the term is
//! left out for the step (documented simplification: those points are by
//! construction within 10% of a segment from a real point).

use super::assignment::Assignment;
use super::dofs::DofLayout;
use super::inertia::Inertia;
use super::params::SimParams;
use crate::rod::{
    bending::Bending,
    eil::{EilToEil, EilToPoint},
    friction::FrictionSpring,
    gravity::SegmentGravity,
    mass::segment_mass,
    parallel::{parallel_enabled, CrossingSide, ParallelContact},
    shear::Shear,
    stretch::Stretch,
    wrapping::Wrapping,
};
use crate::scene::ObstaclePenalty;
use crate::solver::assembly::{AnyStencilSet, StencilSet};
use crate::topology::{ContactKind, Fabric, PointRef};
use nalgebra::SVector;

/// Rest-state data fixed for a whole run.
#[derive(Clone, Debug)]
pub struct RestData {
    /// Mean rest segment length per yarn.
    pub rest_seg: Vec<f64>,
    /// Rest wrap angle per (contact, role): role 0 = front yarn wraps back yarn.
    pub wrap_rest: Vec<[f64; 2]>,
    /// Rest crossing angle per contact (float and layer crossings).
    pub shear_rest: Vec<f64>,
}

/// Inputs of a step that are not positions.
#[derive(Clone, Debug)]
pub struct StepInputs<'a> {
    /// Time step and predicted coordinates `q_n + h v_n`; `None` = statics.
    pub inertia: Option<(f64, &'a [f64])>,
    /// Friction anchors, one per global point.
    pub anchors: &'a [f64],
    /// Coulomb limit `mu |f_n|` per global point.
    pub friction_limits: &'a [f64],
}

fn push3(v: &mut Vec<u32>, i: usize) {
    v.extend([i as u32, i as u32 + 1, i as u32 + 2]);
}

fn arr<const N: usize>(v: Vec<u32>) -> [u32; N] {
    let mut a = [0u32; N];
    a.copy_from_slice(&v);
    a
}

fn gather<const N: usize>(q: &[f64], d: &[u32; N]) -> SVector<f64, N> {
    SVector::from_fn(|i, _| q[d[i] as usize])
}

/// Rank of each real point in its yarn's `real` list, by global point
/// number (`usize::MAX` for EIL points).
fn real_ranks(l: &DofLayout, real: &[Vec<usize>]) -> Vec<usize> {
    let mut rank = vec![usize::MAX; l.n_points()];
    for (y, r) in real.iter().enumerate() {
        for (k, &pi) in r.iter().enumerate() {
            rank[l.yarn_offsets[y] + pi] = k;
        }
    }
    rank
}

/// The structural pieces every term needs, computed once per step.
pub struct Discretization<'a> {
    pub f: &'a Fabric,
    pub l: &'a DofLayout,
    pub a: &'a Assignment,
    /// Real (non-EIL) points per yarn in `u` order.
    pub real: Vec<Vec<usize>>,
    /// Per global point, its place in `real` (`usize::MAX` if EIL): the
    /// neighbour lookups below are then O(1), where a scan of the yarn
    /// made the set-up quadratic (a flat fabric is one yarn).
    pub real_rank: Vec<usize>,
    /// The contact at each node, if any (`Contact::partner` names a node).
    contact_at_node: Vec<Option<usize>>,
}

impl<'a> Discretization<'a> {
    pub fn new(f: &'a Fabric, l: &'a DofLayout, a: &'a Assignment) -> Self {
        let real: Vec<Vec<usize>> = (0..f.yarns.len()).map(|y| a.real_points(l, y).collect()).collect();
        let real_rank = real_ranks(l, &real);
        let mut contact_at_node = vec![None; f.nodes.len()];
        for (ci, c) in f.contacts.iter().enumerate() {
            contact_at_node[c.node] = Some(ci);
        }
        Discretization {
            f,
            l,
            a,
            real,
            real_rank,
            contact_at_node,
        }
    }

    /// Whether a yarn point belongs to a contact (its node is a contact's).
    pub fn is_contact_point(&self, p: PointRef) -> bool {
        self.contact_at_node[self.node(p.yarn, p.point)].is_some()
    }

    fn node(&self, y: usize, p: usize) -> usize {
        self.f.yarns[y].points[p].node
    }

    /// `[x, u]` dofs of a yarn point.
    fn xu(&self, y: usize, p: usize, d: &mut Vec<u32>) {
        push3(d, self.l.x(self.node(y, p)));
        d.push(self.l.u(PointRef { yarn: y, point: p }) as u32);
    }

    /// The 9 interpolation dofs `[x_a, u_a, x_c, u_c, u]` of an EIL point.
    fn eil_dofs(&self, p: PointRef, d: &mut Vec<u32>) -> Option<()> {
        let (pa, pc) = self.a.interpolation_neighbours(self.l, p)?;
        self.xu(p.yarn, pa, d);
        self.xu(p.yarn, pc, d);
        d.push(self.l.u(p) as u32);
        Some(())
    }

    /// Place of a real point among its yarn's real points (None if EIL).
    fn real_index(&self, p: PointRef) -> Option<usize> {
        Some(self.real_rank[self.l.point(p)]).filter(|&k| k != usize::MAX)
    }

    /// Neighbouring real points of a real point along its yarn (sorted
    /// order), or None at a yarn end or for an EIL point.
    fn real_neighbours(&self, p: PointRef) -> Option<(usize, usize)> {
        let (real, k) = (&self.real[p.yarn], self.real_index(p)?);
        Some((*real.get(k.checked_sub(1)?)?, *real.get(k + 1)?))
    }

    /// Tangent-chord dofs `[x_prev, x_next]` of a real point, or None at a yarn end.
    fn chord(&self, p: PointRef, d: &mut Vec<u32>) -> Option<()> {
        let (a, b) = self.real_neighbours(p)?;
        push3(d, self.l.x(self.node(p.yarn, a)));
        push3(d, self.l.x(self.node(p.yarn, b)));
        Some(())
    }

    pub(super) fn is_eil(&self, p: PointRef) -> bool {
        self.a.is_eil(self.l, p)
    }

    /// Wrapping dofs `[a_prev, p, q, a_next, b_prev, b_next]` for yarn `wa`
    /// wrapping around `wb` between contacts `c` and its partner.
    fn wrap_dofs(&self, c: usize, wa_front: bool) -> Option<[u32; 18]> {
        let ct = &self.f.contacts[c];
        let cp = &self.f.contacts[self.contact_at_node[ct.partner?]?];
        let (pa, pb, qa) = if wa_front {
            (ct.front, ct.back, cp.front)
        } else {
            (ct.back, ct.front, cp.back)
        };
        if qa.yarn != pa.yarn || [pa, pb, qa].iter().any(|&p| self.is_eil(p)) {
            return None;
        }
        let real = &self.real[pa.yarn];
        let (kp, kq) = (self.real_index(pa)?, self.real_index(qa)?);
        let (first, last) = if kp <= kq { (kp, kq) } else { (kq, kp) };
        let (p_node, q_node) = if kp <= kq {
            (ct.node, cp.node)
        } else {
            (cp.node, ct.node)
        };
        let prev = real.get(first.checked_sub(1)?)?;
        let next = real.get(last + 1)?;
        let mut d = Vec::with_capacity(18);
        push3(&mut d, self.l.x(self.node(pa.yarn, *prev)));
        push3(&mut d, self.l.x(p_node));
        push3(&mut d, self.l.x(q_node));
        push3(&mut d, self.l.x(self.node(pa.yarn, *next)));
        self.chord(pb, &mut d)?;
        Some(arr(d))
    }

    fn shear_dofs(&self, c: usize) -> Option<[u32; 12]> {
        let ct = &self.f.contacts[c];
        if self.is_eil(ct.front) || self.is_eil(ct.back) {
            return None;
        }
        let mut d = Vec::with_capacity(12);
        self.chord(ct.front, &mut d)?;
        self.chord(ct.back, &mut d)?;
        Some(arr(d))
    }
}

/// Rest data from the compiled fabric (all points real).
pub fn rest_data(f: &Fabric, l: &DofLayout, a: &Assignment, q: &[f64]) -> RestData {
    let disc = Discretization::new(f, l, a);
    let wrap_rest = (0..f.contacts.len())
        .map(|c| {
            let w = |front| {
                disc.wrap_dofs(c, front)
                    .map_or(0.0, |d| crate::rod::wrapping::wrap_angle(&gather(q, &d)))
            };
            [w(true), w(false)]
        })
        .collect();
    let shear_rest = (0..f.contacts.len())
        .map(|c| {
            disc.shear_dofs(c)
                .map_or(0.0, |d| Shear::at_rest(1.0, 0.0, 0.0, &gather(q, &d)).rest_angle)
        })
        .collect();
    RestData {
        rest_seg: super::assignment::rest_segment_lengths(f),
        wrap_rest,
        shear_rest,
    }
}

/// All stencil sets of a step. Terms that are off, or have no instance in
/// this fabric, produce no set.
pub fn build_sets(
    disc: &Discretization,
    q: &[f64],
    p: &SimParams,
    rest: &RestData,
    step: &StepInputs,
) -> Vec<Box<dyn AnyStencilSet>> {
    let (f, l) = (disc.f, disc.l);
    let rp = &p.rod;
    let radii = p.yarn_radii(f);
    let mut sets: Vec<Box<dyn AnyStencilSet>> = Vec::new();
    let mut add = |s: Box<dyn AnyStencilSet>| {
        if !s.is_empty() {
            sets.push(s);
        }
    };

    // Rod terms along each yarn's real points.
    let (mut st, mut sd, mut bt, mut bd, mut it, mut id, mut gt, mut gd) =
        (vec![], vec![], vec![], vec![], vec![], vec![], vec![], vec![]);
    for (y, real) in disc.real.iter().enumerate() {
        for w in real.windows(2) {
            let mut d = Vec::with_capacity(8);
            disc.xu(y, w[0], &mut d);
            disc.xu(y, w[1], &mut d);
            let d: [u32; 8] = arr(d);
            st.push(Stretch::new(rp.ks));
            sd.push(d);
            if let Some((h, pred)) = step.inertia {
                let m = segment_mass(rp.rho, &gather(q, &d)) / (h * h);
                it.push(Inertia {
                    m_over_h2: m,
                    pred: gather(pred, &d),
                });
                id.push(d);
            }
            if p.terms.gravity {
                gt.push(SegmentGravity::new(rp.rho, rp.gravity));
                gd.push(d);
            }
        }
        if p.terms.bending {
            for w in real.windows(3) {
                let mut d = Vec::with_capacity(12);
                for &pi in w {
                    disc.xu(y, pi, &mut d);
                }
                bt.push(Bending::new(rp.kb).with_hessian(p.bending_hessian));
                bd.push(arr::<12>(d));
            }
        }
    }
    add(Box::new(StencilSet::new("stretch", st, sd)));
    add(Box::new(StencilSet::new("bending", bt, bd)));
    add(Box::new(StencilSet::new("inertia", it, id)));
    add(Box::new(StencilSet::new("gravity", gt, gd)));

    // Contacts: EIL constraints, friction, wrapping, shear.
    let (mut e1t, mut e1d, mut e2t, mut e2d) = (vec![], vec![], vec![], vec![]);
    let (mut ft, mut fd, mut wt, mut wd, mut sht, mut shd) = (vec![], vec![], vec![], vec![], vec![], vec![]);
    for (ci, c) in f.contacts.iter().enumerate() {
        let (ea, eb) = (disc.is_eil(c.front), disc.is_eil(c.back));
        let kc = |pr: PointRef| rp.contact_stiffness(rest.rest_seg[pr.yarn]);
        match (ea, eb) {
            (false, false) => {}
            (true, true) => {
                let mut d = Vec::with_capacity(18);
                if disc.eil_dofs(c.front, &mut d).is_some() && disc.eil_dofs(c.back, &mut d).is_some() {
                    e2t.push(EilToEil::new(kc(c.front).min(kc(c.back))));
                    e2d.push(arr::<18>(d));
                }
            }
            (true, false) | (false, true) => {
                let (e, other) = if ea { (c.front, c.back) } else { (c.back, c.front) };
                let _ = other;
                let mut d = Vec::with_capacity(12);
                if disc.eil_dofs(e, &mut d).is_some() {
                    push3(&mut d, l.x(c.node));
                    e1t.push(EilToPoint::new(kc(e)));
                    e1d.push(arr::<12>(d));
                }
            }
        }
        if p.terms.friction {
            for pr in [c.front, c.back] {
                if !f.yarns[pr.yarn].points[pr.point].fixed_u {
                    ft.push(FrictionSpring::new(
                        rp.kf,
                        step.anchors[l.point(pr)],
                        step.friction_limits[l.point(pr)],
                    ));
                    fd.push([l.u(pr) as u32]);
                }
            }
        }
        if p.terms.wrapping && c.kind == ContactKind::Stitch {
            for (role, front) in [(0, true), (1, false)] {
                if let Some(d) = disc.wrap_dofs(ci, front) {
                    wt.push(Wrapping::new(rp.kw, rest.wrap_rest[ci][role]));
                    wd.push(d);
                }
            }
        }
        if p.terms.shear && matches!(c.kind, ContactKind::Float | ContactKind::Layer) {
            if let Some(d) = disc.shear_dofs(ci) {
                sht.push(Shear::new(
                    rp.ksh,
                    rest.shear_rest[ci],
                    rp.shear_jam_angle,
                    rp.shear_jam_gain,
                ));
                shd.push(d);
            }
        }
    }
    add(Box::new(StencilSet::new("eil-contact", e1t, e1d)));
    add(Box::new(StencilSet::new("eil-eil-contact", e2t, e2d)));
    add(Box::new(StencilSet::new("friction", ft, fd)));
    add(Box::new(StencilSet::new("wrapping", wt, wd)));
    add(Box::new(StencilSet::new("shear", sht, shd)));

    if p.terms.parallel {
        let (pt, pd) = parallel_terms(disc, q, p, &radii);
        add(Box::new(StencilSet::new("parallel", pt, pd)));
    }
    if p.terms.secured_ends {
        let (et, ed) = super::end_stops::end_stops(disc, p, &radii);
        add(Box::new(StencilSet::new("yarn-ends", et, ed)));
    }

    if !p.obstacles.is_empty() {
        let (ot, od) = obstacle_terms(disc, p, &radii);
        add(Box::new(StencilSet::new("obstacles", ot, od)));
    }
    sets
}

/// Every unpinned node against every obstacle, kept off it by the radius of
/// its thickest yarn.
fn obstacle_terms(disc: &Discretization, p: &SimParams, radii: &[f64]) -> (Vec<ObstaclePenalty>, Vec<[u32; 3]>) {
    let (f, l) = (disc.f, disc.l);
    let mut node_radius = vec![0.0f64; f.nodes.len()];
    for (y, yarn) in f.yarns.iter().enumerate() {
        for pt in &yarn.points {
            node_radius[pt.node] = node_radius[pt.node].max(radii[y]);
        }
    }
    let (mut t, mut d) = (vec![], vec![]);
    for (n, node) in f.nodes.iter().enumerate() {
        if node.pinned {
            continue;
        }
        let thickness = if node_radius[n] > 0.0 {
            node_radius[n]
        } else {
            p.rod.radius
        };
        for s in &p.obstacles {
            t.push(ObstaclePenalty {
                shape: s.clone(),
                thickness,
                stiffness: p.obstacle_stiffness,
            });
            let x = l.x(n) as u32;
            d.push([x, x + 1, x + 2]);
        }
    }
    (t, d)
}

/// Parallel-yarn contact between consecutive contact points on a yarn,
/// with the enable rules of docs/MODEL.md, "Parallel-yarn contact". The two crossing yarns keep
/// their centre lines the sum of their radii apart along this one.
fn parallel_terms(
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
            c.kind == ContactKind::Layer,
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

#[cfg(test)]
#[path = "radii_tests.rs"]
mod radii_tests;
