//! `knitsim stability`: a whole-solver sweep over stiff and extreme cases,
//! written up as `stability.md` and `stability.csv`.
//!
//! Every case (`cases`) is compiled from pattern text, relaxed through the
//! same `app::run_relax` the `relax` command runs, and judged by the same
//! state checks (`app::checks`), so the report shows what a user of the CLI
//! would get for that input, and whether the run's own verdict
//! ("converged" or not) holds up. Each case runs under `catch_unwind`: a
//! panic becomes a failure row, not the end of the sweep. Each case has a
//! step cap and a wall-time cap (the run is stopped between iterations once
//! the time is up) so the full sweep ends in minutes.
//!
//! A subcommand rather than an example: the suite is a user-facing check of
//! an installed binary (run it on the machine and build that will do the
//! work, with the same output conventions as `relax`), it needs no source
//! checkout or cargo, and the CI test drives the same library entry point,
//! [`run_suite`], so there is one implementation of the sweep.

pub mod cases;
mod report;

use super::checks::{Limits, RunStatus, StateChecks};
use super::relax_job::{run_relax, RelaxJob};
use crate::sim::RelaxOptions;
use crate::solver::linear::LinearSolver;
use cases::{build, Case};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

pub use report::{write_report, StabilityError};

/// Which cases and how large.
#[derive(Clone, Copy, Debug)]
pub struct SuiteOptions {
    /// Only the cases marked quick, on a smaller swatch with fewer steps.
    pub quick: bool,
}

impl SuiteOptions {
    /// Swatch size (stitches each way) and step cap of the ordinary cases.
    pub fn size_and_steps(&self) -> (usize, usize) {
        if self.quick {
            (4, 15)
        } else {
            (8, 30)
        }
    }

    pub fn cases(&self) -> Vec<Case> {
        let (n, steps) = self.size_and_steps();
        let mut all = cases::all(n, steps);
        if self.quick {
            all.retain(|c| c.quick);
            for c in &mut all {
                c.time_cap_s = c.time_cap_s.min(20.0);
            }
        }
        all
    }
}

/// How a case ended.
#[derive(Clone, Debug, PartialEq)]
pub enum CaseOutcome {
    Converged,
    NotConverged(String),
    /// Building or relaxing returned an error.
    Error(String),
    /// The case panicked (a bug to fix at its source).
    Panic(String),
}

impl CaseOutcome {
    pub fn label(&self) -> &'static str {
        match self {
            CaseOutcome::Converged => "converged",
            CaseOutcome::NotConverged(_) => "not converged",
            CaseOutcome::Error(_) => "error",
            CaseOutcome::Panic(_) => "panic",
        }
    }

    pub fn detail(&self) -> &str {
        match self {
            CaseOutcome::Converged => "",
            CaseOutcome::NotConverged(s) | CaseOutcome::Error(s) | CaseOutcome::Panic(s) => s,
        }
    }
}

/// One row of the report.
#[derive(Clone, Debug)]
pub struct CaseRow {
    pub name: String,
    pub contact: bool,
    pub max_steps: usize,
    pub outcome: CaseOutcome,
    pub steps: usize,
    pub newton_iterations: usize,
    /// The relaxer's stopping quantity: largest free force over `ks`.
    pub residual: f64,
    pub max_eil: usize,
    pub checks: StateChecks,
    pub wall_s: f64,
}

impl CaseRow {
    /// The row's final state passes the state checks.
    pub fn checks_pass(&self) -> bool {
        self.checks.rejection(&Limits::default(), self.contact).is_none()
    }
}

/// Runs every case of `opts`, writing each case's relax outputs under
/// `dir/cases/<n>-<name>/`, then the report. `progress` sees each finished
/// row.
pub fn run_suite(
    dir: &Path,
    opts: SuiteOptions,
    progress: &mut dyn FnMut(&CaseRow),
) -> Result<Vec<CaseRow>, StabilityError> {
    std::fs::create_dir_all(dir).map_err(|source| StabilityError::OutDir {
        path: dir.display().to_string(),
        source,
    })?;
    let mut rows = Vec::new();
    for (k, case) in opts.cases().iter().enumerate() {
        let slug: String = case
            .name
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() || c == '.' { c } else { '-' })
            .collect();
        let row = run_case(case, dir.join("cases").join(format!("{:02}-{slug}", k + 1)));
        progress(&row);
        rows.push(row);
    }
    write_report(dir, &opts, &rows)?;
    Ok(rows)
}

/// One case, with panics caught and turned into a row.
pub fn run_case(case: &Case, out_dir: PathBuf) -> CaseRow {
    let start = Instant::now();
    let mut row = CaseRow {
        name: case.name.clone(),
        contact: case.contact,
        max_steps: case.max_steps,
        outcome: CaseOutcome::Error(String::new()),
        steps: 0,
        newton_iterations: 0,
        residual: f64::NAN,
        max_eil: 0,
        checks: StateChecks::default(),
        wall_s: 0.0,
    };
    let result = catch_unwind(AssertUnwindSafe(|| relax_case(case, out_dir, &mut row)));
    row.outcome = match result {
        Ok(Ok(outcome)) => outcome,
        Ok(Err(message)) => CaseOutcome::Error(message),
        Err(payload) => CaseOutcome::Panic(panic_message(payload.as_ref())),
    };
    row.wall_s = start.elapsed().as_secs_f64();
    row
}

fn relax_case(case: &Case, out_dir: PathBuf, row: &mut CaseRow) -> Result<CaseOutcome, String> {
    let (fabric, params) = build(case)?;
    let job = RelaxJob {
        params,
        options: RelaxOptions {
            max_steps: case.max_steps,
            ..RelaxOptions::default()
        },
        solver: LinearSolver::direct(),
        out_dir,
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let done = Arc::new(AtomicBool::new(false));
    let watchdog = {
        let (cancel, done) = (cancel.clone(), done.clone());
        let cap = Duration::from_secs_f64(case.time_cap_s);
        std::thread::spawn(move || {
            let start = Instant::now();
            while !done.load(Ordering::Relaxed) {
                if start.elapsed() >= cap {
                    cancel.store(true, Ordering::Relaxed);
                    return;
                }
                std::thread::sleep(Duration::from_millis(50));
            }
        })
    };
    let result = run_relax(fabric, job, Some(&cancel), &mut |_, _| {});
    done.store(true, Ordering::Relaxed);
    let _ = watchdog.join();
    let o = result.map_err(|e| format!("{e}"))?;
    row.steps = o.report.steps;
    row.newton_iterations = o.report.newton_iterations;
    row.residual = o.report.residual;
    row.max_eil = o.report.max_eil;
    row.checks = o.checks;
    Ok(match o.status {
        RunStatus::Converged => CaseOutcome::Converged,
        RunStatus::Stopped => {
            let mut why = format!(
                "time cap {:.0} s reached after {} steps (residual {:.3e})",
                case.time_cap_s, o.report.steps, o.report.residual
            );
            if let Some(r) = o.checks.rejection(&Limits::default(), case.contact) {
                why += &format!("; state rejected: {r}");
            }
            CaseOutcome::NotConverged(why)
        }
        RunStatus::NotConverged(why) => CaseOutcome::NotConverged(why.to_string()),
    })
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "panic without a message".into())
}
