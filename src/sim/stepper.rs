//! Time stepping of an EoL fabric: [`Simulation`].
//!
//! One step (docs/MODEL.md, "Solver"): remove contacts whose `u` left a yarn
//! (`sim::events::removal`), re-assign EIL points and move the state so
//! every EIL constraint starts at rest (`sim::discretization::transfer`),
//! take the friction springs' Coulomb limits from the state at the step's
//! start (`sim::terms::coulomb_limits`), build the stencils and minimise the
//! incremental potential with Newton (`sim::problem`). A failed solve halves
//! the step and retries; successes let it grow back (docs/MODEL.md,
//! "Adaptive step"). After an accepted step the friction anchors move to
//! where the capped springs' return mapping left them, and with separation
//! on the contacts that pull are split (`sim::events::separation`).
//!
//! The settings of the steps are a [`Schedule`] passed to each step
//! ([`Simulation::step_with`]); [`Simulation::step`] uses the simulation's
//! own.

use super::discretization::assignment::{assign_after, Assignment};
use super::discretization::dofs::DofLayout;
use super::discretization::rest_data::RestData;
use super::discretization::transfer::transfer;
use super::discretization::Discretization;
use super::events::{removal, separation, ContactRemoval, RemovedContact};
use super::params::{AssignParams, SimParams};
use super::problem::build::ProblemBuilder;
use super::problem::solve::minimize;
use super::problem::EolProblem;
use super::schedule::Schedule;
use super::state::EolState;
use super::terms::coulomb_limits::{coulomb_limits, update_anchors};
use super::terms::thickness_contact::ContactState;
use crate::solver::assembly::timing::TermTimes;
use crate::solver::assembly::AssemblyError;
use crate::solver::linear::LinearSolver;
use crate::solver::newton::{IterStats, NewtonError, NewtonHooks, NewtonStatus};
use crate::topology::{ContactKind, Fabric, PointRef, Vec3};
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
    /// The step ended early because a real segment closed (`sim::problem::tripwire`).
    pub closed_segment: bool,
    /// Seconds per stencil set and in the linear solver, retried attempts included.
    pub times: TermTimes,
}

/// An EoL fabric being simulated: its state, parameters, linear solver and
/// dynamics schedule, and what happened to it so far.
pub struct Simulation {
    state: EolState,
    params: SimParams,
    solver: LinearSolver,
    /// The schedule of [`Simulation::step`].
    schedule: Schedule,
    /// Simulated time (s): the sum of the accepted steps.
    time: f64,
    /// Barrier stiffness and gap carried between steps (contact on only).
    contact: ContactState,
    /// Contacts removed so far: their `u` left a yarn or they pulled.
    removed: Vec<RemovedContact>,
    /// See [`Simulation::record_iterates`].
    iterate_log: Option<Vec<Vec<f64>>>,
}

impl Simulation {
    /// A simulation of `fabric` at rest, stepping by `h` (its schedule:
    /// [`Schedule::new`]).
    pub fn new(fabric: Fabric, params: SimParams, solver: LinearSolver, h: f64) -> Self {
        let mut state = EolState::new(fabric, params.assign);
        state.friction_limits = coulomb_limits(
            &state.fabric,
            &state.layout,
            &state.assignment,
            &state.q,
            &params,
            &state.rest.rest_seg,
        );
        let mut sim = Simulation {
            state,
            params,
            solver,
            schedule: Schedule::new(h),
            time: 0.0,
            contact: ContactState::default(),
            removed: Vec::new(),
            iterate_log: None,
        };
        if sim.params.separation.is_some() {
            sim.update_contact_normals();
        }
        sim
    }

    /// The compiled fabric under the run (positions as compiled; the
    /// current state is [`Simulation::snapshot`]).
    pub fn fabric(&self) -> &Fabric {
        &self.state.fabric
    }

    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// The parameters; a change applies from the next step on.
    pub fn params_mut(&mut self) -> &mut SimParams {
        &mut self.params
    }

    /// Which coordinate of [`Simulation::q`] is what.
    pub fn layout(&self) -> &DofLayout {
        &self.state.layout
    }

    /// The coordinates: node positions, then one `u` per yarn point.
    pub fn q(&self) -> &[f64] {
        &self.state.q
    }

    /// The coordinates, to prescribe a motion (a pinned node moved before a
    /// step, say).
    pub fn q_mut(&mut self) -> &mut [f64] {
        &mut self.state.q
    }

    /// The EIL assignment of the last step.
    pub fn assignment(&self) -> &Assignment {
        &self.state.assignment
    }

    pub fn rest(&self) -> &RestData {
        &self.state.rest
    }

    /// The whole state carried from step to step.
    pub fn state(&self) -> &EolState {
        &self.state
    }

    /// The state, for tests that set up what a run could not reach.
    #[cfg(test)]
    pub(crate) fn state_mut(&mut self) -> &mut EolState {
        &mut self.state
    }

    /// The schedule of [`Simulation::step`] (its Newton settings, current
    /// time step and bounds).
    pub fn schedule(&self) -> &Schedule {
        &self.schedule
    }

    pub fn schedule_mut(&mut self) -> &mut Schedule {
        &mut self.schedule
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Contacts removed so far: their `u` left a yarn
    /// (`sim::events::removal`) or they pulled (`sim::events::separation`).
    pub fn removed(&self) -> &[RemovedContact] {
        &self.removed
    }

    /// Per contact, the unit normal from its back yarn to its front yarn
    /// while separation is on (`sim::events::separation`); empty otherwise.
    pub fn contact_normals(&self) -> &[Vec3] {
        &self.state.contact_normals
    }

    /// Starts (`true`) or stops recording every accepted Newton iterate of
    /// the following steps, the iterates of a retried attempt removed
    /// again: the path the solver took, for tests and diagnostics that
    /// audit it. Off by default.
    pub fn record_iterates(&mut self, on: bool) {
        self.iterate_log = on.then(Vec::new);
    }

    /// The iterates recorded since the last call (empty when not
    /// recording); recording goes on.
    pub fn take_iterates(&mut self) -> Vec<Vec<f64>> {
        self.iterate_log.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// The discretization of the current assignment.
    fn discretization(&self) -> Discretization<'_> {
        Discretization::new(&self.state.fabric, &self.state.layout, &self.state.assignment)
    }

    fn builder(&self) -> ProblemBuilder<'_> {
        ProblemBuilder {
            state: &self.state,
            params: &self.params,
            contact: &self.contact,
        }
    }

    /// Builds the Newton problem for the current assignment; `inertia` is
    /// the time step and the predicted coordinates `q_n + h v_n` (`None`:
    /// statics).
    pub fn problem(&self, inertia: Option<(f64, &[f64])>) -> Result<EolProblem, SimError> {
        Ok(self.builder().build(inertia, false)?)
    }

    /// The potential energy `V(q)` of the current state: every term of the
    /// current discretization, without inertia (J).
    pub fn potential_energy(&self) -> Result<f64, SimError> {
        use crate::solver::newton::Problem;
        Ok(self.problem(None)?.energy(self.q()))
    }

    /// Largest free-row force of the potential alone (no inertia), in
    /// units of the axial stiffness: a dimensionless equilibrium residual
    /// (`ProblemBuilder::static_residual`).
    pub fn static_residual(&self) -> Result<f64, SimError> {
        Ok(self.builder().static_residual()?)
    }

    /// The assignment the next step would start from, under `assign_params`.
    fn next_assignment(&self, assign_params: AssignParams) -> Assignment {
        let st = &self.state;
        assign_after(
            &st.fabric,
            &st.layout,
            &st.q,
            &st.rest.rest_seg,
            assign_params,
            Some(&st.assignment),
        )
    }

    /// Points whose kind (real or EIL) the next re-assignment would
    /// change. A relaxed state is an equilibrium under its current
    /// assignment; when this is not 0, the next step would start from a
    /// different discretization (docs/RELAX.md, "Open problems").
    pub fn pending_kind_changes(&self) -> usize {
        let next = self.next_assignment(self.params.assign);
        next.eil
            .iter()
            .zip(&self.state.assignment.eil)
            .filter(|(a, b)| a != b)
            .count()
    }

    /// Re-assigns EIL points and moves the state so every soft EIL
    /// constraint starts the step at rest (see `sim::discretization::transfer`).
    fn reassign(&mut self, assign_params: AssignParams) {
        let new = self.next_assignment(assign_params);
        let st = &mut self.state;
        transfer(&st.fabric, &st.layout, &st.assignment, &new, &mut st.q);
        st.assignment = new;
    }

    /// Applies a contact removal and keeps its records.
    fn apply(&mut self, edit: ContactRemoval, assign_params: AssignParams) {
        let removed = edit.apply(&mut self.state, assign_params);
        self.removed.extend(removed);
    }

    /// One step on the simulation's own schedule ([`Simulation::step_with`]).
    pub fn step(
        &mut self,
        dynamic: bool,
        cancel: Option<&AtomicBool>,
        on_iter: &mut dyn FnMut(&IterStats, usize),
    ) -> Result<StepReport, SimError> {
        let mut schedule = self.schedule;
        let report = self.step_with(&mut schedule, dynamic, cancel, on_iter);
        self.schedule = schedule;
        report
    }

    /// One step with the settings of `schedule`, whose time step it adapts.
    /// `dynamic = false` is a relaxation step: zero velocity prediction, so
    /// the inertia term is a proximal regulariser. `on_iter` sees every
    /// Newton iteration with the step's EIL count.
    pub fn step_with(
        &mut self,
        schedule: &mut Schedule,
        dynamic: bool,
        cancel: Option<&AtomicBool>,
        on_iter: &mut dyn FnMut(&IterStats, usize),
    ) -> Result<StepReport, SimError> {
        let assign_params = schedule.assign_params(self.params.assign);
        if self.params.remove_slid_off {
            self.remove_slid_off_with(assign_params);
        }
        self.reassign(assign_params);
        let st = &mut self.state;
        st.friction_limits = coulomb_limits(
            &st.fabric,
            &st.layout,
            &st.assignment,
            &st.q,
            &self.params,
            &st.rest.rest_seg,
        );
        if schedule.stick {
            // Contacts between layers slide at their Coulomb limit whatever
            // the schedule: sticking holds a fabric's own loops, not one
            // fabric on another (`topology::layers`).
            let mut slides = vec![false; st.friction_limits.len()];
            for c in st.fabric.contacts.iter().filter(|c| c.kind == ContactKind::Layer) {
                for p in [c.front, c.back] {
                    slides[st.layout.point(p)] = true;
                }
            }
            for (limit, slides) in st.friction_limits.iter_mut().zip(slides) {
                if !slides {
                    *limit = f64::INFINITY;
                }
            }
        }
        let eil_count = st.assignment.eil_count();
        let q0 = st.q.clone();
        let mut retries = 0;
        let mut times = TermTimes::default();
        loop {
            let h = schedule.h;
            let pred: Vec<f64> = if dynamic {
                q0.iter().zip(&self.state.v).map(|(q, v)| q + h * v).collect()
            } else {
                q0.clone()
            };
            let mut problem = self.builder().build(Some((h, &pred)), !dynamic)?;
            let mut q = q0.clone();
            let mut cb = |s: &IterStats| on_iter(s, eil_count);
            let logged = self.iterate_log.as_ref().map_or(0, Vec::len);
            let mut log = self.iterate_log.as_mut().map(|l| move |q: &[f64]| l.push(q.to_vec()));
            let hooks = NewtonHooks {
                on_iteration: Some(&mut cb),
                cancel,
                on_accepted: log.as_mut().map(|f| f as &mut dyn FnMut(&[f64])),
            };
            let report = minimize(&mut problem, &mut q, &mut self.solver, &schedule.newton, hooks)?;
            times.merge(&problem.times);
            times.linear_solve_s += report.history.iter().map(|s| s.solve_s).sum::<f64>();
            // A relaxation step is a proximal step in pseudo time: any iterate
            // that lowered the energy is progress, so hitting the iteration cap
            // is not a failure there (dynamics must converge every step).
            let decreased = report.history.first().is_some_and(|s0| report.energy < s0.energy);
            let accept_partial = !dynamic
                && decreased
                && matches!(report.status, NewtonStatus::MaxIterations | NewtonStatus::Rediscretize);
            if report.converged() || accept_partial || report.status == NewtonStatus::Cancelled {
                let converged = report.converged();
                if let Some(c) = &problem.contact {
                    self.contact = c.state(&q);
                }
                self.accept(q, &q0, h, dynamic);
                if converged && retries == 0 {
                    schedule.h = (schedule.h * 2.0).min(schedule.h_max);
                }
                // On the state the step ended in, before a prescribed
                // motion of the next step can move pins (sim::events::separation).
                if self.params.separation.is_some() {
                    self.separate_after_step(assign_params);
                }
                return Ok(StepReport {
                    h,
                    newton_iterations: report.history.len(),
                    retries,
                    eil_count,
                    converged,
                    closed_segment: report.status == NewtonStatus::Rediscretize,
                    times,
                });
            }
            if let Some(l) = self.iterate_log.as_mut() {
                l.truncate(logged);
            }
            retries += 1;
            schedule.h *= 0.5;
            if schedule.h < schedule.h_min {
                return Err(SimError::StepTooSmall(schedule.h));
            }
        }
    }

    /// Takes the accepted coordinates `q` of a step of `h` from `q0`: the
    /// velocities, the time and the friction anchors follow.
    fn accept(&mut self, q: Vec<f64>, q0: &[f64], h: f64, dynamic: bool) {
        let st = &mut self.state;
        st.v = if dynamic {
            q.iter().zip(q0).map(|(a, b)| (a - b) / h).collect()
        } else {
            vec![0.0; q.len()]
        };
        st.q = q;
        self.time += h;
        if self.params.terms.friction {
            update_anchors(
                &mut st.anchors,
                &st.friction_limits,
                &st.q,
                &st.layout,
                self.params.rod.kf,
            );
        }
    }

    /// Every contact point whose `u` left its yarn, with its contact
    /// (`sim::events::removal`).
    pub fn slid_off_contacts(&self) -> Vec<(usize, PointRef)> {
        removal::slid_off_contacts(&self.state)
    }

    /// Removes every contact that slid off a yarn; returns how many points
    /// left their yarns (one per removed contact, two if both did).
    pub fn remove_slid_off(&mut self) -> usize {
        self.remove_slid_off_with(self.params.assign)
    }

    fn remove_slid_off_with(&mut self, assign_params: AssignParams) -> usize {
        let Some(edit) = removal::remove_slid_off(&self.state, self.time) else {
            return 0;
        };
        let n = edit.removed.len();
        self.apply(edit, assign_params);
        n
    }

    /// Sets or turns every contact normal (`sim::events::separation`).
    /// Called when the simulation is made while separation is on.
    pub fn update_contact_normals(&mut self) {
        let normals = separation::turned_normals(&self.state, &self.discretization());
        self.state.contact_normals = normals;
    }

    /// The end-of-step work while separation is on: turn the normals, then
    /// split the contacts that pull.
    fn separate_after_step(&mut self, assign_params: AssignParams) -> usize {
        self.update_contact_normals();
        let forces = self.contact_normal_forces();
        self.split_pulling(forces, assign_params)
    }

    /// The normal force of each contact (N, positive pushing), `None` where
    /// it is not tested (`sim::events::separation`).
    pub fn contact_normal_forces(&self) -> Vec<Option<f64>> {
        separation::normal_forces(&self.state, &self.params, &self.discretization())
    }

    /// Splits every tested contact whose normal force is below
    /// `-min_pull`; returns how many went.
    pub fn separate_pulling(&mut self) -> usize {
        let forces = self.contact_normal_forces();
        self.split_pulling(forces, self.params.assign)
    }

    fn split_pulling(&mut self, forces: Vec<Option<f64>>, assign_params: AssignParams) -> usize {
        let Some(min_pull) = self.params.separation.as_ref().map(|s| s.min_pull) else {
            return 0;
        };
        let Some(edit) = separation::split_pulling(&self.state, forces, min_pull, self.time) else {
            return 0;
        };
        let n = edit.removed.len();
        self.apply(edit, assign_params);
        n
    }

    /// Per contact with an EIL point, the distance between where its two
    /// yarns put it (`EolState::eil_gaps`).
    pub fn eil_gaps(&self) -> Vec<f64> {
        self.state.eil_gaps()
    }

    /// The fabric with the current state written in (`EolState::snapshot`).
    pub fn snapshot(&self) -> Fabric {
        self.state.snapshot()
    }
}

#[cfg(test)]
#[path = "stepper_tests.rs"]
mod tests;
