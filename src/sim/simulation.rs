//! Time stepping and quasi-static relaxation of an EoL fabric.
//!
//! One step (docs/MODEL.md, "Solver"): re-assign EIL points, initialise the nodes
//! that come back from EIL from the contact constraint, build the stencils,
//! and minimise the incremental potential with Newton. A failed solve halves
//! the step and retries; successes let it grow back (docs/MODEL.md, "Adaptive step").
//! Contacts whose `u` left a yarn are removed before the assignment
//! (`sim::removal`). The Coulomb limits of the friction springs are taken
//! from the state at the start of each step; after an accepted step the
//! anchors move to where the capped springs' return mapping left them (see
//! `sim::friction`).

use super::assignment::{assign, assign_after, free_mask, Assignment};
use super::contact_terms::{self, ContactState, ContactTerms};
use super::dofs::DofLayout;
use super::friction::{coulomb_limits, update_anchors};
use super::params::SimParams;
use super::problem::EolProblem;
use super::slide_stops::SlideStops;
use super::system::{build_sets, rest_data, Discretization, RestData, StepInputs};
use super::transfer::transfer;
use super::tripwire::Tripwire;
use crate::solver::assembly::{gradient, AnyStencilSet, AssemblyError};
use crate::solver::linear::LinearSolver;
use crate::solver::newton::{IterStats, NewtonError, NewtonHooks, NewtonParams, NewtonStatus};
use crate::topology::{Fabric, PointRef};
use std::sync::atomic::AtomicBool;

#[derive(Debug, thiserror::Error)]
pub enum SimError {
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error(transparent)]
    Newton(#[from] NewtonError),
    #[error("the step failed even at the smallest time step {0:.3e} s")]
    StepTooSmall(f64),
}

/// What one accepted step did.
#[derive(Clone, Debug)]
pub struct StepReport {
    pub h: f64,
    pub newton_iterations: usize,
    pub retries: usize,
    pub eil_count: usize,
    pub converged: bool,
    /// The step ended early because a real segment closed (`sim::tripwire`).
    pub closed_segment: bool,
}

pub struct Simulation {
    pub fabric: Fabric,
    pub params: SimParams,
    pub layout: DofLayout,
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub anchors: Vec<f64>,
    /// Coulomb limit `mu |f_n|` per point, lagged from the step's start.
    pub friction_limits: Vec<f64>,
    pub rest: RestData,
    pub assignment: Assignment,
    pub solver: LinearSolver,
    pub newton: NewtonParams,
    /// Current time step (s); adapted.
    pub h: f64,
    pub h_min: f64,
    pub h_max: f64,
    pub time: f64,
    /// Barrier stiffness and gap carried between steps (contact on only).
    pub contact: ContactState,
    /// Contacts removed so far: their `u` left a yarn (`sim::removal`) or
    /// they pulled (`sim::separation`).
    pub removed: Vec<super::removal::RemovedContact>,
    /// Per contact, the unit normal from its back yarn to its front yarn,
    /// carried from step to step while separation is on (`sim::separation`);
    /// empty otherwise.
    pub contact_normals: Vec<crate::topology::Vec3>,
    /// When `Some`, every accepted Newton iterate of the following steps is
    /// appended (`NewtonHooks::on_accepted`), the iterates of a retried
    /// attempt removed again: the path the solver took, for tests and
    /// diagnostics that audit it. `None` (the default) records nothing.
    pub iterate_log: Option<Vec<Vec<f64>>>,
}

impl Simulation {
    pub fn new(fabric: Fabric, params: SimParams, solver: LinearSolver, h: f64) -> Self {
        let layout = DofLayout::new(&fabric);
        let q = layout.gather(&fabric);
        let rest_seg = super::assignment::rest_segment_lengths(&fabric);
        let assignment = assign(&fabric, &layout, &q, &rest_seg, params.assign);
        let rest = rest_data(&fabric, &layout, &assignment, &q);
        let anchors = (0..layout.n_points()).map(|i| q[3 * layout.n_nodes + i]).collect();
        let friction_limits = coulomb_limits(&fabric, &layout, &assignment, &q, &params, &rest.rest_seg);
        let mut sim = Simulation {
            v: vec![0.0; q.len()],
            fabric,
            params,
            layout,
            q,
            anchors,
            friction_limits,
            rest,
            assignment,
            solver,
            newton: NewtonParams::default(),
            h,
            h_min: h * 1e-4,
            h_max: h,
            time: 0.0,
            contact: ContactState::default(),
            removed: Vec::new(),
            contact_normals: Vec::new(),
            iterate_log: None,
        };
        if sim.params.separation.is_some() {
            sim.update_contact_normals();
        }
        sim
    }

    /// The stencil sets of the current assignment; `inertia` as in [`StepInputs`].
    fn sets(&self, disc: &Discretization, inertia: Option<(f64, &[f64])>) -> Vec<Box<dyn AnyStencilSet>> {
        let step = StepInputs {
            inertia,
            anchors: &self.anchors,
            friction_limits: &self.friction_limits,
        };
        build_sets(disc, &self.q, &self.params, &self.rest, &step)
    }

    /// Builds the Newton problem for the current assignment; `inertia` as in [`StepInputs`].
    pub fn problem(&self, inertia: Option<(f64, &[f64])>) -> Result<EolProblem, SimError> {
        self.step_problem(inertia, false)
    }

    /// [`problem`](Self::problem), with the tripwire of a relaxation step
    /// when `relaxing` (`sim::tripwire`).
    fn step_problem(&self, inertia: Option<(f64, &[f64])>, relaxing: bool) -> Result<EolProblem, SimError> {
        let disc = Discretization::new(&self.fabric, &self.layout, &self.assignment);
        let sets = self.sets(&disc, inertia);
        let contact = ContactTerms::new(&disc, &self.q, &self.params, &self.contact);
        let stops = self.slide_stops(&disc);
        let tripwire = if relaxing {
            self.tripwire(&disc)
        } else {
            Tripwire::default()
        };
        Ok(self
            .problem_of(sets, contact)?
            .with_slide_stops(stops)
            .with_tripwire(tripwire))
    }

    /// `fraction` of each yarn's rest segment, the distances of the
    /// sliding stops and the tripwire; `None` (the mechanism is off)
    /// without EIL or with `fraction` 0.
    fn eil_margins(&self, fraction: f64) -> Option<Vec<f64>> {
        (self.params.assign.enable_eil && fraction > 0.0)
            .then(|| self.rest.rest_seg.iter().map(|s| fraction * s).collect())
    }

    /// Where sliding points stop within a step (`sim::slide_stops`).
    fn slide_stops(&self, disc: &Discretization) -> SlideStops {
        self.eil_margins(self.params.assign.stop_fraction)
            .map_or_else(SlideStops::default, |m| SlideStops::new(disc, &m))
    }

    /// The segments whose closing ends a relaxation step (`sim::tripwire`).
    fn tripwire(&self, disc: &Discretization) -> Tripwire {
        self.eil_margins(self.params.assign.close_fraction)
            .map_or_else(Tripwire::default, |m| Tripwire::new(disc, &m))
    }

    /// The Newton problem of these sets, with the thickness contact attached.
    fn problem_of(
        &self,
        sets: Vec<Box<dyn AnyStencilSet>>,
        contact: Option<ContactTerms>,
    ) -> Result<EolProblem, SimError> {
        let free = free_mask(&self.fabric, &self.layout, &self.assignment);
        let mut problem = EolProblem::new(self.layout.n_nodes, self.layout.len(), sets, free)?
            .with_ordering_groups(self.layout.node_of_dof(&self.fabric));
        if let Some(terms) = contact {
            problem.attach_contact(&self.q, terms)?;
        }
        Ok(problem)
    }

    /// Largest free-row force of the potential alone (no inertia), in
    /// units of the axial stiffness: a dimensionless equilibrium residual.
    ///
    /// Only a gradient is needed, so without thickness contact the sets are
    /// summed directly: no Hessian pattern, binding or Hessian values (this
    /// test runs after every relaxation step). With contact the barrier's
    /// stiffness is balanced against the elastic forces when the problem is
    /// built, so that path builds the whole problem.
    pub fn static_residual(&self) -> Result<f64, SimError> {
        let disc = Discretization::new(&self.fabric, &self.layout, &self.assignment);
        let sets = self.sets(&disc, None);
        let g = match ContactTerms::new(&disc, &self.q, &self.params, &self.contact) {
            Some(terms) => self.problem_of(sets, Some(terms))?.free_gradient(&self.q)?,
            None => gradient(&sets, &self.q, &free_mask(&self.fabric, &self.layout, &self.assignment)),
        };
        Ok(g.iter().fold(0.0f64, |m, v| m.max(v.abs())) / self.params.rod.ks)
    }

    /// The potential energy `V(q)` of the current state: every term of the
    /// current discretization, without inertia (J).
    pub fn potential_energy(&self) -> Result<f64, SimError> {
        use crate::solver::newton::Problem;
        Ok(self.problem(None)?.energy(&self.q))
    }

    /// The assignment the next step would start from.
    fn next_assignment(&self) -> Assignment {
        assign_after(
            &self.fabric,
            &self.layout,
            &self.q,
            &self.rest.rest_seg,
            self.params.assign,
            Some(&self.assignment),
        )
    }

    /// Points whose kind (real or EIL) the next re-assignment would
    /// change. A relaxed state is an equilibrium under its current
    /// assignment; when this is not 0, the next step would start from a
    /// different discretization (docs/RELAX.md, "Open problems").
    pub fn pending_kind_changes(&self) -> usize {
        let next = self.next_assignment();
        next.eil
            .iter()
            .zip(&self.assignment.eil)
            .filter(|(a, b)| a != b)
            .count()
    }

    /// Re-assigns EIL points and moves the state so every soft EIL
    /// constraint starts the step at rest (see `sim::transfer`).
    fn reassign(&mut self) {
        let new = self.next_assignment();
        transfer(&self.fabric, &self.layout, &self.assignment, &new, &mut self.q);
        self.assignment = new;
    }

    /// One step. `dynamic = false` is a relaxation step: zero velocity
    /// prediction, so the inertia term is a proximal regulariser.
    pub fn step(
        &mut self,
        dynamic: bool,
        cancel: Option<&AtomicBool>,
        on_iter: &mut dyn FnMut(&IterStats, usize),
    ) -> Result<StepReport, SimError> {
        if self.params.remove_slid_off {
            self.remove_slid_off();
        }
        self.reassign();
        self.friction_limits = coulomb_limits(
            &self.fabric,
            &self.layout,
            &self.assignment,
            &self.q,
            &self.params,
            &self.rest.rest_seg,
        );
        let eil_count = self.assignment.eil_count();
        let q0 = self.q.clone();
        let mut retries = 0;
        loop {
            let h = self.h;
            let pred: Vec<f64> = if dynamic {
                q0.iter().zip(&self.v).map(|(q, v)| q + h * v).collect()
            } else {
                q0.clone()
            };
            let mut problem = self.step_problem(Some((h, &pred)), !dynamic)?;
            let mut q = q0.clone();
            let mut cb = |s: &IterStats| on_iter(s, eil_count);
            let logged = self.iterate_log.as_ref().map_or(0, Vec::len);
            let mut log = self.iterate_log.as_mut().map(|l| move |q: &[f64]| l.push(q.to_vec()));
            let hooks = NewtonHooks {
                on_iteration: Some(&mut cb),
                cancel,
                on_accepted: log.as_mut().map(|f| f as &mut dyn FnMut(&[f64])),
            };
            let report = contact_terms::minimize(&mut problem, &mut q, &mut self.solver, &self.newton, hooks)?;
            // A relaxation step is a proximal step in pseudo time: any iterate
            // that lowered the energy is progress, so hitting the iteration cap
            // is not a failure there (dynamics must converge every step).
            let decreased = report.history.first().is_some_and(|s0| report.energy < s0.energy);
            let accept_partial = !dynamic
                && decreased
                && matches!(report.status, NewtonStatus::MaxIterations | NewtonStatus::Rediscretize);
            if report.converged() || accept_partial || report.status == NewtonStatus::Cancelled {
                let converged = report.converged();
                self.v = if dynamic {
                    q.iter().zip(&q0).map(|(a, b)| (a - b) / h).collect()
                } else {
                    vec![0.0; q.len()]
                };
                if let Some(c) = &problem.contact {
                    self.contact = c.state(&q);
                }
                self.q = q;
                self.time += h;
                if self.params.terms.friction {
                    update_anchors(
                        &mut self.anchors,
                        &self.friction_limits,
                        &self.q,
                        &self.layout,
                        self.params.rod.kf,
                    );
                }
                if converged && retries == 0 {
                    self.h = (self.h * 2.0).min(self.h_max);
                }
                // On the state the step ended in, before a prescribed
                // motion of the next step can move pins (sim::separation).
                if self.params.separation.is_some() {
                    self.separate_after_step();
                }
                return Ok(StepReport {
                    h,
                    newton_iterations: report.history.len(),
                    retries,
                    eil_count,
                    converged,
                    closed_segment: report.status == NewtonStatus::Rediscretize,
                });
            }
            if let Some(l) = self.iterate_log.as_mut() {
                l.truncate(logged);
            }
            retries += 1;
            self.h *= 0.5;
            if self.h < self.h_min {
                return Err(SimError::StepTooSmall(self.h));
            }
        }
    }

    /// Per contact with an EIL point, the distance between where its two
    /// yarns put it (the soft constraint's violation; see
    /// `RodParams::kc_factor`). Contacts with both points real share one
    /// node and have no gap.
    pub fn eil_gaps(&self) -> Vec<f64> {
        let (f, l, a) = (&self.fabric, &self.layout, &self.assignment);
        f.contacts
            .iter()
            .filter(|c| a.is_eil(l, c.front) || a.is_eil(l, c.back))
            .map(|c| (interpolated(f, l, a, &self.q, c.front) - interpolated(f, l, a, &self.q, c.back)).norm())
            .collect()
    }

    /// The fabric with the current state written in: positions, `u`,
    /// EIL flags, points re-sorted by `u` and contacts re-addressed.
    pub fn snapshot(&self) -> Fabric {
        let mut f = self.fabric.clone();
        let l = &self.layout;
        l.scatter(&self.q, &mut f);
        for (yi, y) in f.yarns.iter_mut().enumerate() {
            for (pi, p) in y.points.iter_mut().enumerate() {
                p.eil = self.assignment.is_eil(l, PointRef { yarn: yi, point: pi });
            }
        }
        // Nodes whose every point is EIL sit where the front point interpolates.
        for c in &self.fabric.contacts {
            if self.assignment.is_eil(l, c.front) && self.assignment.is_eil(l, c.back) {
                f.nodes[c.node].x = interpolated(&self.fabric, l, &self.assignment, &self.q, c.front);
            }
        }
        sort_points(&mut f, &self.assignment);
        f
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::assignment::tests::crossing_fabric;

    /// Yarn 0's contact point starts 0.21 from a fixed point (rest segment
    /// 1/3, safety distance 0.033): real, and the assignment holds.
    fn crossing() -> Simulation {
        let f = crossing_fabric(
            &[
                [0.7, 0.0, 0.0],
                [0.0, 0.0, 0.0],
                [0.49, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.7, -0.5, 0.0],
                [0.7, 0.5, 0.0],
            ],
            [
                &[(1, 0.0, true), (2, 0.49, true), (0, 0.7, false), (3, 1.0, true)],
                &[(4, 0.0, true), (0, 0.5, false), (5, 1.0, true)],
            ],
            1.0,
            2,
            1,
        );
        Simulation::new(f, SimParams::default(), LinearSolver::direct(), 1e-2)
    }

    #[test]
    fn a_contact_slid_next_to_a_fixed_point_is_a_pending_kind_change() {
        let mut sim = crossing();
        assert_eq!(sim.pending_kind_changes(), 0);
        let contact = PointRef { yarn: 0, point: 2 };
        assert!(!sim.assignment.is_eil(&sim.layout, contact));
        // Slid to 0.01 from the fixed point at 0.49: the next step would
        // make it EIL.
        let u = sim.layout.u(contact);
        sim.q[u] = 0.5;
        assert_eq!(sim.pending_kind_changes(), 1);
        sim.reassign();
        assert!(sim.assignment.is_eil(&sim.layout, contact));
        assert_eq!(sim.pending_kind_changes(), 0, "the new assignment holds");
    }
}
