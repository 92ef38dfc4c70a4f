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
//! The other removal, by the normal-force sign test, is `sim::separation`;
//! both end in `Simulation::remove_contacts`.

use super::assignment::{assign, rest_segment_lengths};
use super::dofs::DofLayout;
use super::simulation::{interpolated, Simulation};
use crate::topology::{Contact, PointRef};

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
    /// The normal force pulled the yarns together (`sim::separation`); N.
    Pulling { normal_force: f64 },
}

impl RemovalCause {
    pub fn is_slid_off(&self) -> bool {
        matches!(self, RemovalCause::SlidOff(_))
    }
}

impl Simulation {
    /// Whether a point's `u` is at or beyond its yarn's end points (NaN
    /// counts as off).
    fn is_off_yarn(&self, p: PointRef) -> bool {
        let l = &self.layout;
        let u = |point| self.q[l.u(PointRef { yarn: p.yarn, point })];
        let last = self.fabric.yarns[p.yarn].points.len() - 1;
        let up = u(p.point);
        !(up > u(0) && up < u(last))
    }

    /// Every contact point whose `u` left its yarn, with its contact.
    pub fn slid_off_contacts(&self) -> Vec<(usize, PointRef)> {
        self.fabric
            .contacts
            .iter()
            .enumerate()
            .flat_map(|(k, c)| [(k, c.front), (k, c.back)])
            .filter(|&(_, p)| self.is_off_yarn(p))
            .collect()
    }

    /// Removes every contact that slid off a yarn; returns how many points
    /// left their yarns (one per removed contact, two if both did).
    pub fn remove_slid_off(&mut self) -> usize {
        let found = self.slid_off_contacts();
        if found.is_empty() {
            return 0;
        }
        let old_layout = self.layout.clone();
        // The state written into the fabric, EIL points at their interpolated
        // positions (the staying point becomes real and must start there).
        let mut f = self.fabric.clone();
        old_layout.scatter(&self.q, &mut f);
        for &(k, gone) in &found {
            let c = &self.fabric.contacts[k];
            let stay = if gone == c.front { c.back } else { c.front };
            if found.contains(&(k, stay)) {
                // Both left their yarns: both go, and the node is unused.
                continue;
            }
            if self.assignment.is_eil(&old_layout, stay) {
                f.nodes[c.node].x = interpolated(&self.fabric, &old_layout, &self.assignment, &self.q, stay);
            }
            f.yarns[stay.yarn].points[stay.point].fixed_u = true;
        }
        // Old global point -> new global point (None for deleted points).
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
            retain_mask(&mut y.points, k);
        }
        let keep_contact: Vec<bool> = (0..f.contacts.len())
            .map(|k| !found.iter().any(|&(r, _)| r == k))
            .collect();
        for &(k, gone) in &found {
            self.removed.push(RemovedContact {
                contact: self.fabric.contacts[k].clone(),
                cause: RemovalCause::SlidOff(gone),
                time: self.time,
            });
        }
        self.remove_contacts(f, &keep_contact, &old_layout, &new_index);
        found.len()
    }

    /// Drops the contacts of `f` whose `keep_contact` entry is false (and
    /// their per-contact data), renumbers the kept contacts' points by
    /// `new_index`, and installs `f` (see [`Self::rebuild`]).
    pub(super) fn remove_contacts(
        &mut self,
        mut f: crate::topology::Fabric,
        keep_contact: &[bool],
        old_layout: &DofLayout,
        new_index: &[Vec<Option<usize>>],
    ) {
        let removed_nodes: Vec<usize> = (0..f.contacts.len())
            .filter(|&k| !keep_contact[k])
            .map(|k| f.contacts[k].node)
            .collect();
        retain_mask(&mut f.contacts, keep_contact);
        for c in &mut f.contacts {
            for p in [&mut c.front, &mut c.back] {
                p.point = new_index[p.yarn][p.point].expect("a kept contact's points are kept");
            }
            // A stitch contact's other node lost its contact: no wrapping pair.
            if c.partner.is_some_and(|n| removed_nodes.contains(&n)) {
                c.partner = None;
            }
        }
        retain_mask(&mut self.rest.wrap_rest, keep_contact);
        retain_mask(&mut self.rest.shear_rest, keep_contact);
        if self.contact_normals.len() == keep_contact.len() {
            retain_mask(&mut self.contact_normals, keep_contact);
        }
        self.rebuild(f, old_layout, new_index);
    }

    /// Installs a fabric whose nodes are the old ones (plus, after a
    /// separation, copies appended at the end, whose velocities the caller
    /// sets) and whose points are the old ones minus some (`new_index`),
    /// carrying the per-point state.
    fn rebuild(&mut self, f: crate::topology::Fabric, old: &DofLayout, new_index: &[Vec<Option<usize>>]) {
        let layout = DofLayout::new(&f);
        let q = layout.gather(&f);
        let mut v = vec![0.0; layout.len()];
        v[..3 * old.n_nodes].copy_from_slice(&self.v[..3 * old.n_nodes]);
        let mut anchors = vec![0.0; layout.n_points()];
        for (yi, map) in new_index.iter().enumerate() {
            for (pi, np) in map.iter().enumerate() {
                let Some(np) = *np else { continue };
                let (o, n) = (PointRef { yarn: yi, point: pi }, PointRef { yarn: yi, point: np });
                v[layout.u(n)] = self.v[old.u(o)];
                anchors[layout.point(n)] = self.anchors[old.point(o)];
            }
        }
        // Points that just became fixed-u hold no friction spring (the
        // anchors of fixed coordinates are never read), so no reset is needed.
        self.rest.rest_seg = rest_segment_lengths(&f);
        self.assignment = assign(&f, &layout, &q, &self.rest.rest_seg, self.params.assign);
        self.friction_limits = vec![0.0; layout.n_points()];
        self.fabric = f;
        self.layout = layout;
        self.q = q;
        self.v = v;
        self.anchors = anchors;
    }
}

/// Keeps the elements whose `keep` entry is true.
fn retain_mask<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut it = keep.iter();
    v.retain(|_| *it.next().expect("one mask entry per element"));
}

#[cfg(test)]
mod tests {
    use super::RemovalCause;
    use crate::sim::assignment::tests::crossing_fabric;
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
            let x = sim.layout.x(11);
            sim.q[x] += 0.001;
            sim.step(false, None, &mut |_, _| {}).expect("step");
        }
        sim
    }

    #[test]
    fn a_tail_pulled_through_its_crossing_leaves_it() {
        // Pulled 3 mm: the tail (4 mm) still passes the crossing.
        let sim = pull(true, 3);
        assert_eq!(sim.fabric.contacts.len(), 1);
        assert!(sim.removed.is_empty());

        // Pulled 8 mm: the contact's u on yarn 0 went below the yarn start
        // and the contact is gone; yarn 1 keeps the node as a fixed-u point.
        let mut sim = pull(true, 8);
        assert_eq!(sim.removed.len(), 1, "{:?}", sim.removed);
        assert_eq!(
            sim.removed[0].cause,
            RemovalCause::SlidOff(PointRef { yarn: 0, point: 1 })
        );
        assert!(sim.fabric.contacts.is_empty());
        assert_eq!(sim.fabric.yarns[0].points.len(), 11);
        assert!(sim.fabric.yarns[0].points.iter().all(|p| p.node != 0));
        let kept = &sim.fabric.yarns[1].points[2];
        assert!(kept.node == 0 && kept.fixed_u);
        assert!(sim.q.iter().all(|v| v.is_finite()));
        assert!(sim.slid_off_contacts().is_empty());

        // The two yarns are now independent: pulling on goes on without
        // error, yarn 0 follows its end (its tail node moves by the pull),
        // and yarn 1 stays on its straight line between its pins (to 1 um,
        // about 1e-3 of the radius: the sliding before removal dragged it by
        // a few 1e-8 m through the soft EIL constraint).
        let tail0 = sim.layout.node_x(&sim.q, 1).x;
        for _ in 0..3 {
            let x = sim.layout.x(11);
            sim.q[x] += 0.001;
            sim.step(false, None, &mut |_, _| {}).expect("step after removal");
        }
        let moved = sim.layout.node_x(&sim.q, 1).x - tail0;
        assert!(
            (moved - 0.003).abs() < 3e-4,
            "the free tail moved {moved} m, the end 3 mm"
        );
        for p in &sim.fabric.yarns[1].points {
            let x = sim.layout.node_x(&sim.q, p.node);
            assert!((x.x - 0.004).abs() < 1e-6 && x.z.abs() < 1e-6, "yarn 1 bent: {x:?}");
        }
    }

    #[test]
    fn without_removal_the_contact_point_ends_outside_its_yarn() {
        // What removal prevents: the contact stays and its u on yarn 0 is
        // below the yarn's start.
        let sim = pull(false, 8);
        assert_eq!(sim.fabric.contacts.len(), 1);
        let found = sim.slid_off_contacts();
        assert_eq!(found, vec![(0, PointRef { yarn: 0, point: 1 })]);
    }
}
