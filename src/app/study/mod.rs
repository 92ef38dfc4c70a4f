//! `knitsim study`: error against run time for the relaxer.
//!
//! The relaxer stops at a static residual `tol`, and a state that passes a
//! loose test can still be far from equilibrium (docs/RELAX.md, "What the
//! default tolerance means"). The study measures how far: it relaxes one
//! pattern at a ladder of tolerances, with every available linear solver,
//! EIL on and off, and compares each final state with a reference relaxed
//! at a tighter tolerance with a larger step cap. Errors are taken over
//! matched material points, the swatch's extents and the potential energy
//! (`error`); each run's wall time, steps, Newton iterations, convergence
//! and final residual are recorded beside them.
//!
//! Outputs (`report`, `plot`): `study.csv`, `study.md` and `study.png`, all
//! rewritten atomically after every run, so a study stopped by Ctrl-C or
//! killed still leaves what it measured. A reference that does not converge
//! is stated at the top of `study.md`: the errors are then against an
//! unconverged state.
//!
//! Wall time covers building the `Simulation` and relaxing it, not the
//! compilation of the pattern or the measurement of the result.

pub mod error;
mod font;
pub mod plot;
pub mod report;
mod setup;

pub use error::{CompareError, Errors, MaterialSamples, Measured};
pub use setup::{load_resized, machine_description, resize_text, StudyConfig, StudyError, DEFAULT_TOLS};

use crate::sim::{relax, RelaxOptions, SimError, SimParams, Simulation};
use crate::solver::linear::{select, software_adapter, AutoParams, LinearSolver, SolverChoice};
use crate::topology::{Fabric, StitchGrid};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// One relaxation of the study and what was measured of it.
#[derive(Clone, Debug)]
pub struct RunRecord {
    pub solver: String,
    pub eil: bool,
    pub tol: f64,
    pub max_steps: usize,
    pub converged: bool,
    pub steps: usize,
    pub newton_iterations: usize,
    pub wall_s: f64,
    pub residual: f64,
    /// Total potential energy of the final state (J).
    pub energy: f64,
    /// Bounding-box extents (x, y, z) of the final state (m).
    pub extents: [f64; 3],
    /// Errors against the reference (`None` for the reference itself and
    /// for a run that failed).
    pub errors: Option<Errors>,
    /// Why the relaxation failed or could not be compared, if it did.
    pub failure: Option<String>,
}

impl RunRecord {
    /// The family label: solver and EIL setting.
    pub fn family(&self) -> String {
        format!("{} {}", self.solver, if self.eil { "eil" } else { "no-eil" })
    }
}

/// Everything the study measured, as the reports write it.
#[derive(Clone, Debug)]
pub struct StudyReport {
    pub pattern: String,
    /// Stitches per row and rows, after `--size`.
    pub size: (usize, usize),
    pub unknowns: usize,
    pub reference: Option<RunRecord>,
    pub runs: Vec<RunRecord>,
    /// Runs planned (reference excluded).
    pub planned: usize,
    /// Solvers left out, with the reason.
    pub skipped_solvers: Vec<String>,
    /// Stopped by the user before the plan was done.
    pub cancelled: bool,
    pub samples: usize,
}

/// Progress after each relaxation: runs done (reference included), the
/// total, and the label of the run that just finished.
pub type OnProgress<'a> = &'a mut dyn FnMut(usize, usize, &str);

/// Solver name as on the command line.
pub fn solver_name(c: SolverChoice) -> &'static str {
    match c {
        SolverChoice::Auto => "auto",
        SolverChoice::CpuDirect => "cpu-direct",
        SolverChoice::CpuCg => "cpu-cg",
        SolverChoice::Gpu => "gpu",
    }
}

/// Runs the study and writes its outputs into `config.out_dir`.
pub fn run_study(
    config: &StudyConfig,
    cancel: Option<&AtomicBool>,
    on_progress: OnProgress,
) -> Result<StudyReport, StudyError> {
    config.validate()?;
    std::fs::create_dir_all(&config.out_dir).map_err(|source| StudyError::OutDir {
        path: config.out_dir.display().to_string(),
        source,
    })?;
    let fabric = load_resized(&config.pattern, config.size, &config.compile)?.0;
    let params = crate::scene::params_for(&fabric, config.scene.as_deref())?;
    let unknowns = crate::sim::discretization::dofs::DofLayout::new(&fabric).len();
    let (solvers, skipped_solvers) = available_solvers(&config.solvers, unknowns);
    // Loosest first, so each family's runs go down the ladder in order.
    let mut tols = config.tols.clone();
    tols.sort_by(|a, b| b.total_cmp(a));
    let plan: Vec<(SolverChoice, bool, f64)> = solvers
        .iter()
        .flat_map(|&s| config.eil.iter().map(move |&e| (s, e)))
        .flat_map(|(s, e)| tols.iter().map(move |&t| (s, e, t)))
        .collect();
    let mut report = StudyReport {
        pattern: fabric.meta.name.clone(),
        size: (fabric.meta.width, fabric.meta.height),
        unknowns,
        reference: None,
        runs: Vec::new(),
        planned: plan.len(),
        skipped_solvers,
        cancelled: false,
        samples: 0,
    };
    let total = plan.len() + 1;
    let cancelled = || cancel.is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed));

    // The reference: cpu-direct, EIL on, the tightest tolerance.
    let ref_tol = config.reference_tol();
    let run = relax_once(
        &fabric,
        &params,
        SolverChoice::CpuDirect,
        true,
        ref_tol,
        config.ref_max_steps,
        cancel,
    )?;
    let Some((ref_record, reference)) = run else {
        report.cancelled = true;
        report::write_all(&config.out_dir, &report, config)?;
        return Ok(report);
    };
    let samples = MaterialSamples::of(&reference.fabric, config.samples_per_segment);
    report.samples = samples.len();
    on_progress(1, total, &format!("reference {}", ref_record.family()));
    report.reference = Some(ref_record);
    report::write_all(&config.out_dir, &report, config)?;

    for (k, &(solver, eil, tol)) in plan.iter().enumerate() {
        if cancelled() {
            report.cancelled = true;
            break;
        }
        let mut record = match relax_once(&fabric, &params, solver, eil, tol, config.max_steps, cancel) {
            Ok(Some((mut record, state))) => {
                match state.errors(&reference, &samples) {
                    Ok(e) => record.errors = Some(e),
                    Err(e) => record.failure = Some(format!("not comparable: {e}")),
                }
                record
            }
            Ok(None) => {
                report.cancelled = true;
                break;
            }
            Err(e) => failed_run(solver, eil, tol, config.max_steps, e),
        };
        record.max_steps = config.max_steps;
        on_progress(k + 2, total, &format!("{} tol {tol:.0e}", record.family()));
        report.runs.push(record);
        report::write_all(&config.out_dir, &report, config)?;
    }
    report::write_all(&config.out_dir, &report, config)?;
    Ok(report)
}

/// The requested solvers that can run here; the others with the reason. A
/// GPU family on a software adapter is skipped: it would not be a GPU.
fn available_solvers(requested: &[SolverChoice], unknowns: usize) -> (Vec<SolverChoice>, Vec<String>) {
    let mut ok = Vec::new();
    let mut skipped = Vec::new();
    for &s in requested {
        match select(s, unknowns, &AutoParams::default()) {
            Ok(sel) => match software_adapter(&sel.solver) {
                Some(adapter) => skipped.push(format!(
                    "{}: the only adapter, {adapter}, is a software one, which would time these CPU cores",
                    solver_name(s)
                )),
                None => ok.push(s),
            },
            Err(e) => skipped.push(format!("{}: {e}", solver_name(s))),
        }
    }
    (ok, skipped)
}

/// The solver for one run; the choice was checked by [`available_solvers`].
fn make_solver(choice: SolverChoice, unknowns: usize) -> Result<LinearSolver, StudyError> {
    select(choice, unknowns, &AutoParams::default())
        .map(|s| s.solver)
        .map_err(|e| StudyError::Solver(e.to_string()))
}

/// One relaxation, timed; `None` when it was cancelled.
fn relax_once(
    fabric: &Fabric,
    params: &SimParams,
    solver: SolverChoice,
    eil: bool,
    tol: f64,
    max_steps: usize,
    cancel: Option<&AtomicBool>,
) -> Result<Option<(RunRecord, Measured)>, StudyError> {
    let mut params = params.clone();
    params.assign.enable_eil = eil;
    let options = RelaxOptions {
        tol,
        max_steps,
        ..RelaxOptions::default()
    };
    let linear = make_solver(solver, crate::sim::discretization::dofs::DofLayout::new(fabric).len())?;
    let start = Instant::now();
    let mut sim = Simulation::new(fabric.clone(), params, linear, options.h_initial);
    let rep = relax(&mut sim, options, cancel, &mut |_, _| {}, &mut |_, _| {})?;
    let wall_s = start.elapsed().as_secs_f64();
    if rep.cancelled {
        return Ok(None);
    }
    let energy = potential_energy(&sim)?;
    let state = Measured::new(sim.snapshot(), energy, &StitchGrid::of(fabric));
    let record = RunRecord {
        solver: solver_name(solver).to_string(),
        eil,
        tol,
        max_steps,
        converged: rep.converged,
        steps: rep.steps,
        newton_iterations: rep.newton_iterations,
        wall_s,
        residual: rep.residual,
        energy,
        extents: state.extents,
        errors: None,
        failure: None,
    };
    Ok(Some((record, state)))
}

/// Total potential energy of the current state: the sum of every term of
/// the static problem (no inertia) under the current discretization.
fn potential_energy(sim: &Simulation) -> Result<f64, SimError> {
    sim.potential_energy()
}

/// The record of a run whose relaxation returned an error.
fn failed_run(solver: SolverChoice, eil: bool, tol: f64, max_steps: usize, e: StudyError) -> RunRecord {
    RunRecord {
        solver: solver_name(solver).to_string(),
        eil,
        tol,
        max_steps,
        converged: false,
        steps: 0,
        newton_iterations: 0,
        wall_s: f64::NAN,
        residual: f64::NAN,
        energy: f64::NAN,
        extents: [f64::NAN; 3],
        errors: None,
        failure: Some(e.to_string()),
    }
}
