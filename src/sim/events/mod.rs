//! The events layer: changes of the fabric itself between steps.
//!
//! - [`removal`]: a contact whose `u` left a yarn (checked at a step's start);
//! - [`separation`]: a contact whose normal force pulls its yarns together
//!   (checked at a step's end).
//!
//! Each is a function of the state (and the parameters) that returns an
//! edit, a [`ContactRemoval`], or nothing; the stepper applies it with
//! [`ContactRemoval::apply`] and keeps the records. The functions never see
//! the stepper, so the state they read and the edit they return are all
//! there is to them.
//!
//! An assignment change within the same fabric is no event: its state
//! transfer is `sim::discretization::transfer`.

pub mod removal;
pub mod separation;

use super::discretization::assignment::{assign, rest_segment_lengths};
use super::discretization::dofs::DofLayout;
use super::params::AssignParams;
use super::state::EolState;
use crate::topology::{Contact, Fabric, PointRef};

/// A contact removed during a run (twice if both of its points slid off).
#[derive(Clone, Debug, PartialEq)]
pub struct RemovedContact {
    pub contact: Contact,
    pub cause: RemovalCause,
    /// Simulated time of the removal (s).
    pub time: f64,
}

/// Why a contact went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RemovalCause {
    /// This point's `u` left its yarn (its address before the removal).
    SlidOff(PointRef),
    /// The normal force pulled the yarns together (`sim::events::separation`); N.
    Pulling { normal_force: f64 },
}

impl RemovalCause {
    pub fn is_slid_off(&self) -> bool {
        matches!(self, RemovalCause::SlidOff(_))
    }
}

/// An edit of the fabric that removes contacts: the new fabric (the state
/// written in), which contacts stay, where each kept point went, and which
/// nodes were copied.
#[derive(Clone, Debug)]
pub struct ContactRemoval {
    /// The fabric after the edit, with the old contacts still listed.
    fabric: Fabric,
    /// Per old contact, whether it stays.
    keep_contact: Vec<bool>,
    /// Old point -> new point, per yarn (`None` for deleted points).
    new_index: Vec<Vec<Option<usize>>>,
    /// `(node, copy)`: nodes appended to the fabric as copies, whose
    /// velocity the copy takes.
    node_copies: Vec<(usize, usize)>,
    /// What went, and why.
    pub removed: Vec<RemovedContact>,
}

impl ContactRemoval {
    /// Drops the removed contacts (and their per-contact data), renumbers
    /// the kept contacts' points, installs the new fabric in `state` and
    /// carries the per-point state over; returns the records of what went.
    pub fn apply(self, state: &mut EolState, assign_params: AssignParams) -> Vec<RemovedContact> {
        let ContactRemoval {
            mut fabric,
            keep_contact,
            new_index,
            node_copies,
            removed,
        } = self;
        let f = &mut fabric;
        let removed_nodes: Vec<usize> = (0..f.contacts.len())
            .filter(|&k| !keep_contact[k])
            .map(|k| f.contacts[k].node)
            .collect();
        retain_mask(&mut f.contacts, &keep_contact);
        for c in &mut f.contacts {
            for p in [&mut c.front, &mut c.back] {
                p.point = new_index[p.yarn][p.point].expect("a kept contact's points are kept");
            }
            // A stitch contact's other node lost its contact: no wrapping pair.
            if c.partner.is_some_and(|n| removed_nodes.contains(&n)) {
                c.partner = None;
            }
        }
        retain_mask(&mut state.rest.wrap_rest, &keep_contact);
        retain_mask(&mut state.rest.shear_rest, &keep_contact);
        if state.contact_normals.len() == keep_contact.len() {
            retain_mask(&mut state.contact_normals, &keep_contact);
        }
        install(state, fabric, &new_index, assign_params);
        for (node, copy) in node_copies {
            for d in 0..3 {
                state.v[3 * copy + d] = state.v[3 * node + d];
            }
        }
        removed
    }
}

/// Installs a fabric whose nodes are the old ones (plus, after a
/// separation, copies appended at the end, whose velocities the caller
/// sets) and whose points are the old ones minus some (`new_index`),
/// carrying the per-point state.
///
/// The system changes size, so the linear solver's symbolic analysis is
/// redone once; removals are rare events.
fn install(state: &mut EolState, f: Fabric, new_index: &[Vec<Option<usize>>], assign_params: AssignParams) {
    let old = state.layout.clone();
    let old = &old;
    let layout = DofLayout::new(&f);
    let q = layout.gather(&f);
    let mut v = vec![0.0; layout.len()];
    v[..3 * old.n_nodes].copy_from_slice(&state.v[..3 * old.n_nodes]);
    let mut anchors = vec![0.0; layout.n_points()];
    for (yi, map) in new_index.iter().enumerate() {
        for (pi, np) in map.iter().enumerate() {
            let Some(np) = *np else { continue };
            let (o, n) = (PointRef { yarn: yi, point: pi }, PointRef { yarn: yi, point: np });
            v[layout.u(n)] = state.v[old.u(o)];
            anchors[layout.point(n)] = state.anchors[old.point(o)];
        }
    }
    // Points that just became fixed-u hold no friction spring (the
    // anchors of fixed coordinates are never read), so no reset is needed.
    state.rest.rest_seg = rest_segment_lengths(&f);
    state.assignment = assign(&f, &layout, &q, &state.rest.rest_seg, assign_params);
    state.friction_limits = vec![0.0; layout.n_points()];
    state.fabric = f;
    state.layout = layout;
    state.q = q;
    state.v = v;
    state.anchors = anchors;
}

/// Keeps the elements whose `keep` entry is true.
fn retain_mask<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut it = keep.iter();
    v.retain(|_| *it.next().expect("one mask entry per element"));
}
