//! Quasi-static relaxation: the pattern's equilibrium (docs/RELAX.md;
//! docs/MODEL.md, "Incremental potential").
//!
//! A sequence of implicit steps with zero predicted velocity: each step is a
//! proximal Newton solve `min V(q) + 1/(2h^2) |q - q_k|_M^2`, which keeps the
//! first iterations well-posed (the mass term regularises rigid modes and
//! the unbalanced compiled geometry) and becomes plain Newton on `V` as `h`
//! grows: `h` doubles after every step that converged, up to `h_max`.
//! Converged when the static residual, the largest free force over the
//! scene's force scale ([`ForceScale`]: a loop's bending force, or its
//! weight with gravity on), is below `tol`.
//!
//! Three choices make the answer a converged one (docs/RELAX.md, "Sticking
//! contacts", "Exact Hessian", "What the default tolerance means"):
//!
//! - **Contacts stick** (`Schedule::stick`): the friction springs have no
//!   Coulomb cap while relaxing, so the yarn keeps the loop lengths the
//!   compiler gave it and the loops only change shape. With sliding at the
//!   Coulomb limit (`RelaxOptions::sliding`) the relaxation is a slow flow
//!   of yarn through its contacts whose end depends on the path: tighter
//!   tolerances kept drawing the 16 x 16 stockinette in, from 71.5 mm wide
//!   at 100 force scales to 54.1 mm at 0.1, with its EIL count growing to
//!   745 of 2048 points.
//! - **Newton with the exact Hessian** (`NewtonParams::exact_hessian`),
//!   falling back to the projected one only for an iteration whose exact
//!   system has no descent direction: the edge roll of a stockinette is a
//!   soft mode along which projected Newton converges linearly.
//! - **Steps solved, not capped**: `newton_per_step` is a safety bound (a
//!   step that reaches it with a lower energy is accepted and the next one
//!   starts from there), and the default tolerance, 0.01 force scales, is
//!   where a hundred times tighter no longer moves the swatch (1%
//!   in width and height, a tenth of a millimetre out of plane).
//!
//! A step also ends early at the first iterate where a real segment has
//! closed to `assign.close_fraction` (1e-5) of a rest segment
//! (`sim::problem::tripwire`): the next re-assignment makes that point EIL,
//! where iterating on would only stiffen the closed segment's stretch
//! without bound (docs/RELAX.md, "Closed segments"). The equilibrium test
//! also runs at every Newton iterate (`NewtonParams::max_force_tol`), so a
//! step that passes through equilibrium ends there.
//!
//! `RelaxOptions::keep_eil` (opt-in) stops EIL points from being released
//! while relaxing (docs/RELAX.md, "Keeping EIL points").

use super::force_scale::ForceScale;
use super::schedule::Schedule;
use super::stepper::{SimError, Simulation};
use crate::solver::assembly::timing::TermTimes;
use crate::solver::newton::IterStats;
use std::sync::atomic::{AtomicBool, Ordering};

#[derive(Clone, Copy, Debug)]
pub struct RelaxOptions {
    /// Stopping tolerance: the largest free force over the scene's force
    /// scale ([`ForceScale`], docs/RELAX.md, "Stopping test").
    pub tol: f64,
    pub max_steps: usize,
    /// Safety bound on the Newton iterations of one proximal step; a step
    /// that stops there with lower energy is still accepted.
    pub newton_per_step: usize,
    /// First pseudo time step (s).
    pub h_initial: f64,
    /// Largest pseudo time step (s).
    pub h_max: f64,
    /// Newton's relative residual tolerance inside one step; steps need
    /// not be solved tighter than the continuation moves them.
    pub newton_rel_tol: f64,
    /// Keep every EIL point EIL until the relaxation ends: no EIL-to-EoL
    /// re-initialisation between relaxation steps (`Schedule::keep_eil`;
    /// the simulation's own schedule keeps releasing). Opt-in; see the
    /// module docs.
    pub keep_eil: bool,
    /// Let yarn slide through its contacts at the Coulomb limit while
    /// relaxing. Off by default: contacts stick (`Schedule::stick`), see
    /// the module docs.
    pub sliding: bool,
    /// Newton with the exact Hessian and a projected fallback
    /// (`NewtonParams::exact_hessian`); `false`: projected throughout.
    pub exact_hessian: bool,
}

impl Default for RelaxOptions {
    fn default() -> Self {
        RelaxOptions {
            tol: 0.01,
            max_steps: 100,
            newton_per_step: 200,
            h_initial: 0.1,
            h_max: 1e2,
            newton_rel_tol: 1e-6,
            keep_eil: false,
            sliding: false,
            exact_hessian: true,
        }
    }
}

#[derive(Clone, Debug)]
pub struct RelaxReport {
    pub steps: usize,
    pub newton_iterations: usize,
    /// The largest free force over [`RelaxReport::force_scale`]: the
    /// quantity `tol` is tested against.
    pub residual: f64,
    /// The scale forces are measured against (N).
    pub force_scale: ForceScale,
    pub converged: bool,
    pub cancelled: bool,
    pub max_eil: usize,
    /// Steps that ended early at a closed segment (`sim::problem::tripwire`).
    pub closed_segment_steps: usize,
    /// Seconds per stencil set (the active terms) and in the linear solver.
    pub term_seconds: TermTimes,
}

/// Relaxes `sim` in place. `on_iter` sees every Newton iteration with the
/// current EIL count; `on_step` every accepted step with the static
/// residual over the force scale.
///
/// The steps run on a schedule of their own ([`schedule`]), so a caller
/// that goes on to simulate dynamics with the same `Simulation` keeps its
/// own.
pub fn relax(
    sim: &mut Simulation,
    opts: RelaxOptions,
    cancel: Option<&AtomicBool>,
    on_iter: &mut dyn FnMut(&IterStats, usize),
    on_step: &mut dyn FnMut(usize, f64),
) -> Result<RelaxReport, SimError> {
    let mut schedule = schedule(sim, &opts);
    let scale = ForceScale::of(sim.fabric(), sim.params());
    let ks = sim.params().rod.ks;
    let mut rep = RelaxReport {
        steps: 0,
        newton_iterations: 0,
        residual: scale.from_ks_units(sim.static_residual()?, ks),
        force_scale: scale,
        converged: false,
        cancelled: false,
        max_eil: 0,
        closed_segment_steps: 0,
        term_seconds: TermTimes::default(),
    };
    while rep.steps < opts.max_steps {
        if rep.residual <= opts.tol {
            rep.converged = true;
            break;
        }
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            rep.cancelled = true;
            break;
        }
        let s = sim.step_with(&mut schedule, false, cancel, on_iter)?;
        rep.steps += 1;
        rep.newton_iterations += s.newton_iterations;
        rep.max_eil = rep.max_eil.max(s.eil_count);
        rep.closed_segment_steps += usize::from(s.closed_segment);
        rep.term_seconds.merge(&s.times);
        rep.residual = scale.from_ks_units(sim.static_residual()?, ks);
        on_step(rep.steps, rep.residual);
    }
    rep.converged |= rep.residual <= opts.tol;
    Ok(rep)
}

/// The relaxation schedule of `opts` for `sim`: the Newton parameters of
/// `sim`'s own schedule with the relaxation's iteration cap and
/// tolerances, the pseudo time steps and the EIL release rule. [`relax`]
/// steps with it; a diagnostic that calls `Simulation::step_with` itself
/// (`examples/relax_diagnose.rs`) does too, so it follows the same path
/// step for step.
pub fn schedule(sim: &Simulation, opts: &RelaxOptions) -> Schedule {
    let mut s = Schedule {
        newton: sim.schedule().newton,
        ..Schedule::new(opts.h_initial)
    };
    s.newton.max_iterations = opts.newton_per_step;
    s.newton.rel_residual_tol = opts.newton_rel_tol;
    // The equilibrium test, in force units, at every Newton iterate: a step
    // that passes through equilibrium ends there instead of running on to
    // its cap (the static test in [`relax`] then decides, without inertia).
    s.newton.max_force_tol = opts.tol * ForceScale::of(sim.fabric(), sim.params()).value;
    s.h_max = opts.h_max;
    // No gap is ever wide enough: `assign_after` keeps every EIL point.
    s.keep_eil = opts.keep_eil;
    s.stick = !opts.sliding;
    s.newton.exact_hessian = opts.exact_hessian;
    s
}
