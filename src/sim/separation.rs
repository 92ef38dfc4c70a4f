//! Removing a persistent contact whose normal force pulls its yarns
//! together instead of pushing them apart (docs/MODEL.md, "Contact removal":
//! the sign test, as for a buckling tag that lifts off a shirt).
//!
//! Why it needs state of its own: both yarns of a contact share one node,
//! so the node's position says nothing about which side each yarn is on.
//! The side is carried instead, as a unit normal per contact pointing from
//! the back yarn to the front yarn ([`Simulation::contact_normals`]). It
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
//! (`sim::friction`, the same force that sets the Coulomb limit), and the
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
//! by sliding (`sim::removal`). A contact with an EIL point is not tested:
//! its two yarn points do not share a node during the transition.
//!
//! Which contacts may separate ([`SeparationParams::kinds`], default
//! `Layer` only): a stitch or tuck contact is a loop through a loop, which
//! cannot come apart by pulling, and removing it would unravel the fabric.
//! A float lies on a leg and could lift off it, but once its contact is
//! gone nothing but the thickness barrier (`"contact"` in a scene) keeps the
//! float from passing through the leg, so floats are opt-in.

use super::friction::real_contact_force;
use super::removal::{RemovalCause, RemovedContact};
use super::simulation::Simulation;
use super::system::Discretization;
use crate::topology::{ContactKind, PointRef, Vec3};
use serde::{Deserialize, Serialize};

/// The sign test's settings; `SimParams::separation` is `None` (off) by default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SeparationParams {
    /// Contact kinds that may separate (see the module docs).
    pub kinds: Vec<ContactKind>,
    /// A contact goes when its normal force is below `-min_pull` (N). The
    /// default 0 removes any contact that pulls at all.
    #[serde(deserialize_with = "crate::scene::non_negative")]
    pub min_pull: f64,
}

impl Default for SeparationParams {
    fn default() -> Self {
        SeparationParams {
            kinds: vec![ContactKind::Layer],
            min_pull: 0.0,
        }
    }
}

impl Simulation {
    /// Sets or turns every contact normal (see the module docs). Called when
    /// the simulation is made while separation is on.
    pub fn update_contact_normals(&mut self) {
        let disc = Discretization::new(&self.fabric, &self.layout, &self.assignment);
        self.contact_normals = self.turned_normals(&disc);
    }

    /// The end-of-step work while separation is on: turn the normals, then
    /// split the contacts that pull, on one discretization of the state.
    pub(super) fn separate_after_step(&mut self) -> usize {
        let disc = Discretization::new(&self.fabric, &self.layout, &self.assignment);
        self.contact_normals = self.turned_normals(&disc);
        let forces = self.normal_forces(&disc);
        self.split_pulling(forces)
    }

    /// [`Self::contact_normals`] turned with the current yarn tangents.
    fn turned_normals(&self, disc: &Discretization) -> Vec<Vec3> {
        let mut normals = self.contact_normals.clone();
        normals.resize(self.fabric.contacts.len(), Vec3::zeros());
        for (c, n_old) in self.fabric.contacts.iter().zip(normals.iter_mut()) {
            let tangent = |p| self.tangent(disc, p);
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
    fn tangent(&self, disc: &Discretization, p: PointRef) -> Option<Vec3> {
        let (l, yarn) = (&self.layout, &self.fabric.yarns[p.yarn]);
        let (a, b) = if disc.is_eil(p) {
            self.assignment.interpolation_neighbours(l, p)?
        } else {
            let real = &disc.real[p.yarn];
            let k = disc.real_rank[l.point(p)];
            (real[k.saturating_sub(1)], real[(k + 1).min(real.len() - 1)])
        };
        let x = |pi: usize| l.node_x(&self.q, yarn.points[pi].node);
        (x(b) - x(a)).try_normalize(1e-300)
    }

    /// The normal force of each contact (N, positive pushing), `None` where
    /// it is not tested: a kind that may not separate, an EIL point, or no
    /// normal yet.
    pub fn contact_normal_forces(&self) -> Vec<Option<f64>> {
        let disc = Discretization::new(&self.fabric, &self.layout, &self.assignment);
        self.normal_forces(&disc)
    }

    fn normal_forces(&self, disc: &Discretization) -> Vec<Option<f64>> {
        let Some(sp) = &self.params.separation else {
            return vec![None; self.fabric.contacts.len()];
        };
        let force_on = |p: PointRef| {
            let (real, k) = (&disc.real[p.yarn], disc.real_rank[self.layout.point(p)]);
            real_contact_force(&self.fabric, &self.layout, &self.q, &self.params, real, k, p).map(|(f, _)| f)
        };
        self.fabric
            .contacts
            .iter()
            .enumerate()
            .map(|(ci, c)| {
                let n = *self.contact_normals.get(ci)?;
                if !sp.kinds.contains(&c.kind) || n == Vec3::zeros() || disc.is_eil(c.front) || disc.is_eil(c.back) {
                    return None;
                }
                Some(0.5 * (force_on(c.front)? - force_on(c.back)?).dot(&n))
            })
            .collect()
    }

    /// Splits every tested contact whose normal force is below
    /// `-min_pull`; returns how many went.
    pub fn separate_pulling(&mut self) -> usize {
        let forces = self.contact_normal_forces();
        self.split_pulling(forces)
    }

    /// Splits the contacts whose normal force (from [`Self::normal_forces`])
    /// is below `-min_pull`.
    fn split_pulling(&mut self, forces: Vec<Option<f64>>) -> usize {
        let Some(min_pull) = self.params.separation.as_ref().map(|s| s.min_pull) else {
            return 0;
        };
        let found: Vec<(usize, f64)> = forces
            .into_iter()
            .enumerate()
            .filter_map(|(ci, n)| n.filter(|&n| n < -min_pull).map(|n| (ci, n)))
            .collect();
        if found.is_empty() {
            return 0;
        }
        let old_layout = self.layout.clone();
        let mut f = self.fabric.clone();
        old_layout.scatter(&self.q, &mut f);
        let mut copies = Vec::with_capacity(found.len());
        for &(ci, normal_force) in &found {
            let c = f.contacts[ci].clone();
            let copy = f.nodes.len();
            f.nodes.push(f.nodes[c.node].clone());
            copies.push((c.node, copy));
            f.yarns[c.back.yarn].points[c.back.point].node = copy;
            for p in [c.front, c.back] {
                f.yarns[p.yarn].points[p.point].fixed_u = true;
            }
            self.removed.push(RemovedContact {
                contact: c,
                cause: RemovalCause::Pulling { normal_force },
                time: self.time,
            });
        }
        let keep: Vec<bool> = (0..f.contacts.len())
            .map(|k| !found.iter().any(|&(r, _)| r == k))
            .collect();
        let identity: Vec<Vec<Option<usize>>> = f
            .yarns
            .iter()
            .map(|y| (0..y.points.len()).map(Some).collect())
            .collect();
        self.remove_contacts(f, &keep, &old_layout, &identity);
        for (node, copy) in copies {
            for d in 0..3 {
                self.v[3 * copy + d] = self.v[3 * node + d];
            }
        }
        found.len()
    }
}

#[cfg(test)]
#[path = "separation_tests.rs"]
mod tests;
