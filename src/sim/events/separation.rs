//! Removing a persistent contact whose normal force pulls its yarns
//! together instead of pushing them apart (docs/MODEL.md, "Contact removal":
//! the sign test, as for a buckling tag that lifts off a shirt).
//!
//! Why it needs state of its own: both yarns of a contact share one node,
//! so the node's position says nothing about which side each yarn is on.
//! The side is carried instead, as a unit normal per contact pointing from
//! the back yarn to the front yarn (`EolState::contact_normals`). It
//! starts from the compiled convention (the front yarn lies on the +z, RS
//! side of the fabric) and is then turned with the two yarn tangents, step
//! by step: each step takes `t_front x t_back`, normalised, with the sign
//! that keeps it within 90 degrees of the last one. When the tangents are
//! parallel the last normal is kept.
//!
//! The test runs at the end of each step, on the state the step ended in
//! (not at the start of the next: a scene that moves pins between steps
//! would test a state that is not an equilibrium; a lowered end lifts the
//! middle of its yarn until the step has relaxed it). For each contact:
//! the force the back yarn exerts on the front one through the node is the
//! gradient of the front yarn's own stretch, bending and gravity there
//! (`sim::terms::coulomb_limits`, the same force that sets the Coulomb limit), and the
//! other way round. The normal force is
//!
//! ```text
//! N = 1/2 (F_on_front - F_on_back) . n
//! ```
//!
//! positive when the contact pushes the yarns apart. A contact of a
//! separable kind with `N < -min_pull` is removed: the front point keeps the
//! node, the back point gets a copy of it (same position and velocity),
//! and both points become fixed-`u` Lagrangian points, as after a removal
//! by sliding (`sim::events::removal`). A contact with an EIL point is not tested:
//! its two yarn points do not share a node during the transition.
//!
//! Which contacts may separate ([`SeparationParams::kinds`], default
//! `Layer` only): a stitch or tuck contact is a loop through a loop, which
//! cannot come apart by pulling, and removing it would unravel the fabric.
//! A float lies on a leg and could lift off it, but once its contact is
//! gone nothing but the thickness barrier (`"contact"` in a scene) keeps the
//! float from passing through the leg, so floats are opt-in.

use super::{ContactRemoval, RemovalCause, RemovedContact};
use crate::sim::discretization::Discretization;
use crate::sim::params::SimParams;
use crate::sim::state::EolState;
use crate::sim::terms::coulomb_limits::real_contact_force;
use crate::topology::{PointRef, Vec3};

/// The contact normals of `state` turned with the current yarn tangents
/// (see the module docs); a contact without a normal yet starts from +z.
pub fn turned_normals(state: &EolState, disc: &Discretization) -> Vec<Vec3> {
    let mut normals = state.contact_normals.clone();
    normals.resize(state.fabric.contacts.len(), Vec3::zeros());
    for (c, n_old) in state.fabric.contacts.iter().zip(normals.iter_mut()) {
        let tangent = |p| tangent(state, disc, p);
        let (Some(tf), Some(tb)) = (tangent(c.front), tangent(c.back)) else {
            continue;
        };
        let Some(n) = tf.cross(&tb).try_normalize(1e-12) else {
            continue;
        };
        let reference = if *n_old == Vec3::zeros() { Vec3::z() } else { *n_old };
        *n_old = if n.dot(&reference) < 0.0 { -n } else { n };
    }
    normals
}

/// Unit tangent of a yarn point: along the chord between its real
/// neighbours (or, for an EIL point, its interpolation neighbours).
fn tangent(state: &EolState, disc: &Discretization, p: PointRef) -> Option<Vec3> {
    let (l, yarn) = (&state.layout, &state.fabric.yarns[p.yarn]);
    let (a, b) = if disc.is_eil(p) {
        state.assignment.interpolation_neighbours(l, p)?
    } else {
        let real = &disc.real[p.yarn];
        let k = disc.real_rank[l.point(p)];
        (real[k.saturating_sub(1)], real[(k + 1).min(real.len() - 1)])
    };
    let x = |pi: usize| l.node_x(&state.q, yarn.points[pi].node);
    (x(b) - x(a)).try_normalize(1e-300)
}

/// The normal force of each contact (N, positive pushing), `None` where
/// it is not tested: separation off, a kind that may not separate, an EIL
/// point, or no normal yet.
pub fn normal_forces(state: &EolState, params: &SimParams, disc: &Discretization) -> Vec<Option<f64>> {
    let Some(sp) = &params.separation else {
        return vec![None; state.fabric.contacts.len()];
    };
    let force_on = |p: PointRef| {
        let (real, k) = (&disc.real[p.yarn], disc.real_rank[state.layout.point(p)]);
        real_contact_force(&state.fabric, &state.layout, &state.q, params, real, k, p).map(|(f, _)| f)
    };
    state
        .fabric
        .contacts
        .iter()
        .enumerate()
        .map(|(ci, c)| {
            let n = *state.contact_normals.get(ci)?;
            if !sp.kinds.contains(&c.kind) || n == Vec3::zeros() || disc.is_eil(c.front) || disc.is_eil(c.back) {
                return None;
            }
            Some(0.5 * (force_on(c.front)? - force_on(c.back)?).dot(&n))
        })
        .collect()
}

/// The split of every contact whose normal force (from [`normal_forces`])
/// is below `-min_pull`, or `None` if there is none; `time` stamps the
/// records.
pub fn split_pulling(state: &EolState, forces: Vec<Option<f64>>, min_pull: f64, time: f64) -> Option<ContactRemoval> {
    let found: Vec<(usize, f64)> = forces
        .into_iter()
        .enumerate()
        .filter_map(|(ci, n)| n.filter(|&n| n < -min_pull).map(|n| (ci, n)))
        .collect();
    if found.is_empty() {
        return None;
    }
    let mut f = state.fabric.clone();
    state.layout.scatter(&state.q, &mut f);
    let mut node_copies = Vec::with_capacity(found.len());
    let mut removed = Vec::with_capacity(found.len());
    for &(ci, normal_force) in &found {
        let c = f.contacts[ci].clone();
        let copy = f.nodes.len();
        f.nodes.push(f.nodes[c.node].clone());
        node_copies.push((c.node, copy));
        f.yarns[c.back.yarn].points[c.back.point].node = copy;
        for p in [c.front, c.back] {
            f.yarns[p.yarn].points[p.point].fixed_u = true;
        }
        removed.push(RemovedContact {
            contact: c,
            cause: RemovalCause::Pulling { normal_force },
            time,
        });
    }
    let keep_contact: Vec<bool> = (0..f.contacts.len())
        .map(|k| !found.iter().any(|&(r, _)| r == k))
        .collect();
    let new_index: Vec<Vec<Option<usize>>> = f
        .yarns
        .iter()
        .map(|y| (0..y.points.len()).map(Some).collect())
        .collect();
    Some(ContactRemoval {
        fabric: f,
        keep_contact,
        new_index,
        node_copies,
        removed,
    })
}

#[cfg(test)]
#[path = "separation_tests.rs"]
mod tests;
