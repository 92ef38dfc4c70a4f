//! The discretization layer: which coordinate of `q` is what, and which
//! yarn points are real this step.
//!
//! - [`dofs`]: the fixed layout of `q` (node positions, then one `u` per
//!   yarn point).
//! - [`assignment`]: the per-step EIL assignment (docs/MODEL.md, "Node
//!   assignment").
//! - [`Discretization`] (this file): the real points of each yarn under one
//!   assignment and the dof lists of every stencil shape built on them, and
//!   [`interpolated`], where a point is under an assignment.
//! - [`rest_data`]: rest data fixed for a run (rest segments, wrap and shear angles).
//! - [`transfer`]: moving the state when the assignment changes, so every
//!   soft EIL constraint starts the step at rest.
//!
//! Everything here is geometry and bookkeeping: no energy, no solver. Every
//! layer above (terms, the Newton problem, events, the stepper) reads it,
//! and it reads only `sim::params` below it.

pub mod assignment;
pub mod dofs;
pub mod rest_data;
pub mod transfer;

use crate::topology::{Contact, Fabric, PointRef};
use assignment::Assignment;
use dofs::DofLayout;
use nalgebra::SVector;

/// Appends the three `x` dofs that start at `i`.
pub(crate) fn push3(v: &mut Vec<u32>, i: usize) {
    v.extend([i as u32, i as u32 + 1, i as u32 + 2]);
}

/// A dof list of known length as an array.
pub(crate) fn arr<const N: usize>(v: Vec<u32>) -> [u32; N] {
    let mut a = [0u32; N];
    a.copy_from_slice(&v);
    a
}

/// The coordinates of `q` at the dofs `d`.
pub(crate) fn gather<const N: usize>(q: &[f64], d: &[u32; N]) -> SVector<f64, N> {
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

    /// The contact at point `p`'s node, if any.
    pub fn contact_at(&self, p: PointRef) -> Option<&Contact> {
        self.contact_at_node[self.node(p.yarn, p.point)].map(|c| &self.f.contacts[c])
    }

    /// Node of point `p` of yarn `y`.
    pub(crate) fn node(&self, y: usize, p: usize) -> usize {
        self.f.yarns[y].points[p].node
    }

    /// `[x, u]` dofs of a yarn point.
    pub(crate) fn xu(&self, y: usize, p: usize, d: &mut Vec<u32>) {
        push3(d, self.l.x(self.node(y, p)));
        d.push(self.l.u(PointRef { yarn: y, point: p }) as u32);
    }

    /// The 9 interpolation dofs `[x_a, u_a, x_c, u_c, u]` of an EIL point.
    pub(crate) fn eil_dofs(&self, p: PointRef, d: &mut Vec<u32>) -> Option<()> {
        let (pa, pc) = self.a.interpolation_neighbours(self.l, p)?;
        self.xu(p.yarn, pa, d);
        self.xu(p.yarn, pc, d);
        d.push(self.l.u(p) as u32);
        Some(())
    }

    /// Place of a real point among its yarn's real points (None if EIL).
    pub(crate) fn real_index(&self, p: PointRef) -> Option<usize> {
        Some(self.real_rank[self.l.point(p)]).filter(|&k| k != usize::MAX)
    }

    /// Neighbouring real points of a real point along its yarn (sorted
    /// order), or None at a yarn end or for an EIL point.
    pub(crate) fn real_neighbours(&self, p: PointRef) -> Option<(usize, usize)> {
        let (real, k) = (&self.real[p.yarn], self.real_index(p)?);
        Some((*real.get(k.checked_sub(1)?)?, *real.get(k + 1)?))
    }

    /// Tangent-chord dofs `[x_prev, x_next]` of a real point, or None at a yarn end.
    pub(crate) fn chord(&self, p: PointRef, d: &mut Vec<u32>) -> Option<()> {
        let (a, b) = self.real_neighbours(p)?;
        push3(d, self.l.x(self.node(p.yarn, a)));
        push3(d, self.l.x(self.node(p.yarn, b)));
        Some(())
    }

    /// Whether `p` is EIL in this discretization.
    pub fn is_eil(&self, p: PointRef) -> bool {
        self.a.is_eil(self.l, p)
    }

    /// Wrapping dofs `[a_prev, p, q, a_next, b_prev, b_next]` for yarn `wa`
    /// wrapping around `wb` between contacts `c` and its partner.
    pub(crate) fn wrap_dofs(&self, c: usize, wa_front: bool) -> Option<[u32; 18]> {
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

    /// Shear dofs `[a_prev, a_next, b_prev, b_next]` of a contact whose
    /// two points are real.
    pub(crate) fn shear_dofs(&self, c: usize) -> Option<[u32; 12]> {
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

/// Position of a point under an assignment: its node, or the interpolation
/// between its real neighbours (docs/MODEL.md, "Kinematics") when it is EIL.
pub fn interpolated(f: &Fabric, l: &DofLayout, a: &Assignment, q: &[f64], p: PointRef) -> nalgebra::Vector3<f64> {
    let pt = &f.yarns[p.yarn].points[p.point];
    if !a.is_eil(l, p) {
        return l.node_x(q, pt.node);
    }
    let Some((pa, pc)) = a.interpolation_neighbours(l, p) else {
        return l.node_x(q, pt.node);
    };
    let y = &f.yarns[p.yarn];
    let (ua, uc, u) = (
        q[l.u(PointRef {
            yarn: p.yarn,
            point: pa,
        })],
        q[l.u(PointRef {
            yarn: p.yarn,
            point: pc,
        })],
        q[l.u(p)],
    );
    // Not clamped to [0, 1]: within a step an EIL point may slide past a
    // neighbour (the order is revised at the next step), and the constraint
    // stencil (`rod::eil`) extrapolates along the chord; so does this.
    let s = if uc > ua { (u - ua) / (uc - ua) } else { 0.5 };
    l.node_x(q, y.points[pa].node) * (1.0 - s) + l.node_x(q, y.points[pc].node) * s
}
