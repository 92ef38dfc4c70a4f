//! How steps are taken: the Newton settings, the time step and its bounds,
//! and whether EIL points may be released.
//!
//! A [`Schedule`] is passed to each step (`Simulation::step_with`), so a
//! relaxation runs on its own schedule and a simulation keeps its dynamics
//! schedule for the steps after: nothing is set on the simulation for a
//! run and put back after it.

use super::params::AssignParams;
use crate::solver::newton::NewtonParams;

/// The settings of a sequence of steps, and its adapted time step.
#[derive(Clone, Copy, Debug)]
pub struct Schedule {
    pub newton: NewtonParams,
    /// Current time step (s); a failed step halves it, a step that
    /// converged at once doubles it up to `h_max`.
    pub h: f64,
    /// Below this a failed step is an error (`SimError::StepTooSmall`).
    pub h_min: f64,
    pub h_max: f64,
    /// Keep every EIL point EIL: no EIL-to-EoL release between steps
    /// (`RelaxOptions::keep_eil`).
    pub keep_eil: bool,
    /// Contacts stick: the friction springs have no Coulomb cap, so their
    /// anchors never move and the yarn does not slide through its contacts
    /// beyond the springs' elastic give (`RelaxOptions::sliding`).
    pub stick: bool,
}

impl Schedule {
    /// Steps of `h`, never larger, down to `h * 1e-4`; default Newton settings.
    pub fn new(h: f64) -> Self {
        Schedule {
            newton: NewtonParams::default(),
            h,
            h_min: h * 1e-4,
            h_max: h,
            keep_eil: false,
            stick: false,
        }
    }

    /// The assignment settings of these steps: `base`, with no release
    /// while `keep_eil` (no gap is ever wide enough, so `assign_after`
    /// keeps every EIL point).
    pub fn assign_params(&self, base: AssignParams) -> AssignParams {
        if self.keep_eil {
            AssignParams {
                release_fraction: f64::INFINITY,
                ..base
            }
        } else {
            base
        }
    }
}
