//! The Newton loop itself; types and the design rationale are in the parent module.

use super::bounds::Bounds;
use super::{
    Converged, Direction, IterStats, NewtonError, NewtonHooks, NewtonParams, NewtonReport, NewtonStatus, Problem,
};
use crate::solver::line_search::{backtracking_armijo, LineSearchStep};
use crate::solver::linear::LinearSolver;
use crate::sparse::{dot, CsrMatrix};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// `v^T H v`.
fn curvature(h: &CsrMatrix, v: &[f64], scratch: &mut [f64]) -> f64 {
    h.mul_vec(v, scratch);
    dot(v, scratch)
}

/// Scratch vectors reused across iterations.
struct Work {
    g: Vec<f64>,
    dq: Vec<f64>,
    rhs: Vec<f64>,
    hv: Vec<f64>,
    trial: Vec<f64>,
    bounds: Bounds,
}

/// Minimises `problem.energy` from `q` (updated in place) over the free coordinates.
pub fn minimize<P: Problem + ?Sized>(
    problem: &mut P,
    q: &mut [f64],
    solver: &mut LinearSolver,
    params: &NewtonParams,
    mut hooks: NewtonHooks<'_>,
) -> Result<NewtonReport, NewtonError> {
    let start = Instant::now();
    let mut h = problem.hessian_pattern();
    let free = problem.free().to_vec();
    let n = q.len();
    if free.len() != n || h.n != n {
        return Err(NewtonError::Dimension {
            q: n,
            free: free.len(),
            hessian: h.n,
        });
    }
    let blocks = problem.blocks();
    solver.set_ordering_groups(&problem.ordering_groups());
    let mut energy = problem.energy(q);
    if !energy.is_finite() {
        return Err(NewtonError::NonFiniteStart(energy));
    }
    let mut w = Work {
        g: vec![0.0; n],
        dq: vec![0.0; n],
        rhs: vec![0.0; n],
        hv: vec![0.0; n],
        trial: vec![0.0; n],
        bounds: Bounds::new(n),
    };
    let diag_slots: Vec<Option<usize>> = (0..n).map(|r| if free[r] { h.find(r, r) } else { None }).collect();
    let mut damping = 0.0;
    let mut history = Vec::new();
    let mut g0 = None;
    let mut status = NewtonStatus::MaxIterations;

    for iteration in 0..params.max_iterations {
        if hooks.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            status = NewtonStatus::Cancelled;
            break;
        }
        let assembly_start = Instant::now();
        problem.set_projection(!params.exact_hessian);
        assemble_free(problem, q, &free, &mut w.g, &mut h)?;
        let assembly_s = assembly_start.elapsed().as_secs_f64();
        let full_sq = dot(&w.g, &w.g);
        if !full_sq.is_finite() {
            return Err(NewtonError::NonFiniteGradient(iteration));
        }
        // The caller's equilibrium test reads every free force, held or not.
        let max_force = w.g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if w.bounds.active {
            // Only a problem that bounded something wrote into the box.
            w.bounds.lower.fill(f64::NEG_INFINITY);
            w.bounds.upper.fill(f64::INFINITY);
        }
        w.bounds.active = problem.bounds(q, &mut w.bounds.lower, &mut w.bounds.upper);
        w.bounds.hold(q, &free, &mut w.g, &mut h);
        let residual = if w.bounds.held.is_empty() {
            full_sq.sqrt()
        } else {
            dot(&w.g, &w.g).sqrt()
        };
        let g0 = *g0.get_or_insert(residual);
        let rel_residual = residual / g0.max(params.residual_floor);
        let mut stats = IterStats {
            iteration,
            elapsed_s: 0.0,
            energy,
            residual,
            rel_residual,
            max_force,
            decrement: 0.0,
            step: 0.0,
            direction: Direction::None,
            damping,
            linear_iterations: 0,
            line_search_trials: 0,
            held: w.bounds.held.len(),
            projected: false,
            assembly_s,
            solve_s: 0.0,
            line_search_s: 0.0,
        };
        let outcome = if rel_residual < params.rel_residual_tol || max_force <= params.max_force_tol {
            Some(NewtonStatus::Converged(Converged::Residual))
        } else {
            add_damping(&mut h, &diag_slots, damping);
            let exact = params.exact_hessian;
            solver.set_definite_only(exact);
            let mut outcome = step(
                problem,
                q,
                solver,
                params,
                &blocks,
                &free,
                &h,
                &mut w,
                &mut energy,
                &mut stats,
                !exact,
            );
            if exact && outcome.is_none() && stats.direction == Direction::None {
                // The true Hessian gave no descent step: this iteration
                // again with the projected one (module docs).
                let reassembly = Instant::now();
                problem.set_projection(true);
                assemble_free(problem, q, &free, &mut w.g, &mut h)?;
                w.bounds.hold(q, &free, &mut w.g, &mut h);
                add_damping(&mut h, &diag_slots, damping);
                stats.assembly_s += reassembly.elapsed().as_secs_f64();
                stats.projected = true;
                solver.set_definite_only(false);
                outcome = step(
                    problem,
                    q,
                    solver,
                    params,
                    &blocks,
                    &free,
                    &h,
                    &mut w,
                    &mut energy,
                    &mut stats,
                    true,
                );
            }
            damping = next_damping(damping, &stats, params);
            match outcome {
                None if stats.step > 0.0 && problem.must_rediscretize(q) => Some(NewtonStatus::Rediscretize),
                None if problem.must_rebuild() => Some(NewtonStatus::Rebuild),
                other => other,
            }
        };
        if stats.step > 0.0 {
            if let Some(cb) = hooks.on_accepted.as_mut() {
                cb(q);
            }
        }
        stats.elapsed_s = start.elapsed().as_secs_f64();
        if let Some(cb) = hooks.on_iteration.as_mut() {
            cb(&stats);
        }
        history.push(stats);
        if let Some(s) = outcome {
            status = s;
            break;
        }
    }
    Ok(NewtonReport {
        status,
        history,
        energy,
    })
}

/// The gradient and Hessian at `q`, the gradient zeroed on the coordinates
/// that are not free.
fn assemble_free<P: Problem + ?Sized>(
    problem: &mut P,
    q: &[f64],
    free: &[bool],
    g: &mut [f64],
    h: &mut CsrMatrix,
) -> Result<(), NewtonError> {
    problem.gradient_hessian(q, g, h)?;
    for (gi, _) in g.iter_mut().zip(free).filter(|(_, &f)| !f) {
        *gi = 0.0;
    }
    Ok(())
}

/// Adds `rel * mean(|H_ii|)` to the free diagonal entries.
fn add_damping(h: &mut CsrMatrix, diag_slots: &[Option<usize>], rel: f64) {
    if rel <= 0.0 {
        return;
    }
    let (sum, count) = diag_slots
        .iter()
        .flatten()
        .fold((0.0, 0usize), |(s, c), &k| (s + h.values[k].abs(), c + 1));
    let mu = rel * (sum / count.max(1) as f64).max(f64::MIN_POSITIVE);
    for &k in diag_slots.iter().flatten() {
        h.values[k] += mu;
    }
}

/// Grows the damping after a poor step, shrinks it (to 0) after a full one.
fn next_damping(current: f64, stats: &IterStats, p: &NewtonParams) -> f64 {
    let full_step = stats.direction == Direction::Newton && stats.line_search_trials == 1;
    if full_step {
        let d = current / p.damping_factor;
        if d < p.damping_min {
            0.0
        } else {
            d
        }
    } else if current == 0.0 {
        p.damping_min
    } else {
        (current * p.damping_factor).min(p.damping_max)
    }
}

/// Computes a direction and takes one line-searched step. Returns a status
/// when the solve must end here.
#[allow(clippy::too_many_arguments)]
fn step<P: Problem + ?Sized>(
    problem: &mut P,
    q: &mut [f64],
    solver: &mut LinearSolver,
    params: &NewtonParams,
    blocks: &[usize],
    free: &[bool],
    h: &CsrMatrix,
    w: &mut Work,
    energy: &mut f64,
    stats: &mut IterStats,
    gradient_fallback: bool,
) -> Option<NewtonStatus> {
    for (r, gi) in w.rhs.iter_mut().zip(&w.g) {
        *r = -gi;
    }
    w.dq.fill(0.0);
    let solve_start = Instant::now();
    let solved = solver.solve(h, &w.rhs, &mut w.dq, blocks);
    stats.solve_s = solve_start.elapsed().as_secs_f64();
    if let Ok(rep) = &solved {
        stats.linear_iterations = rep.iterations;
    }
    for (d, _) in w.dq.iter_mut().zip(free).filter(|(_, &f)| !f) {
        *d = 0.0;
    }
    let gnorm = stats.residual;
    let slope = dot(&w.g, &w.dq);
    let dq_norm = dot(&w.dq, &w.dq).sqrt();
    let solved_definite = solved.as_ref().is_ok_and(|r| gradient_fallback || r.converged);
    let is_descent =
        solved_definite && slope.is_finite() && -slope >= params.descent_cos * gnorm * dq_norm && slope < 0.0;
    if is_descent {
        let decrement = 0.5 * curvature(h, &w.dq, &mut w.hv);
        stats.decrement = if decrement.is_finite() && decrement > 0.0 {
            decrement
        } else {
            -0.5 * slope
        };
        // Converged, but the step is already paid for: take it if the line
        // search accepts it, which squares the remaining error for free.
        let done = (stats.damping == 0.0 && stats.decrement < params.decrement_tol)
            .then_some(NewtonStatus::Converged(Converged::Decrement));
        match line_search(problem, q, params, w, *energy, slope, stats) {
            LineOutcome::Accepted(s) => {
                accept(q, w, energy, stats, s, Direction::Newton);
                return done;
            }
            _ if done.is_some() => return done,
            LineOutcome::Blocked => return Some(NewtonStatus::Blocked),
            LineOutcome::Rejected => {}
        }
    }
    if !gradient_fallback {
        // The caller retries with another Hessian.
        stats.direction = Direction::None;
        return None;
    }
    // Steepest descent, scaled to the minimiser of the quadratic model along -g.
    let ghg = curvature(h, &w.g, &mut w.hv);
    let scale = if ghg.is_finite() && ghg > 0.0 {
        gnorm * gnorm / ghg
    } else {
        1.0
    };
    for (d, gi) in w.dq.iter_mut().zip(&w.g) {
        *d = -scale * gi;
    }
    let slope = -scale * gnorm * gnorm;
    match line_search(problem, q, params, w, *energy, slope, stats) {
        LineOutcome::Accepted(s) => {
            accept(q, w, energy, stats, s, Direction::Gradient);
            None
        }
        LineOutcome::Blocked => Some(NewtonStatus::Blocked),
        LineOutcome::Rejected => Some(NewtonStatus::LineSearchFailed),
    }
}

enum LineOutcome {
    Accepted(LineSearchStep),
    Blocked,
    Rejected,
}

/// [`search_line`], its seconds added to `stats.line_search_s`.
fn line_search<P: Problem + ?Sized>(
    problem: &mut P,
    q: &[f64],
    params: &NewtonParams,
    w: &mut Work,
    e0: f64,
    slope: f64,
    stats: &mut IterStats,
) -> LineOutcome {
    let start = Instant::now();
    let outcome = search_line(problem, q, params, w, e0, slope);
    stats.line_search_s += start.elapsed().as_secs_f64();
    outcome
}

fn search_line<P: Problem + ?Sized>(
    problem: &mut P,
    q: &[f64],
    params: &NewtonParams,
    w: &mut Work,
    e0: f64,
    slope: f64,
) -> LineOutcome {
    let cap = problem.max_step(q, &w.dq);
    if cap.is_nan() || cap <= 0.0 {
        return LineOutcome::Blocked;
    }
    let alpha0 = cap.min(1.0);
    let (dq, trial, bounds) = (&w.dq, &mut w.trial, &w.bounds);
    let energy_at = |alpha: f64| {
        for ((t, qi), di) in trial.iter_mut().zip(q).zip(dq) {
            *t = qi + alpha * di;
        }
        bounds.project(trial);
        problem.energy(trial)
    };
    match backtracking_armijo(energy_at, e0, slope, alpha0, &params.line_search) {
        Some(s) => LineOutcome::Accepted(s),
        None => LineOutcome::Rejected,
    }
}

fn accept(q: &mut [f64], w: &Work, energy: &mut f64, stats: &mut IterStats, s: LineSearchStep, direction: Direction) {
    for (qi, di) in q.iter_mut().zip(&w.dq) {
        *qi += s.alpha * di;
    }
    w.bounds.project(q);
    *energy = s.energy;
    stats.step = s.alpha;
    stats.direction = direction;
    stats.line_search_trials += s.trials;
}
