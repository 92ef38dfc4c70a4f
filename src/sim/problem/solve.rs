//! Newton on an [`EolProblem`] with thickness contact: rounds of the generic
//! Newton loop, the contact candidates rebuilt between them.
//!
//! The candidate list of a solve is exact only while no node has moved the
//! trust radius from where it was built (`sim::terms::thickness_contact`).
//! A step that reached it ends the round with [`NewtonStatus::Rebuild`]
//! ([`Problem::must_rebuild`](crate::solver::newton::Problem::must_rebuild));
//! the list is rebuilt there and the next round goes on. Without contact
//! this is one plain call of [`newton::minimize`].

use super::EolProblem;
use crate::solver::linear::LinearSolver;
use crate::solver::newton::{self, IterStats, NewtonError, NewtonHooks, NewtonParams, NewtonReport, NewtonStatus};
use std::sync::atomic::Ordering;

/// Newton on `problem`, rebuilding the contact candidates whenever the
/// trust radius stops a step (module doc). The iteration cap covers all
/// rounds together; the report's history is that of every round.
pub fn minimize(
    problem: &mut EolProblem,
    q: &mut [f64],
    solver: &mut LinearSolver,
    params: &NewtonParams,
    mut hooks: NewtonHooks<'_>,
) -> Result<NewtonReport, NewtonError> {
    if problem.contact.is_none() {
        return newton::minimize(problem, q, solver, params, hooks);
    }
    let mut history = Vec::new();
    let mut gap = f64::INFINITY;
    loop {
        let mut round = *params;
        round.max_iterations = params.max_iterations.saturating_sub(history.len()).max(1);
        let round_hooks = NewtonHooks {
            on_iteration: hooks
                .on_iteration
                .as_mut()
                .map(|cb| &mut **cb as &mut dyn FnMut(&IterStats)),
            cancel: hooks.cancel,
            on_accepted: hooks.on_accepted.as_mut().map(|cb| &mut **cb as &mut dyn FnMut(&[f64])),
        };
        let report = newton::minimize(problem, q, solver, &round, round_hooks)?;
        let cancelled = hooks.cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        let trust_hit = problem.contact.as_ref().is_some_and(|c| c.trust_exceeded());
        history.extend(report.history);
        let more = trust_hit
            && !cancelled
            && matches!(report.status, NewtonStatus::Rebuild | NewtonStatus::Blocked)
            && history.len() < params.max_iterations;
        if !more {
            // A rebuild the iteration cap (or the caller) left undone.
            let status = match report.status {
                NewtonStatus::Rebuild if cancelled => NewtonStatus::Cancelled,
                NewtonStatus::Rebuild => NewtonStatus::MaxIterations,
                other => other,
            };
            return Ok(NewtonReport {
                status,
                history,
                energy: report.energy,
            });
        }
        gap = problem.refresh_contact(q, gap)?;
    }
}
