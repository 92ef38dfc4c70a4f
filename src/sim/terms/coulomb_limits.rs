//! Coulomb limits of the friction springs: the normal force at each contact
//! point, and the anchor update after a step.
//!
//! The normal force of a point is the contact force the other yarn exerts
//! on it, less its component along this yarn's tangent (that component is
//! what friction resists; counting it as normal load would make a contact
//! stick harder the harder it is pulled).
//!
//! - A real (non-EIL) point shares its node with the partner. At
//!   equilibrium the partner balances this yarn's own forces on the node:
//!   the `x` gradients of its stretch, bending and (when on) gravity
//!   stencils there. Bending matters where a yarn overhangs its support:
//!   the weight of an unsupported tail reaches the last contact through
//!   the bending moment, not through tension.
//! - An EIL point has no node: the contact force is the EIL constraint
//!   spring's, `kc (x_eil - x_partner)`.
//!
//! The limits are computed from the state at the start of a step and held
//! for the step (lagged, as IPC lags friction's normal force), which keeps
//! the friction potential fixed inside one Newton solve.

use crate::energy::Stencil;
use crate::rod::{bending::Bending, friction::coulomb_update, gravity::SegmentGravity, stretch::Stretch};
use crate::sim::discretization::assignment::Assignment;
use crate::sim::discretization::dofs::DofLayout;
use crate::sim::discretization::{interpolated, Discretization};
use crate::sim::params::SimParams;
use crate::topology::{Fabric, PointRef, Vec3};
use nalgebra::SVector;

/// `mu |f_n|` per global point (zero for points that are not in a contact).
pub fn coulomb_limits(
    f: &Fabric,
    l: &DofLayout,
    a: &Assignment,
    q: &[f64],
    p: &SimParams,
    rest_seg: &[f64],
) -> Vec<f64> {
    let mut limits = vec![0.0; l.n_points()];
    if !p.terms.friction {
        return limits;
    }
    let disc = Discretization::new(f, l, a);
    let (real, rank) = (&disc.real, &disc.real_rank);
    let limit = |me: PointRef, other: PointRef| {
        let fn_ = if a.is_eil(l, me) {
            let kc = p.rod.contact_stiffness(rest_seg[me.yarn]);
            eil_normal_force(f, l, a, q, kc, me, other)
        } else {
            real_contact_force(f, l, q, p, &real[me.yarn], rank[l.point(me)], me).map(|(f, t)| across(f, t))
        };
        (l.point(me), p.rod.mu.abs() * fn_.unwrap_or(0.0))
    };
    // Each contact on its own (12 ms per relaxation step of a 40x40 linen
    // stitch on one thread), written in contact order as before.
    crate::parallel::ordered_map(
        crate::parallel::threads(),
        256,
        f.contacts.len(),
        |k| {
            let c = &f.contacts[k];
            [limit(c.front, c.back), limit(c.back, c.front)]
        },
        |_, pairs| {
            for &(point, value) in pairs.iter().flatten() {
                limits[point] = value;
            }
        },
    );
    limits
}

/// Component of `force` across the unit tangent `t`.
fn across(force: Vec3, t: Option<Vec3>) -> f64 {
    match t {
        Some(t) => (force - t * force.dot(&t)).norm(),
        None => force.norm(),
    }
}

/// The force the partner exerts on the real point `me` (rank `k` in its
/// yarn's `real` list) through their shared node, and this yarn's unit
/// tangent there. At equilibrium the partner balances this yarn's own
/// forces on the node, so the contact force is the `x` gradient of this
/// yarn's stretch, bending and (when on) gravity stencils at the node.
pub(crate) fn real_contact_force(
    f: &Fabric,
    l: &DofLayout,
    q: &[f64],
    p: &SimParams,
    real: &[usize],
    k: usize,
    me: PointRef,
) -> Option<(Vec3, Option<Vec3>)> {
    if real.get(k) != Some(&me.point) {
        return None;
    }
    let yarn = &f.yarns[me.yarn];
    let rp = &p.yarn_rod(yarn.layer);
    // Local `[x, u]` of the real point at rank `r`.
    let xu = |r: usize| -> SVector<f64, 4> {
        let pi = real[r];
        let x = l.node_x(q, yarn.points[pi].node);
        SVector::<f64, 4>::new(
            x.x,
            x.y,
            x.z,
            q[l.u(PointRef {
                yarn: me.yarn,
                point: pi,
            })],
        )
    };
    let mut grad = Vec3::zeros();
    // Segments (r, r + 1) touching rank k: stretch and gravity.
    for r in [k.checked_sub(1), Some(k)].into_iter().flatten() {
        if r + 1 >= real.len() {
            continue;
        }
        let mut v = SVector::<f64, 8>::zeros();
        v.fixed_rows_mut::<4>(0).copy_from(&xu(r));
        v.fixed_rows_mut::<4>(4).copy_from(&xu(r + 1));
        let at = if r == k { 0 } else { 4 };
        let mut g = Stretch::new(rp.ks).gradient(&v);
        if p.terms.gravity {
            g += SegmentGravity::new(rp.rho, rp.gravity).gradient(&v);
        }
        grad += g.fixed_rows::<3>(at);
    }
    // Triples (r, r + 1, r + 2) touching rank k: bending.
    if p.terms.bending {
        for r in [k.checked_sub(2), k.checked_sub(1), Some(k)].into_iter().flatten() {
            if r + 2 >= real.len() {
                continue;
            }
            let mut v = SVector::<f64, 12>::zeros();
            for j in 0..3 {
                v.fixed_rows_mut::<4>(4 * j).copy_from(&xu(r + j));
            }
            let g = Bending::new(rp.kb).gradient(&v);
            grad += g.fixed_rows::<3>(4 * (k - r));
        }
    }
    let at = |r: Option<usize>| r.and_then(|r| real.get(r)).map(|&pi| l.node_x(q, yarn.points[pi].node));
    let x0 = l.node_x(q, yarn.points[me.point].node);
    let (prev, next) = (at(k.checked_sub(1)).unwrap_or(x0), at(Some(k + 1)).unwrap_or(x0));
    Some((grad, (next - prev).try_normalize(1e-300)))
}

fn eil_normal_force(
    f: &Fabric,
    l: &DofLayout,
    a: &Assignment,
    q: &[f64],
    kc: f64,
    me: PointRef,
    other: PointRef,
) -> Option<f64> {
    let (pa, pc) = a.interpolation_neighbours(l, me)?;
    let yarn = &f.yarns[me.yarn];
    let t = (l.node_x(q, yarn.points[pc].node) - l.node_x(q, yarn.points[pa].node)).try_normalize(1e-300);
    let gap = interpolated(f, l, a, q, me) - interpolated(f, l, a, q, other);
    Some(across(gap * kc, t))
}

/// Moves every anchor to where the capped spring's return mapping left it.
pub fn update_anchors(anchors: &mut [f64], limits: &[f64], q: &[f64], l: &DofLayout, kf: f64) {
    for (i, anchor) in anchors.iter_mut().enumerate() {
        let u = q[3 * l.n_nodes + i];
        *anchor = coulomb_update(*anchor, u, kf, limits[i]);
    }
}
