//! The state of a run on its current discretization: the fabric, its DOF
//! layout and assignment, the coordinates and velocities, and the per-point
//! and per-contact data carried from step to step.
//!
//! One struct, so that the events layer (contact removal and separation)
//! can take the state, change the fabric under it and carry every field
//! over, without knowing the stepper that owns it.

use super::discretization::assignment::{assign, rest_segment_lengths, Assignment};
use super::discretization::dofs::DofLayout;
use super::discretization::interpolated;
use super::discretization::rest_data::{rest_data, RestData};
use super::params::AssignParams;
use crate::topology::{Fabric, PointRef, Vec3};

/// What a run carries from step to step (the stepper's `Simulation` owns it).
#[derive(Clone, Debug)]
pub struct EolState {
    pub fabric: Fabric,
    pub layout: DofLayout,
    /// Every coordinate (`dofs`): node positions, then one `u` per point.
    pub q: Vec<f64>,
    /// `dq/dt` per coordinate (zero after a relaxation step).
    pub v: Vec<f64>,
    /// Friction anchor per point (`terms::coulomb_limits`).
    pub anchors: Vec<f64>,
    /// Coulomb limit `mu |f_n|` per point, lagged from the step's start.
    pub friction_limits: Vec<f64>,
    pub rest: RestData,
    pub assignment: Assignment,
    /// Per contact, the unit normal from its back yarn to its front yarn,
    /// carried from step to step while separation is on
    /// (`sim::events::separation`); empty otherwise.
    pub contact_normals: Vec<Vec3>,
}

impl EolState {
    /// The compiled state of `fabric`: at rest, anchors where the points
    /// are, no Coulomb limits yet.
    pub fn new(fabric: Fabric, assign_params: AssignParams) -> Self {
        let layout = DofLayout::new(&fabric);
        let q = layout.gather(&fabric);
        let rest_seg = rest_segment_lengths(&fabric);
        let assignment = assign(&fabric, &layout, &q, &rest_seg, assign_params);
        let rest = rest_data(&fabric, &layout, &assignment, &q);
        let anchors = (0..layout.n_points()).map(|i| q[3 * layout.n_nodes + i]).collect();
        EolState {
            v: vec![0.0; q.len()],
            friction_limits: Vec::new(),
            fabric,
            layout,
            q,
            anchors,
            rest,
            assignment,
            contact_normals: Vec::new(),
        }
    }

    /// Per contact with an EIL point, the distance between where its two
    /// yarns put it (the soft constraint's violation; see
    /// `RodParams::kc_factor`). Contacts with both points real share one
    /// node and have no gap.
    pub fn eil_gaps(&self) -> Vec<f64> {
        let (f, l, a, q) = (&self.fabric, &self.layout, &self.assignment, &self.q);
        f.contacts
            .iter()
            .filter(|c| a.is_eil(l, c.front) || a.is_eil(l, c.back))
            .map(|c| (interpolated(f, l, a, q, c.front) - interpolated(f, l, a, q, c.back)).norm())
            .collect()
    }

    /// The fabric with the current state written in: positions, `u`,
    /// EIL flags, points re-sorted by `u` and contacts re-addressed.
    pub fn snapshot(&self) -> Fabric {
        let st = self;
        let mut f = st.fabric.clone();
        let l = &st.layout;
        l.scatter(&st.q, &mut f);
        for (yi, y) in f.yarns.iter_mut().enumerate() {
            for (pi, p) in y.points.iter_mut().enumerate() {
                p.eil = st.assignment.is_eil(l, PointRef { yarn: yi, point: pi });
            }
        }
        // Nodes whose every point is EIL sit where the front point interpolates.
        for c in &st.fabric.contacts {
            if st.assignment.is_eil(l, c.front) && st.assignment.is_eil(l, c.back) {
                f.nodes[c.node].x = interpolated(&st.fabric, l, &st.assignment, &st.q, c.front);
            }
        }
        sort_points(&mut f, &st.assignment);
        f
    }
}

/// Reorders each yarn's points by the assignment's `u` order and rewrites contact addresses.
fn sort_points(f: &mut Fabric, a: &Assignment) {
    let mut new_index: Vec<Vec<usize>> = Vec::with_capacity(f.yarns.len());
    for (yi, y) in f.yarns.iter_mut().enumerate() {
        let ord = &a.orders()[yi];
        let mut inv = vec![0; ord.len()];
        for (k, &pi) in ord.iter().enumerate() {
            inv[pi] = k;
        }
        y.points = ord.iter().map(|&pi| y.points[pi].clone()).collect();
        new_index.push(inv);
    }
    for c in &mut f.contacts {
        for p in [&mut c.front, &mut c.back] {
            p.point = new_index[p.yarn][p.point];
        }
    }
}
