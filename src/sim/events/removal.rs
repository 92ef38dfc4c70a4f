//! Removing a persistent contact whose material coordinate has left its
//! yarn (docs/MODEL.md, "Contact removal").
//!
//! Why it is needed: a contact's `u` slides. When a yarn is pulled through a
//! crossing until its tail passes the other yarn, the contact's `u` on that
//! yarn goes below the yarn's start (or above its end). The EIL stencil
//! would keep extrapolating along the last segment, i.e. hold a point that
//! is no longer on the yarn, and the `u` order of the yarn would put a
//! contact outside its ends. With secured ends (`Terms::secured_ends`, the
//! default for relaxation) this cannot happen; it is for scenes with free
//! tails.
//!
//! What removal does, at the start of a step (the discretization is fixed
//! within a step):
//! - the yarn point that left its yarn is deleted from that yarn;
//! - the other yarn keeps the node as a plain Lagrangian point (`u` fixed
//!   where it is), since a free `u` with no contact would be a sliding mode
//!   with no stiffness;
//! - the contact and its rest data go; a partner contact loses its pairing
//!   (its wrapping term needs both);
//! - the state is carried over point by point: positions and velocities of
//!   the nodes, `u`, velocities and friction anchors of the remaining
//!   points. Node numbers do not change, so the shared node stays where it
//!   was, now owned by one yarn.
//!
//! The system changes size, so the linear solver's symbolic analysis is
//! redone once; this is a rare event (one per yarn end at most).
//!
//! The other removal, by the normal-force sign test, is `sim::events::separation`;
//! both are a [`ContactRemoval`].

use super::{ContactRemoval, RemovalCause, RemovedContact};
use crate::sim::discretization::interpolated;
use crate::sim::state::EolState;
use crate::topology::PointRef;

/// Whether a point's `u` is at or beyond its yarn's end points (NaN
/// counts as off).
fn is_off_yarn(state: &EolState, p: PointRef) -> bool {
    let l = &state.layout;
    let u = |point| state.q[l.u(PointRef { yarn: p.yarn, point })];
    let last = state.fabric.yarns[p.yarn].points.len() - 1;
    let up = u(p.point);
    !(up > u(0) && up < u(last))
}

/// Every contact point whose `u` left its yarn, with its contact.
pub fn slid_off_contacts(state: &EolState) -> Vec<(usize, PointRef)> {
    state
        .fabric
        .contacts
        .iter()
        .enumerate()
        .flat_map(|(k, c)| [(k, c.front), (k, c.back)])
        .filter(|&(_, p)| is_off_yarn(state, p))
        .collect()
}

/// The removal of every contact that slid off a yarn (one record per point
/// that left its yarn, two if both did), or `None` if none did; `time`
/// stamps the records.
pub fn remove_slid_off(state: &EolState, time: f64) -> Option<ContactRemoval> {
    let found = slid_off_contacts(state);
    if found.is_empty() {
        return None;
    }
    let old_layout = &state.layout;
    // The state written into the fabric, EIL points at their interpolated
    // positions (the staying point becomes real and must start there).
    let mut f = state.fabric.clone();
    old_layout.scatter(&state.q, &mut f);
    for &(k, gone) in &found {
        let c = &state.fabric.contacts[k];
        let stay = if gone == c.front { c.back } else { c.front };
        if found.contains(&(k, stay)) {
            // Both left their yarns: both go, and the node is unused.
            continue;
        }
        if state.assignment.is_eil(old_layout, stay) {
            f.nodes[c.node].x = interpolated(&state.fabric, old_layout, &state.assignment, &state.q, stay);
        }
        f.yarns[stay.yarn].points[stay.point].fixed_u = true;
    }
    let mut keep: Vec<Vec<bool>> = f.yarns.iter().map(|y| vec![true; y.points.len()]).collect();
    for &(_, gone) in &found {
        keep[gone.yarn][gone.point] = false;
    }
    let new_index: Vec<Vec<Option<usize>>> = keep
        .iter()
        .map(|k| {
            let mut next = 0;
            k.iter()
                .map(|&kept| {
                    kept.then(|| {
                        next += 1;
                        next - 1
                    })
                })
                .collect()
        })
        .collect();
    for (y, k) in f.yarns.iter_mut().zip(&keep) {
        let mut it = k.iter();
        y.points.retain(|_| *it.next().expect("one mask entry per point"));
    }
    let keep_contact: Vec<bool> = (0..f.contacts.len())
        .map(|k| !found.iter().any(|&(r, _)| r == k))
        .collect();
    let removed = found
        .iter()
        .map(|&(k, gone)| RemovedContact {
            contact: state.fabric.contacts[k].clone(),
            cause: RemovalCause::SlidOff(gone),
            time,
        })
        .collect();
    Some(ContactRemoval {
        fabric: f,
        keep_contact,
        new_index,
        node_copies: Vec::new(),
        removed,
    })
}

#[cfg(test)]
mod tests {
    use crate::sim::discretization::assignment::tests::crossing_fabric;
    use crate::sim::events::RemovalCause;
    use crate::sim::{SimParams, Simulation};
    use crate::solver::linear::LinearSolver;
    use crate::topology::{Fabric, PointRef};

    /// Yarn 0 along x from 0 to 0.1 m, crossing yarn 1 (along y at
    /// x = 4 mm) 4 mm from its start: a short free tail. Yarn 1 and the far
    /// end of yarn 0 are pinned; the far end is then pulled along +x, which
    /// draws the tail through the crossing.
    fn pulled_tail() -> Fabric {
        let mut nodes = vec![[0.004, 0.0, 0.0], [0.0, 0.0, 0.0]];
        let mut yarn0 = vec![(1, 0.0, true), (0, 0.004, false)];
        for i in 1..=10 {
            let x = 0.01 * i as f64;
            yarn0.push((nodes.len(), x, true));
            nodes.push([x, 0.0, 0.0]);
        }
        let mut yarn1 = Vec::new();
        for (k, y) in [-0.05, -0.025, 0.0, 0.025, 0.05].into_iter().enumerate() {
            if y == 0.0 {
                yarn1.push((0, 0.05, false));
            } else {
                yarn1.push((nodes.len(), 0.025 * k as f64, true));
                nodes.push([0.004, y, 0.0]);
            }
        }
        let mut f = crossing_fabric(&nodes, [&yarn0, &yarn1], 0.1, 1, 2);
        for n in [11, 12, 15] {
            f.nodes[n].pinned = true;
        }
        f
    }

    /// Pulls the far end of yarn 0 by 1 mm per step for `steps` steps.
    fn pull(remove: bool, steps: usize) -> Simulation {
        let mut p = SimParams::default();
        p.terms.friction = false;
        p.terms.secured_ends = false;
        p.remove_slid_off = remove;
        let mut sim = Simulation::new(pulled_tail(), p, LinearSolver::direct(), 1e-2);
        for _ in 0..steps {
            let x = sim.layout().x(11);
            sim.q_mut()[x] += 0.001;
            sim.step(false, None, &mut |_, _| {}).expect("step");
        }
        sim
    }

    #[test]
    fn a_tail_pulled_through_its_crossing_leaves_it() {
        // Pulled 3 mm: the tail (4 mm) still passes the crossing.
        let sim = pull(true, 3);
        assert_eq!(sim.fabric().contacts.len(), 1);
        assert!(sim.removed().is_empty());

        // Pulled 8 mm: the contact's u on yarn 0 went below the yarn start
        // and the contact is gone; yarn 1 keeps the node as a fixed-u point.
        let mut sim = pull(true, 8);
        assert_eq!(sim.removed().len(), 1, "{:?}", sim.removed());
        assert_eq!(
            sim.removed()[0].cause,
            RemovalCause::SlidOff(PointRef { yarn: 0, point: 1 })
        );
        assert!(sim.fabric().contacts.is_empty());
        assert_eq!(sim.fabric().yarns[0].points.len(), 11);
        assert!(sim.fabric().yarns[0].points.iter().all(|p| p.node != 0));
        let kept = &sim.fabric().yarns[1].points[2];
        assert!(kept.node == 0 && kept.fixed_u);
        assert!(sim.q().iter().all(|v| v.is_finite()));
        assert!(sim.slid_off_contacts().is_empty());

        // The two yarns are now independent: pulling on goes on without
        // error, yarn 0 follows its end (its tail node moves by the pull),
        // and yarn 1 stays on its straight line between its pins (to 1 um,
        // about 1e-3 of the radius: the sliding before removal dragged it by
        // a few 1e-8 m through the soft EIL constraint).
        let tail0 = sim.layout().node_x(sim.q(), 1).x;
        for _ in 0..3 {
            let x = sim.layout().x(11);
            sim.q_mut()[x] += 0.001;
            sim.step(false, None, &mut |_, _| {}).expect("step after removal");
        }
        let moved = sim.layout().node_x(sim.q(), 1).x - tail0;
        assert!(
            (moved - 0.003).abs() < 3e-4,
            "the free tail moved {moved} m, the end 3 mm"
        );
        for p in &sim.fabric().yarns[1].points {
            let x = sim.layout().node_x(sim.q(), p.node);
            assert!((x.x - 0.004).abs() < 1e-6 && x.z.abs() < 1e-6, "yarn 1 bent: {x:?}");
        }
    }

    #[test]
    fn without_removal_the_contact_point_ends_outside_its_yarn() {
        // What removal prevents: the contact stays and its u on yarn 0 is
        // below the yarn's start.
        let sim = pull(false, 8);
        assert_eq!(sim.fabric().contacts.len(), 1);
        let found = sim.slid_off_contacts();
        assert_eq!(found, vec![(0, PointRef { yarn: 0, point: 1 })]);
    }
}
