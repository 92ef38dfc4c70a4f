//! `knitsim drape`: relax a fabric, then simulate it under gravity with its
//! scene's obstacles, pins and motions until it comes to rest, writing
//! frames as it goes.
//!
//! Outputs, in one directory, each written atomically:
//! - `frames/frame_NNNN.vtu` at the scene's frame rate (frame 0 is the
//!   start) and `drape.pvd`, the collection ParaView opens as an animation,
//!   rewritten after every frame, so a run stopped with Ctrl-C keeps a
//!   playable animation of the frames written so far;
//! - the final state as `state.json`, `draped.vtk`, `draped.obj` (+ `.mtl`)
//!   and `draped.png`, and the obstacles as `obstacles.vtu` and
//!   `obstacles.obj`;
//! - `energy.csv`, one row per time step: time, step, kinetic and
//!   potential energy, Newton iterations, retries, the stopping quantity
//!   (largest node speed), wall seconds;
//! - `summary.json` (`outputs::DrapeSummary`).
//!
//! A run that fails (a step that does not converge even at the smallest
//! time step) keeps its frames and `energy.csv` and reports the error.
//!
//! With no scene the embedded default applies (`scene`): the pattern is
//! relaxed first with the default `RelaxOptions`, then dropped onto a
//! sphere, with friction and air drag.

pub mod layers;
pub mod outputs;
pub mod scene;

use crate::app::summary::extents;
use crate::io::{save_json, write_pvd, write_vtu, IoError, PvdEntry};
use crate::sim::dynamics::pins::{resolve_pins, PinError};
use crate::sim::dynamics::{dynamic_params, pin_nodes, run_dynamics, DynamicsReport, StepRow};
use crate::sim::{relax, RelaxOptions, RelaxReport, SimError, SimParams, Simulation};
use crate::solver::linear::{select, AutoParams, SelectError, SolverChoice};
use crate::topology::Fabric;
use outputs::{min_clearance, write_final, DrapeSummary};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

#[derive(Debug, thiserror::Error)]
pub enum DrapeError {
    #[error(transparent)]
    Sim(#[from] SimError),
    #[error(transparent)]
    Io(#[from] IoError),
    #[error(transparent)]
    Pins(#[from] PinError),
    #[error(transparent)]
    Solver(#[from] SelectError),
    #[error("motions[{index}] moves pin set {pins}, but the scene has {count} pin sets")]
    Motion { index: usize, pins: usize, count: usize },
    #[error(transparent)]
    Layers(#[from] layers::LayersError),
    #[error("cannot create output directory {path}")]
    OutDir { path: String, source: std::io::Error },
}

/// What to drape and how.
pub struct DrapeJob {
    /// The parameters, `dynamics` included.
    pub params: SimParams,
    /// Put the default scene's sphere under the relaxed fabric (no scene
    /// file given).
    pub default_scene: bool,
    /// Relax first with these options (`None`: drape the input as it is).
    pub relax: Option<RelaxOptions>,
    pub solver: SolverChoice,
    pub out_dir: PathBuf,
}

/// What a drape run did.
pub struct DrapeOutcome {
    pub relax: Option<RelaxReport>,
    pub dynamics: DynamicsReport,
    pub rows: Vec<StepRow>,
    pub frames: usize,
    pub summary: DrapeSummary,
    pub fabric: Fabric,
    /// The linear solver's note (which one `auto` picked).
    pub solver_note: String,
}

/// Progress of a run: relaxing (step, residual) or draping (a step).
pub enum Progress<'a> {
    Relax(usize, f64),
    Drape(&'a StepRow),
}

/// Runs the job on `fabric` (as compiled or loaded) and writes every
/// output. `cancel` stops between Newton iterations; the frames written so
/// far, and the state reached, are kept.
pub fn run_drape(
    fabric: Fabric,
    job: DrapeJob,
    cancel: Option<&AtomicBool>,
    on_progress: &mut dyn FnMut(Progress),
) -> Result<DrapeOutcome, DrapeError> {
    let out = job.out_dir.clone();
    let frames_dir = out.join("frames");
    std::fs::create_dir_all(&frames_dir).map_err(|source| DrapeError::OutDir {
        path: frames_dir.display().to_string(),
        source,
    })?;
    let start = Instant::now();
    let n_dofs = crate::sim::discretization::dofs::DofLayout::new(&fabric).len();
    let solver = || select(job.solver, n_dofs, &AutoParams::default());
    let selection = solver()?;
    let solver_note = selection.note.clone();
    let compiled = fabric.clone();
    // Relax without the scene's obstacles, dynamics terms or gravity.
    let (fabric, relax_report) = match job.relax {
        Some(opts) => {
            let mut rp = job.params.clone();
            rp.obstacles.clear();
            rp.dynamics = Default::default();
            let mut sim = Simulation::new(fabric, rp, selection.solver, opts.h_initial);
            let rep = relax(&mut sim, opts, cancel, &mut |_, _| {}, &mut |k, r| {
                on_progress(Progress::Relax(k, r))
            })?;
            (sim.snapshot(), Some(rep))
        }
        None => (fabric, None),
    };
    let relax_wall_s = start.elapsed().as_secs_f64();
    let mut params = job.params.clone();
    if job.default_scene {
        params = scene::with_default_scene(params, &fabric);
    }
    let d = &params.dynamics;
    if let Some((index, m)) = d.motions.iter().enumerate().find(|(_, m)| m.pins >= d.pins.len()) {
        return Err(DrapeError::Motion {
            index,
            pins: m.pins,
            count: d.pins.len(),
        });
    }
    let pin_sets = resolve_pins(&compiled, &d.pins)?;
    // Layers: copies of the relaxed fabric; pins select nodes of the first.
    let (mut fabric, pin_sets, mut layer_summary) = match params.layers.as_ref().filter(|l| !l.patches.is_empty()) {
        Some(lp) => {
            let l = layers::build_layers(&fabric, lp)?;
            let pins: Vec<Vec<usize>> = pin_sets
                .iter()
                .map(|set| set.iter().map(|&n| l.node_maps[0][n]).collect())
                .collect();
            let summary = outputs::LayerSummary {
                patches: lp.patches.len(),
                layer_contacts: l.layer_contacts,
                seam_contacts: l.seam_contacts,
                ..Default::default()
            };
            (l.fabric, pins, Some(summary))
        }
        None => (fabric, pin_sets, None),
    };
    pin_nodes(&mut fabric, &pin_sets);
    let flat = extents(&compiled);
    let params = dynamic_params(params);
    let dt = params.dynamics.dt;
    let frame_interval = 1.0 / params.dynamics.frame_rate;
    let mut sim = Simulation::new(fabric, params, solver()?.solver, dt);

    let mut entries: Vec<PvdEntry> = Vec::new();
    let write_frame = |sim: &Simulation, entries: &mut Vec<PvdEntry>| -> Result<(), IoError> {
        let name = format!("frame_{:04}.vtu", entries.len());
        write_vtu(&sim.snapshot(), &frames_dir.join(&name))?;
        entries.push(PvdEntry {
            time: sim.time(),
            file: format!("frames/{name}"),
        });
        write_pvd(entries, &out.join("drape.pvd"))
    };
    let t0 = sim.time();
    write_frame(&sim, &mut entries)?;
    let mut clearance = min_clearance(&sim);
    let mut rows: Vec<StepRow> = Vec::new();
    let mut io_error: Option<IoError> = None;
    let mut next_frame = 1usize;
    let report = run_dynamics(&mut sim, &pin_sets, cancel, &mut |sim, row| {
        rows.push(*row);
        clearance = clearance.min(min_clearance(sim));
        on_progress(Progress::Drape(row));
        if row.time + 1e-9 * frame_interval >= next_frame as f64 * frame_interval {
            while row.time + 1e-9 * frame_interval >= next_frame as f64 * frame_interval {
                next_frame += 1;
            }
            if let Err(e) = write_frame(sim, &mut entries) {
                io_error = Some(e);
                return false;
            }
        }
        true
    });
    let report = match report {
        Ok(r) => r,
        Err(e) => {
            // The steps taken so far are still worth a look.
            let _ = outputs::write_energy_csv(&rows, &out.join("energy.csv"));
            return Err(e.into());
        }
    };
    if let Some(e) = io_error {
        return Err(e.into());
    }
    // The last state is always a frame.
    if entries.last().is_some_and(|e| e.time < sim.time()) {
        write_frame(&sim, &mut entries)?;
    }
    let wall_s = start.elapsed().as_secs_f64();
    let fabric = sim.snapshot();
    save_json(&fabric, &out.join("state.json"))?;
    if let Some(l) = layer_summary.as_mut() {
        l.removed_slid_off = sim.removed().iter().filter(|r| r.cause.is_slid_off()).count();
        l.removed_pulling = sim.removed().len() - l.removed_slid_off;
    }
    let mut summary = DrapeSummary::new(
        &sim,
        &fabric,
        flat,
        &report,
        relax_report.as_ref(),
        (relax_wall_s, wall_s),
        entries.len(),
        clearance,
        sim.time() - t0,
    )?;
    summary.layers = layer_summary;
    write_final(&sim, &fabric, &out, &rows, &summary)?;
    Ok(DrapeOutcome {
        relax: relax_report,
        dynamics: report,
        rows,
        frames: entries.len(),
        summary,
        fabric,
        solver_note,
    })
}
