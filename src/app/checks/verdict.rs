//! The outcome of a run as the user is told it: converged only when the
//! relaxer's stopping test passed *and* the final state passes the checks
//! of [`super`]; otherwise not converged, with the reason.

use super::{Limits, Rejection, StateChecks};
use crate::sim::RelaxReport;
use std::fmt;

/// How a relaxation ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RunStatus {
    Converged,
    /// Stopped by the user (Ctrl-C) before the stopping test passed.
    Stopped,
    NotConverged(NotConverged),
}

/// Why a run is not converged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NotConverged {
    /// The step cap came first: the residual is still above the tolerance.
    Residual { residual: f64, tol: f64 },
    /// The stopping test passed (or the cap came first) on a state that the
    /// state checks reject.
    State(Rejection),
}

impl fmt::Display for NotConverged {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NotConverged::Residual { residual, tol } => {
                write!(f, "residual {residual:.3e} above tol {tol:.1e} at the step cap")
            }
            NotConverged::State(r) => write!(f, "state rejected: {r}"),
        }
    }
}

impl fmt::Display for RunStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunStatus::Converged => write!(f, "converged"),
            RunStatus::Stopped => write!(f, "stopped by user"),
            RunStatus::NotConverged(why) => write!(f, "NOT converged: {why}"),
        }
    }
}

impl RunStatus {
    /// A rejected state wins over everything but a user's stop, so no
    /// broken state is ever called converged; `contact`: thickness contact
    /// was on (overlaps count only then).
    pub fn of(report: &RelaxReport, tol: f64, checks: &StateChecks, limits: &Limits, contact: bool) -> Self {
        if report.cancelled && !report.converged {
            return RunStatus::Stopped;
        }
        if let Some(r) = checks.rejection(limits, contact) {
            return RunStatus::NotConverged(NotConverged::State(r));
        }
        if report.converged {
            RunStatus::Converged
        } else {
            RunStatus::NotConverged(NotConverged::Residual {
                residual: report.residual,
                tol,
            })
        }
    }

    pub fn is_converged(&self) -> bool {
        matches!(self, RunStatus::Converged)
    }
}
