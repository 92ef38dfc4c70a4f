//! `knitsim relax`: relax a fabric and write every output of the run.
//!
//! Outputs go to one directory: `state.json` (the relaxed fabric, which
//! `knitsim export` and later runs read back), `relaxed.vtk`, `relaxed.obj`
//! (+ `.mtl`), `relaxed.png`, `convergence.csv` with one row per Newton
//! iteration (elapsed seconds, energy, the stopping quantity, gradient
//! norm, step length, EIL count), and `summary.json`: what a knitter and a
//! reviewer read first (measured gauge and finished size, the stopping
//! quantity and its force scale, energy, wall time). Every file is written
//! atomically, so a stopped run never leaves a half-written output.

use super::checks::{check_state, Limits, RunStatus, StateChecks};
use super::summary::Summary;
use crate::io::{
    fit_preview, save_json, write_atomic, write_obj, write_png, write_vtk, IoError, ObjOptions, PngOptions, VtkOptions,
};
use crate::sim::{relax, RelaxOptions, RelaxReport, RemovalCause, SimError, SimParams, Simulation};
use crate::solver::linear::LinearSolver;
use crate::topology::{Fabric, SimInfo, StitchGrid};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

#[derive(Debug, thiserror::Error)]
pub enum RelaxJobError {
    #[error(transparent)]
    Sim(#[from] SimError),
    #[error(transparent)]
    Io(#[from] IoError),
    #[error("cannot create output directory {path}")]
    OutDir { path: String, source: std::io::Error },
}

pub struct RelaxJob {
    pub params: SimParams,
    pub options: RelaxOptions,
    pub solver: LinearSolver,
    pub out_dir: PathBuf,
}

/// One Newton iteration, as written to `convergence.csv`.
#[derive(Clone, Copy, Debug)]
pub struct CsvRow {
    pub elapsed_s: f64,
    pub step: usize,
    pub energy: f64,
    /// The stopping quantity: largest free force over the force scale
    /// (of the step's incremental potential, which in relaxation differs
    /// from the static one only by the weak proximal term).
    pub max_force: f64,
    /// `|g|` of the step's incremental potential (N).
    pub gradient_norm: f64,
    pub step_length: f64,
    pub eil: usize,
}

pub struct RelaxOutcome {
    pub report: RelaxReport,
    pub wall_s: f64,
    pub rows: Vec<CsvRow>,
    pub fabric: Fabric,
    /// Contacts removed because a yarn was pulled out of them (`sim::events::removal`).
    pub slid_off_contacts: usize,
    /// Contacts removed because their yarns pulled apart (`sim::events::separation`).
    pub separated_contacts: usize,
    /// Points whose kind the next re-assignment would change
    /// (`Simulation::pending_kind_changes`).
    pub pending_kind_changes: usize,
    /// What `summary.json` holds.
    pub summary: Summary,
    /// The state checks on the final state (`app::checks`).
    pub checks: StateChecks,
    /// Converged only if the stopping test passed and the checks accept the
    /// state; `report.converged` is cleared when they do not.
    pub status: RunStatus,
}

/// Runs the relaxation and writes all outputs. `on_step(step, residual)`
/// drives a progress display; `cancel` stops cleanly between iterations
/// (the outputs of the state reached so far are still written).
pub fn run_relax(
    fabric: Fabric,
    job: RelaxJob,
    cancel: Option<&AtomicBool>,
    on_step: &mut dyn FnMut(usize, f64),
) -> Result<RelaxOutcome, RelaxJobError> {
    std::fs::create_dir_all(&job.out_dir).map_err(|source| RelaxJobError::OutDir {
        path: job.out_dir.display().to_string(),
        source,
    })?;
    let start = Instant::now();
    let grid = StitchGrid::of(&fabric);
    let mut sim = Simulation::new(fabric, job.params, job.solver, job.options.h_initial);
    let scale = crate::sim::ForceScale::of(sim.fabric(), sim.params()).value;
    let mut rows = Vec::new();
    let step = std::cell::Cell::new(0usize);
    let mut report = {
        let mut on_iter = |s: &crate::solver::newton::IterStats, eil: usize| {
            rows.push(CsvRow {
                elapsed_s: start.elapsed().as_secs_f64(),
                step: step.get(),
                energy: s.energy,
                max_force: s.max_force / scale,
                gradient_norm: s.residual,
                step_length: s.step,
                eil,
            })
        };
        let mut on_accepted = |k: usize, r: f64| {
            step.set(k);
            on_step(k, r);
        };
        relax(&mut sim, job.options, cancel, &mut on_iter, &mut on_accepted)?
    };
    let wall_s = start.elapsed().as_secs_f64();
    let mut out = sim.snapshot();
    let checks = check_state(&out, sim.params(), &Limits::default());
    let status = RunStatus::of(
        &report,
        job.options.tol,
        &checks,
        &Limits::default(),
        sim.params().contact_on(),
    );
    report.converged &= status.is_converged();
    out.sim = Some(SimInfo {
        time: sim.time(),
        newton_iterations: report.newton_iterations,
        residual: report.residual,
    });
    let energy = sim.potential_energy()?;
    let summary = Summary::new(&out, &grid, &report, job.options.tol, energy, wall_s, checks);
    write_outputs(&out, &job.out_dir, &rows)?;
    summary.write(&job.out_dir.join("summary.json"))?;
    let count = |which: fn(&RemovalCause) -> bool| sim.removed().iter().filter(|r| which(&r.cause)).count();
    Ok(RelaxOutcome {
        report,
        wall_s,
        rows,
        fabric: out,
        slid_off_contacts: count(RemovalCause::is_slid_off),
        separated_contacts: count(|c| !c.is_slid_off()),
        pending_kind_changes: sim.pending_kind_changes(),
        summary,
        checks,
        status,
    })
}

fn write_outputs(f: &Fabric, dir: &Path, rows: &[CsvRow]) -> Result<(), IoError> {
    save_json(f, &dir.join("state.json"))?;
    write_vtk(f, &dir.join("relaxed.vtk"), &VtkOptions::default())?;
    write_obj(f, &dir.join("relaxed.obj"), &ObjOptions::default())?;
    write_png(f, &dir.join("relaxed.png"), &fit_preview(f, PngOptions::default()))?;
    write_atomic(&dir.join("convergence.csv"), |w: &mut dyn Write| {
        writeln!(
            w,
            "iteration,step,elapsed_s,energy,max_force_over_scale,gradient_norm,step_length,eil_count"
        )?;
        for (i, r) in rows.iter().enumerate() {
            writeln!(
                w,
                "{},{},{:.6},{:.12e},{:.6e},{:.6e},{:.6e},{}",
                i + 1,
                r.step,
                r.elapsed_s,
                r.energy,
                r.max_force,
                r.gradient_norm,
                r.step_length,
                r.eil
            )?;
        }
        Ok(())
    })
}
