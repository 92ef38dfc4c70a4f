//! Projected Newton minimisation of `E(q)` over the free coordinates
//! (docs/MODEL.md, "Newton iteration").
//!
//! One iteration: assemble `g` and the (per-stencil PSD-projected) Hessian
//! `H`, solve `H dq = -g`, cap the step at the CCD bound, backtrack on `E`.
//! Design decisions:
//! - **Fixed-size system.** `q` holds every coordinate; the problem cancels
//!   non-free rows (identity, zero gradient). Newton additionally zeroes
//!   `dq` there, so a pinned coordinate cannot drift even under an inexact
//!   CG solve.
//! - **Two stopping tests.** The Newton decrement `dq^T H dq / 2` estimates
//!   the remaining energy decrease, in energy units; the relative residual
//!   `|g_free| / max(|g_0|, floor)` is scale-free and is what the time-step
//!   controller reads. Either one ends the solve.
//! - **Robust fallbacks rather than errors.** If the linear solve fails or
//!   returns a non-descent direction (an LDLT of an indefinite matrix, a CG
//!   stopped on negative curvature), the step falls back to steepest descent
//!   scaled by the curvature along `-g`. If the line search rejects a Newton
//!   direction, steepest descent gets one more try before reporting failure.
//!   A failure is a [`NewtonStatus`], not an error: the adaptive time step
//!   (docs/MODEL.md, "Adaptive step") halves `h` on it.
//! - **Adaptive damping.** Without inertia (quasi-static relaxation) the
//!   projected Hessian is often singular: a compressed spring or a straight
//!   rod has no transverse stiffness after PSD projection, so the Newton step
//!   is huge along those modes and the line search cuts it to nothing.
//!   Levenberg-Marquardt damping `H + mu I` on the free rows bridges Newton
//!   and scaled steepest descent: `mu` grows after a step that needed
//!   backtracking or a gradient fallback and shrinks (to exactly 0) after
//!   full steps, so the final iterations are undamped and converge
//!   quadratically. The decrement test only applies to undamped steps, since
//!   damping shrinks `dq` and would fake convergence.
//! - **Exact Hessian on request** (`NewtonParams::exact_hessian`).
//!   Per-stencil PSD projection makes every direction a descent direction
//!   but changes the curvature of the non-convex terms (bending, contact),
//!   so near a minimum the iteration converges only linearly along the
//!   soft modes (the roll of a stockinette edge). With the exact Hessian
//!   the final iterations are true Newton steps; an iteration whose exact
//!   system gave no descent direction (an indefinite Hessian far from the
//!   minimum) is followed by one projected iteration, and the damping
//!   grows as above until the steps are full again.
//! - **Optional box bounds** ([`Problem::bounds`], `bounds.rs`): trial
//!   points are clamped into a per-iteration box and a coordinate pressed
//!   against its bound is held, so one coordinate at a wall does not cut
//!   every other coordinate's step (a projected Newton step). The
//!   relative-residual and decrement tests see only the coordinates not
//!   held; the caller's force test (`max_force_tol`) sees them all.
//! - **Bounded.** The loop is capped by `max_iterations`; the line search by
//!   its own backtrack count; cancellation is polled between iterations.

use crate::solver::assembly::AssemblyError;
use crate::solver::line_search::LineSearchParams;
use crate::sparse::CsrMatrix;
use std::sync::atomic::AtomicBool;

/// What Newton minimises. `q` always holds every coordinate (see module docs).
pub trait Problem {
    /// `E(q)`; may be `+inf` or NaN where `q` is infeasible (rejected by the line search).
    fn energy(&mut self, q: &[f64]) -> f64;
    /// Fills `g` and the values of `h` (pattern from [`Problem::hessian_pattern`])
    /// with non-free rows cancelled: zero gradient, identity row and column.
    fn gradient_hessian(&mut self, q: &[f64], g: &mut [f64], h: &mut CsrMatrix) -> Result<(), AssemblyError>;
    /// The Hessian sparsity pattern (values ignored); fixed during one solve.
    fn hessian_pattern(&self) -> CsrMatrix;
    /// `free[i]`: coordinate `i` is an unknown.
    fn free(&self) -> &[bool];
    /// Largest fraction of `dq` that is safe to take from `q` (CCD). Default: no cap.
    fn max_step(&mut self, _q: &[f64], _dq: &[f64]) -> f64 {
        1.0
    }
    /// Box bounds for the next iteration from `q` (a projected Newton step,
    /// see `bounds.rs`): writes `lower[i] <= q[i] <= upper[i]` for the
    /// coordinates it bounds (the others arrive as `-inf` / `+inf`) and
    /// returns whether it bounded any (writing nothing when it returns
    /// false). A coordinate whose `q[i]` equals a
    /// bound and whose gradient pushes past it is held for the iteration.
    /// Default: none.
    fn bounds(&self, _q: &[f64], _lower: &mut [f64], _upper: &mut [f64]) -> bool {
        false
    }
    /// Whether the accepted iterate `q` has left the region where this
    /// problem's discretization holds (for a yarn model: a real segment
    /// has closed, `sim::problem::tripwire`). Checked after every accepted step;
    /// `true` ends the solve with [`NewtonStatus::Rediscretize`] so the
    /// caller can rebuild the problem there. Default: never.
    fn must_rediscretize(&self, _q: &[f64]) -> bool {
        false
    }
    /// Whether the problem must be rebuilt at the current iterate before
    /// Newton goes on: a part of it holds only near where it was built (for
    /// a yarn model: the contact candidate list, whose trust radius the last
    /// step reached, `sim::terms::thickness_contact`). Checked after every
    /// iteration that did not end the solve otherwise; `true` ends the solve
    /// with [`NewtonStatus::Rebuild`], and the caller rebuilds and calls
    /// Newton again. Default: never.
    fn must_rebuild(&self) -> bool {
        false
    }
    /// Whether [`Problem::gradient_hessian`] projects each stencil's Hessian
    /// to the nearest PSD matrix (`true`, the default) or assembles the
    /// true Hessian. A problem without projection ignores this.
    fn set_projection(&mut self, _project: bool) {}
    /// Block-Jacobi partition for CG (starts, closed by `n`); empty = scalar Jacobi.
    fn blocks(&self) -> Vec<usize> {
        Vec::new()
    }
    /// The group of each unknown for a direct solver's fill-reducing
    /// ordering (for a yarn model, the node it belongs to); empty = none.
    fn ordering_groups(&self) -> Vec<u32> {
        Vec::new()
    }
}

/// Newton parameters.
#[derive(Clone, Copy, Debug)]
pub struct NewtonParams {
    /// Hard cap on iterations (each one assembles and solves once).
    pub max_iterations: usize,
    /// Stop when the Newton decrement `dq^T H dq / 2` is below this (energy units).
    pub decrement_tol: f64,
    /// Stop when `|g_free| / max(|g_0|, residual_floor)` is below this.
    pub rel_residual_tol: f64,
    /// Floor of the residual normalisation, so a start at equilibrium stops at once.
    pub residual_floor: f64,
    /// Stop when the largest free gradient entry is at most this (force
    /// units); 0 = off. The caller's own equilibrium test, checked at every
    /// iterate instead of only where the solve ends.
    pub max_force_tol: f64,
    /// A direction is "descent" if `-g.dq >= descent_cos * |g| |dq|`.
    pub descent_cos: f64,
    /// Smallest nonzero Levenberg-Marquardt damping, relative to the mean free |H_ii|.
    pub damping_min: f64,
    /// Largest damping, same units.
    pub damping_max: f64,
    /// Damping is multiplied by this after a poor step and divided after a full one.
    pub damping_factor: f64,
    /// Assemble the true Hessian ([`Problem::set_projection`]) and fall
    /// back to the projected one for the next iteration only when it gave
    /// no descent direction (see the module docs).
    pub exact_hessian: bool,
    pub line_search: LineSearchParams,
}

impl Default for NewtonParams {
    fn default() -> Self {
        NewtonParams {
            max_iterations: 100,
            decrement_tol: 1e-12,
            rel_residual_tol: 1e-8,
            residual_floor: 1e-12,
            max_force_tol: 0.0,
            descent_cos: 1e-10,
            damping_min: 1e-6,
            damping_max: 1e6,
            damping_factor: 10.0,
            exact_hessian: false,
            line_search: LineSearchParams::default(),
        }
    }
}

/// Which direction an iteration stepped along.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    Newton,
    /// Steepest descent after a failed or non-descent linear solve.
    Gradient,
    /// No step: the iteration only detected convergence or stopped.
    None,
}

/// One row of the convergence history: the state at the start of the
/// iteration and the step taken from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterStats {
    pub iteration: usize,
    /// Seconds since `minimize` started, at the end of this iteration.
    pub elapsed_s: f64,
    /// `E(q)` at the start of the iteration.
    pub energy: f64,
    /// `|g_free|` at the start of the iteration, over the unknowns not
    /// held at a bound ([`Problem::bounds`]).
    pub residual: f64,
    pub rel_residual: f64,
    /// Largest free gradient entry at the start of the iteration, held
    /// unknowns included (force units): what [`NewtonParams::max_force_tol`]
    /// tests.
    pub max_force: f64,
    /// Newton decrement `dq^T H dq / 2` (0 when no Newton direction was computed).
    pub decrement: f64,
    /// Accepted step length (0 when no step was taken).
    pub step: f64,
    pub direction: Direction,
    /// Damping added to the free diagonal for this solve, relative to the mean free |H_ii|.
    pub damping: f64,
    /// CG iterations of the linear solve (0 for the direct solver).
    pub linear_iterations: usize,
    pub line_search_trials: usize,
    /// Unknowns held at a bound this iteration.
    pub held: usize,
    /// This iteration fell back to the projected Hessian
    /// (`NewtonParams::exact_hessian`).
    pub projected: bool,
    /// Seconds of this iteration in the gradient and Hessian assembly.
    pub assembly_s: f64,
    /// Seconds in the linear solve: the factorization (with a symbolic
    /// analysis when the pattern changed) and its triangular solves, or CG.
    pub solve_s: f64,
    /// Seconds in the line search: the step cap and the trial energies.
    pub line_search_s: f64,
}

/// Why a Newton solve ended successfully.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Converged {
    Decrement,
    Residual,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewtonStatus {
    Converged(Converged),
    MaxIterations,
    Cancelled,
    /// No trial along the Newton or gradient direction decreased `E`.
    LineSearchFailed,
    /// `max_step` allowed no motion at all.
    Blocked,
    /// An accepted step left the problem's discretization
    /// ([`Problem::must_rediscretize`]); `q` is that iterate.
    Rediscretize,
    /// The problem must be rebuilt at `q` before iterating on
    /// ([`Problem::must_rebuild`]).
    Rebuild,
}

#[derive(Clone, Debug)]
pub struct NewtonReport {
    pub status: NewtonStatus,
    /// One entry per iteration, the terminal check included.
    pub history: Vec<IterStats>,
    /// `E` at the returned `q`.
    pub energy: f64,
}

impl NewtonReport {
    pub fn converged(&self) -> bool {
        matches!(self.status, NewtonStatus::Converged(_))
    }

    /// Number of steps actually taken.
    pub fn steps(&self) -> usize {
        self.history.iter().filter(|s| s.step > 0.0).count()
    }
}

#[derive(Debug, thiserror::Error)]
pub enum NewtonError {
    #[error("q has {q} coordinates, the free mask {free}, the Hessian {hessian}")]
    Dimension { q: usize, free: usize, hessian: usize },
    #[error("energy at the starting point is not finite ({0})")]
    NonFiniteStart(f64),
    #[error("gradient is not finite at iteration {0}")]
    NonFiniteGradient(usize),
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
}

/// A callback that sees the coordinates of each accepted iterate.
pub type IterateCallback<'a> = &'a mut dyn FnMut(&[f64]);

/// Per-iteration hooks: a progress callback, a cancellation flag, and the
/// iterates themselves.
#[derive(Default)]
pub struct NewtonHooks<'a> {
    pub on_iteration: Option<&'a mut dyn FnMut(&IterStats)>,
    pub cancel: Option<&'a AtomicBool>,
    /// Called with `q` after every accepted step: the path the solver took,
    /// each piece of it a straight line the line search (and its CCD cap)
    /// checked. For diagnostics and tests that audit the path.
    pub on_accepted: Option<IterateCallback<'a>>,
}

mod bounds;
mod iterate;

pub use iterate::minimize;

#[cfg(test)]
mod tests;
