//! The Newton problem of a step, built from the run's state: the term
//! sets of the current discretization, the free mask, the mechanisms that
//! act inside the solve (slide stops, tripwire) and the thickness contact.

use super::slide_stops::SlideStops;
use super::tripwire::Tripwire;
use super::EolProblem;
use crate::sim::discretization::assignment::free_mask;
use crate::sim::discretization::Discretization;
use crate::sim::params::SimParams;
use crate::sim::state::EolState;
use crate::sim::terms::thickness_contact::{ContactState, ContactTerms};
use crate::sim::terms::{build_sets, StepInputs};
use crate::solver::assembly::{gradient, AnyStencilSet, AssemblyError};

/// What the problem of a step is built from.
pub struct ProblemBuilder<'a> {
    pub state: &'a EolState,
    pub params: &'a SimParams,
    /// The contact state carried from the last step.
    pub contact: &'a ContactState,
}

impl ProblemBuilder<'_> {
    /// The discretization of the current assignment.
    fn discretization(&self) -> Discretization<'_> {
        let st = self.state;
        Discretization::new(&st.fabric, &st.layout, &st.assignment)
    }

    /// The stencil sets of the current assignment; `inertia` as in [`StepInputs`].
    fn sets(&self, disc: &Discretization, inertia: Option<(f64, &[f64])>) -> Vec<Box<dyn AnyStencilSet>> {
        let st = self.state;
        let step = StepInputs {
            inertia,
            anchors: &st.anchors,
            friction_limits: &st.friction_limits,
        };
        build_sets(disc, &st.q, self.params, &st.rest, &step)
    }

    /// The Newton problem of a step; `inertia` as in [`StepInputs`], the
    /// tripwire of a relaxation step when `relaxing` (`tripwire`).
    pub fn build(&self, inertia: Option<(f64, &[f64])>, relaxing: bool) -> Result<EolProblem, AssemblyError> {
        let disc = self.discretization();
        let sets = self.sets(&disc, inertia);
        let contact = ContactTerms::new(&disc, &self.state.q, self.params, self.contact);
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
            .then(|| self.state.rest.rest_seg.iter().map(|s| fraction * s).collect())
    }

    /// Where sliding points stop within a step (`slide_stops`).
    fn slide_stops(&self, disc: &Discretization) -> SlideStops {
        self.eil_margins(self.params.assign.stop_fraction)
            .map_or_else(SlideStops::default, |m| SlideStops::new(disc, &m))
    }

    /// The segments whose closing ends a relaxation step (`tripwire`).
    fn tripwire(&self, disc: &Discretization) -> Tripwire {
        self.eil_margins(self.params.assign.close_fraction)
            .map_or_else(Tripwire::default, |m| Tripwire::new(disc, &m))
    }

    /// The Newton problem of these sets, with the thickness contact attached.
    fn problem_of(
        &self,
        sets: Vec<Box<dyn AnyStencilSet>>,
        contact: Option<ContactTerms>,
    ) -> Result<EolProblem, AssemblyError> {
        let (f, l) = (&self.state.fabric, &self.state.layout);
        let free = free_mask(f, l, &self.state.assignment);
        let mut problem = EolProblem::new(l.n_nodes, l.len(), sets, free)?.with_ordering_groups(l.node_of_dof(f));
        if let Some(terms) = contact {
            problem.attach_contact(&self.state.q, terms)?;
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
    pub fn static_residual(&self) -> Result<f64, AssemblyError> {
        let disc = self.discretization();
        let sets = self.sets(&disc, None);
        let st = self.state;
        let g = match ContactTerms::new(&disc, &st.q, self.params, self.contact) {
            Some(terms) => self.problem_of(sets, Some(terms))?.free_gradient(&st.q)?,
            None => gradient(&sets, &st.q, &free_mask(&st.fabric, &st.layout, &st.assignment)),
        };
        Ok(g.iter().fold(0.0f64, |m, v| m.max(v.abs())) / self.params.rod.ks)
    }
}
