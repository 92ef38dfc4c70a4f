//! What `knitsim drape` writes at the end of a run: the final state as VTK,
//! OBJ (+ MTL) and PNG, the obstacles as meshes, `energy.csv` and
//! `summary.json`; and the obstacle clearance it reports.

use super::scene::obstacle_triangles;
use crate::app::checks::{check_state, Limits, StateChecks};
use crate::app::summary::extents;
use crate::io::{
    fit_preview, write_atomic, write_obj, write_png, write_triangles_vtu, write_vtk, IoError, ObjOptions, PngOptions,
    VtkOptions,
};
use crate::rod::obstacle::Shape;
use crate::sim::dynamics::{centre_of_mass, kinetic_energy, DynamicsReport, StepRow};
use crate::sim::{DynamicsParams, RelaxReport, SimError, Simulation};
use crate::solver::assembly::timing::TermTimes;
use crate::topology::Fabric;
use nalgebra::Vector3;
use serde::Serialize;
use std::io::Write;
use std::path::Path;

/// The smallest signed distance of a node to an obstacle, over all nodes
/// and obstacles, in units of that node's clearance (its yarn radius):
/// 1 is touching, below 0 is inside. `f64::INFINITY` without obstacles.
pub fn min_clearance(sim: &Simulation) -> f64 {
    let p = sim.params();
    if p.obstacles.is_empty() {
        return f64::INFINITY;
    }
    let st = sim.state();
    let radii = p.yarn_radii(&st.fabric);
    let mut node_r = vec![0.0f64; st.fabric.nodes.len()];
    for (y, yarn) in st.fabric.yarns.iter().enumerate() {
        for pt in &yarn.points {
            node_r[pt.node] = node_r[pt.node].max(radii[y]);
        }
    }
    let snapshot = sim.snapshot();
    let mut m = f64::INFINITY;
    for (n, node) in snapshot.nodes.iter().enumerate() {
        if node_r[n] <= 0.0 {
            continue;
        }
        let x = Vector3::new(node.x.x, node.x.y, node.x.z);
        for s in &p.obstacles {
            m = m.min(s.sdf(&x).0 / node_r[n]);
        }
    }
    m
}

/// `summary.json` of a drape run.
#[derive(Clone, Debug, Serialize)]
pub struct DrapeSummary {
    pub pattern: String,
    pub nodes: usize,
    pub unknowns: usize,
    /// Came to rest (the rest test passed).
    pub at_rest: bool,
    pub cancelled: bool,
    /// Simulated time (s).
    pub time: f64,
    pub steps: usize,
    pub newton_iterations: usize,
    /// Newton's force tolerance of each step (N).
    pub newton_force_tol: f64,
    pub max_eil: usize,
    pub frames: usize,
    /// Kinetic and potential energy of the final state (J).
    pub kinetic_energy: f64,
    pub potential_energy: f64,
    /// The stopping quantity at the end: largest node speed (m/s).
    pub final_max_speed: f64,
    /// Bounding box of the input as compiled or loaded (mm).
    pub flat_size_mm: [f64; 3],
    /// Bounding box of the final state (mm).
    pub final_size_mm: [f64; 3],
    /// Centre of mass of the final state (m).
    pub centre_of_mass: [f64; 3],
    /// Smallest node-to-obstacle distance over every step, in yarn radii
    /// (see [`min_clearance`]).
    pub min_obstacle_clearance: f64,
    pub obstacles: Vec<Shape>,
    pub dynamics: DynamicsParams,
    /// Relaxation before the drape: steps, and whether it passed its test.
    pub relax_steps: Option<usize>,
    pub relax_converged: Option<bool>,
    pub relax_wall_s: f64,
    /// Wall time of the whole run, relaxation included (s).
    pub wall_s: f64,
    /// Seconds of the dynamic steps per stencil set (the active terms) and
    /// in the linear solver.
    pub term_seconds: TermTimes,
    /// The independent checks of the final state (`app::checks`, as for
    /// `relax`): NaN or infinite coordinates, crossing segment pairs,
    /// largest axial strain.
    pub checks: StateChecks,
    /// The scene's layers, if it has any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layers: Option<LayerSummary>,
}

/// What a layered scene built, and which of its contacts went.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LayerSummary {
    pub patches: usize,
    /// Layer contacts found at the start, and seam contacts sewn.
    pub layer_contacts: usize,
    pub seam_contacts: usize,
    /// Contacts removed because their `u` left a yarn, and because their
    /// normal force pulled the yarns together (the sign test).
    pub removed_slid_off: usize,
    pub removed_pulling: usize,
}

impl DrapeSummary {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        sim: &Simulation,
        fabric: &Fabric,
        flat: [f64; 3],
        report: &DynamicsReport,
        relax: Option<&RelaxReport>,
        (relax_wall_s, wall_s): (f64, f64),
        frames: usize,
        clearance: f64,
        time: f64,
    ) -> Result<Self, SimError> {
        let mm = |e: [f64; 3]| e.map(|v| v * 1e3);
        Ok(DrapeSummary {
            pattern: fabric.meta.name.clone(),
            nodes: fabric.nodes.len(),
            unknowns: sim.layout().len(),
            at_rest: report.at_rest,
            cancelled: report.cancelled,
            time,
            steps: report.steps,
            newton_iterations: report.newton_iterations,
            newton_force_tol: report.newton_force_tol,
            max_eil: report.max_eil,
            frames,
            kinetic_energy: kinetic_energy(sim),
            potential_energy: sim.potential_energy()?,
            final_max_speed: crate::sim::dynamics::max_speed(sim),
            flat_size_mm: mm(flat),
            final_size_mm: mm(extents(fabric)),
            centre_of_mass: centre_of_mass(sim),
            min_obstacle_clearance: clearance,
            obstacles: sim.params().obstacles.clone(),
            dynamics: sim.params().dynamics.clone(),
            relax_steps: relax.map(|r| r.steps),
            relax_converged: relax.map(|r| r.converged),
            relax_wall_s,
            wall_s,
            term_seconds: report.term_seconds.clone(),
            checks: check_state(fabric, sim.params(), &Limits::default()),
            layers: None,
        })
    }
}

/// Writes the final state's files, the obstacles, `energy.csv` and
/// `summary.json` to `dir`.
pub fn write_final(
    sim: &Simulation,
    fabric: &Fabric,
    dir: &Path,
    rows: &[StepRow],
    summary: &DrapeSummary,
) -> Result<(), IoError> {
    write_vtk(fabric, &dir.join("draped.vtk"), &VtkOptions::default())?;
    write_obj(fabric, &dir.join("draped.obj"), &ObjOptions::default())?;
    write_png(
        fabric,
        &dir.join("draped.png"),
        &fit_preview(fabric, PngOptions::default()),
    )?;
    let obstacles = &sim.params().obstacles;
    if !obstacles.is_empty() {
        let ext = extents(fabric);
        let c = summary.centre_of_mass;
        let t = obstacle_triangles(obstacles, c, ext[0].max(ext[1]).max(ext[2]));
        write_triangles_vtu(&t.points, &t.triangles, &t.ids, &dir.join("obstacles.vtu"))?;
        write_atomic(&dir.join("obstacles.obj"), |w: &mut dyn Write| {
            writeln!(w, "# knitsim obstacles")?;
            for p in &t.points {
                writeln!(w, "v {:e} {:e} {:e}", p[0], p[1], p[2])?;
            }
            let mut current = usize::MAX;
            for (tri, id) in t.triangles.iter().zip(&t.ids) {
                if *id != current {
                    writeln!(w, "o obstacle_{id}")?;
                    current = *id;
                }
                writeln!(w, "f {} {} {}", tri[0] + 1, tri[1] + 1, tri[2] + 1)?;
            }
            Ok(())
        })?;
    }
    write_energy_csv(rows, &dir.join("energy.csv"))?;
    write_atomic(&dir.join("summary.json"), |w: &mut dyn Write| {
        serde_json::to_writer_pretty(&mut *w, summary).map_err(std::io::Error::other)?;
        writeln!(w)
    })
}

/// `energy.csv`: one row per time step.
pub fn write_energy_csv(rows: &[StepRow], path: &Path) -> Result<(), IoError> {
    write_atomic(path, |w: &mut dyn Write| {
        writeln!(
            w,
            "time_s,step,h_s,kinetic_j,potential_j,newton_iterations,retries,max_speed_m_per_s,wall_s"
        )?;
        for r in rows {
            writeln!(
                w,
                "{:.9e},{},{:.6e},{:.12e},{:.12e},{},{},{:.6e},{:.3}",
                r.time, r.step, r.h, r.kinetic, r.potential, r.newton_iterations, r.retries, r.max_speed, r.wall_s
            )?;
        }
        Ok(())
    })
}
