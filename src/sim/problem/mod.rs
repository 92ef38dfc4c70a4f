//! The problem layer: the Newton [`Problem`] of one step, [`EolProblem`].
//!
//! It holds the stencil sets the terms layer built for the current
//! discretization, the free mask and the block partition for CG, and the
//! three mechanisms that act *inside* a solve, each through its own hook of
//! the generic Newton loop:
//! - [`slide_stops`]: box bounds on sliding `u` ([`Problem::bounds`]);
//! - [`tripwire`]: a closed real segment ends a relaxation step
//!   ([`Problem::must_rediscretize`]);
//! - the thickness contact's trust radius: a step that reached it ends the
//!   solve so the candidate list is rebuilt ([`Problem::must_rebuild`];
//!   [`solve::minimize`] rebuilds and goes on).
//!
//! [`build::ProblemBuilder`] makes the problem of a step from the run's state.

pub mod build;
pub mod slide_stops;
pub mod solve;
pub mod tripwire;

use crate::sim::terms::thickness_contact::{ContactTerms, CONTACT_SET};
use crate::solver::assembly::timing::TermTimes;
use crate::solver::assembly::{
    assemble_timed, bind_all, gradient, hessian_pattern, total_energy_timed, AnyStencilSet, AssemblyError,
};
use crate::solver::newton::Problem;
use crate::sparse::CsrMatrix;
use slide_stops::SlideStops;
use tripwire::Tripwire;

pub struct EolProblem {
    pub sets: Vec<Box<dyn AnyStencilSet>>,
    pub free: Vec<bool>,
    /// Node `x` blocks of 3 then one block per `u`.
    pub blocks: Vec<usize>,
    /// The node of each unknown, for the direct solver's ordering (empty
    /// until [`EolProblem::with_ordering_groups`]).
    pub ordering_groups: Vec<u32>,
    /// Non-persistent contact of this solve (`None` when off): its stencil
    /// set is in `sets`; this holds the candidate list and the CCD cap.
    pub contact: Option<ContactTerms>,
    /// Where sliding points stop within this solve (empty: nowhere).
    pub slide_stops: SlideStops,
    /// Segments whose closing ends this solve (empty: none).
    pub tripwire: Tripwire,
    /// Seconds spent in each stencil set by the Newton solve so far.
    pub times: TermTimes,
    /// Project each stencil's Hessian to PSD ([`Problem::set_projection`]).
    project: bool,
    pattern: CsrMatrix,
}

impl EolProblem {
    pub fn new(
        n_nodes: usize,
        n: usize,
        mut sets: Vec<Box<dyn AnyStencilSet>>,
        free: Vec<bool>,
    ) -> Result<Self, AssemblyError> {
        for s in &sets {
            s.validate(n)?;
        }
        let pattern = hessian_pattern(n, &sets);
        bind_all(&mut sets, &pattern)?;
        let mut blocks: Vec<usize> = (0..n_nodes).map(|i| 3 * i).collect();
        blocks.extend(3 * n_nodes..=n);
        Ok(EolProblem {
            sets,
            free,
            blocks,
            ordering_groups: Vec::new(),
            contact: None,
            slide_stops: SlideStops::default(),
            tripwire: Tripwire::default(),
            times: TermTimes::default(),
            project: true,
            pattern,
        })
    }

    /// Sets the node of each unknown ([`Problem::ordering_groups`]).
    pub fn with_ordering_groups(mut self, groups: Vec<u32>) -> Self {
        self.ordering_groups = groups;
        self
    }

    /// Bounds the sliding points' `u` for Newton ([`Problem::bounds`]).
    pub fn with_slide_stops(mut self, stops: SlideStops) -> Self {
        self.slide_stops = stops;
        self
    }

    /// Ends the solve once a watched segment closes ([`Problem::must_rediscretize`]).
    pub fn with_tripwire(mut self, tripwire: Tripwire) -> Self {
        self.tripwire = tripwire;
        self
    }

    /// Replaces (or removes, with `None`) the set called `name` and rebuilds
    /// the Hessian pattern; used when the contact candidates change.
    pub fn replace_set(&mut self, name: &str, set: Option<Box<dyn AnyStencilSet>>) -> Result<(), AssemblyError> {
        self.sets.retain(|s| s.name() != name);
        if let Some(s) = set {
            s.validate(self.free.len())?;
            self.sets.push(s);
        }
        self.pattern = hessian_pattern(self.free.len(), &self.sets);
        bind_all(&mut self.sets, &self.pattern)
    }

    /// Energy per term name, for diagnostics.
    pub fn breakdown(&self, q: &[f64]) -> Vec<(String, f64)> {
        self.sets.iter().map(|s| (s.name().to_string(), s.energy(q))).collect()
    }

    /// Free-row gradient of the potential at `q`.
    pub fn free_gradient(&self, q: &[f64]) -> Result<Vec<f64>, AssemblyError> {
        Ok(gradient(&self.sets, q, &self.free))
    }

    /// Adds the contact terms: picks kappa from the gradient balance, then
    /// builds the contact stencil set and the new pattern.
    pub fn attach_contact(&mut self, q: &[f64], mut terms: ContactTerms) -> Result<(), AssemblyError> {
        if terms.candidate_count() > 0 {
            let elastic = self.free_gradient(q)?;
            terms.balance_stiffness(q, &elastic, &self.free);
        }
        let set: Box<dyn AnyStencilSet> = Box::new(terms.stencil_set());
        self.contact = Some(terms);
        self.replace_set(CONTACT_SET, Some(set))
    }

    /// Rebuilds the candidate list at `q` (after the trust radius bound a
    /// step) and doubles kappa if the gaps keep closing (IPC); returns the
    /// smallest gap.
    pub fn refresh_contact(&mut self, q: &[f64], prev_min_gap: f64) -> Result<f64, AssemblyError> {
        let Some(terms) = self.contact.as_mut() else {
            return Ok(f64::INFINITY);
        };
        let gap = terms.refresh(q, prev_min_gap);
        let set: Box<dyn AnyStencilSet> = Box::new(terms.stencil_set());
        self.replace_set(CONTACT_SET, Some(set))?;
        Ok(gap)
    }
}

impl Problem for EolProblem {
    fn energy(&mut self, q: &[f64]) -> f64 {
        total_energy_timed(&self.sets, q, &mut self.times)
    }
    fn gradient_hessian(&mut self, q: &[f64], g: &mut [f64], h: &mut CsrMatrix) -> Result<(), AssemblyError> {
        assemble_timed(&self.sets, q, &self.free, g, h, self.project, &mut self.times)
    }
    fn set_projection(&mut self, project: bool) {
        self.project = project;
    }
    fn hessian_pattern(&self) -> CsrMatrix {
        self.pattern.clone()
    }
    fn free(&self) -> &[bool] {
        &self.free
    }
    fn max_step(&mut self, q: &[f64], dq: &[f64]) -> f64 {
        self.contact.as_ref().map_or(1.0, |c| c.max_step(q, dq))
    }
    fn bounds(&self, q: &[f64], lower: &mut [f64], upper: &mut [f64]) -> bool {
        self.slide_stops.fill(q, lower, upper)
    }
    fn must_rediscretize(&self, q: &[f64]) -> bool {
        self.tripwire.tripped(q)
    }
    fn must_rebuild(&self) -> bool {
        self.contact.as_ref().is_some_and(ContactTerms::trust_exceeded)
    }
    fn blocks(&self) -> Vec<usize> {
        self.blocks.clone()
    }
    fn ordering_groups(&self) -> Vec<u32> {
        self.ordering_groups.clone()
    }
}
