//! The study's written outputs: `study.csv` (one row per relaxation,
//! reference first), `study.md` (the command, the machine, the reference
//! and a table of every run) and `study.png` (`plot`).
//!
//! Every file is written atomically and rewritten after each run, so the
//! directory always holds a consistent picture of what was measured so far.

use super::plot::{write_plot, PlotInfo, PlotPoint, Series};
use super::{RunRecord, StudyConfig, StudyReport};
use crate::io::{write_atomic, IoError};
use std::fmt::Write as _;
use std::path::Path;

pub const PLOT_SIZE: (u32, u32) = (900, 600);

/// Writes `study.csv`, `study.png` and `study.md` into `dir`.
pub fn write_all(dir: &Path, report: &StudyReport, config: &StudyConfig) -> Result<(), IoError> {
    write_csv(&dir.join("study.csv"), report)?;
    let info = write_plot(&dir.join("study.png"), &series(report), PLOT_SIZE.0, PLOT_SIZE.1)?;
    let md = markdown(report, config, &info);
    write_atomic(&dir.join("study.md"), |w| w.write_all(md.as_bytes()))
}

/// The runs grouped by family (solver x EIL), in the order they ran.
pub fn series(report: &StudyReport) -> Vec<Series> {
    let mut out: Vec<Series> = Vec::new();
    for r in &report.runs {
        let Some(e) = r.errors else { continue };
        let point = PlotPoint {
            wall_s: r.wall_s,
            rms_radii: e.rms_radii,
            converged: r.converged,
        };
        let label = r.family();
        match out.iter_mut().find(|s| s.label == label) {
            Some(s) => s.points.push(point),
            None => out.push(Series {
                label,
                points: vec![point],
            }),
        }
    }
    out
}

const CSV_HEADER: &str = "role,pattern,size,solver,eil,tol,max_steps,converged,steps,newton_its,wall_s,residual,\
rms_radii,width_err_pct,height_err_pct,depth_err_pct,energy_err,width_mm,height_mm,depth_mm,energy_j,failure";

fn csv_row(role: &str, report: &StudyReport, r: &RunRecord) -> String {
    let e = r.errors;
    let opt = |f: fn(&super::Errors) -> f64| e.as_ref().map_or(String::new(), |e| format!("{:.6e}", f(e)));
    format!(
        "{role},{},{}x{},{},{},{:e},{},{},{},{},{:.3},{:.3e},{},{},{},{},{},{:.4},{:.4},{:.4},{:.9e},{}",
        report.pattern.replace(',', ";"),
        report.size.0,
        report.size.1,
        r.solver,
        r.eil,
        r.tol,
        r.max_steps,
        r.converged,
        r.steps,
        r.newton_iterations,
        r.wall_s,
        r.residual,
        opt(|e| e.rms_radii),
        opt(|e| e.width_pct),
        opt(|e| e.height_pct),
        opt(|e| e.depth_pct),
        opt(|e| e.energy_rel),
        r.extents[0] * 1e3,
        r.extents[1] * 1e3,
        r.extents[2] * 1e3,
        r.energy,
        r.failure.as_deref().unwrap_or("").replace([',', '\n'], ";"),
    )
}

fn write_csv(path: &Path, report: &StudyReport) -> Result<(), IoError> {
    write_atomic(path, |w| {
        writeln!(w, "{CSV_HEADER}")?;
        if let Some(r) = &report.reference {
            writeln!(w, "{}", csv_row("reference", report, r))?;
        }
        for r in &report.runs {
            writeln!(w, "{}", csv_row("run", report, r))?;
        }
        Ok(())
    })
}

fn state(r: &RunRecord) -> &'static str {
    match (&r.failure, r.converged) {
        (Some(_), _) => "failed",
        (None, true) => "yes",
        (None, false) => "**no**",
    }
}

/// `study.md`.
pub fn markdown(report: &StudyReport, config: &StudyConfig, info: &PlotInfo) -> String {
    let mut s = String::new();
    let (w, h) = report.size;
    let _ = writeln!(s, "# Error against run time: {} {w} x {h}\n", report.pattern);
    let _ = writeln!(s, "Command: `{}`\n", config.command_line);
    let _ = writeln!(s, "Machine: {}\n", config.machine);
    reference_section(&mut s, report, config);
    let done = report.runs.len();
    if report.cancelled {
        let _ = writeln!(s, "**Stopped by the user after {done} of {} runs.**\n", report.planned);
    } else if done < report.planned {
        let _ = writeln!(s, "In progress: {done} of {} runs.\n", report.planned);
    }
    for skipped in &report.skipped_solvers {
        let _ = writeln!(s, "Skipped {skipped}.\n");
    }
    let _ = writeln!(
        s,
        "{} unknowns; errors over {} material samples ({} per reference segment). \
         Ladder runs capped at {} steps.\n",
        report.unknowns, report.samples, config.samples_per_segment, config.max_steps
    );
    let _ = writeln!(
        s,
        "![error against wall time](study.png)\n\nPlot axes (log-log): wall time 1e{} to 1e{} s, \
         RMS error 1e{} to 1e{} yarn radii; filled markers converged, hollow ones hit the step cap{}.\n",
        info.x_decades.0,
        info.x_decades.1,
        info.y_decades.0,
        info.y_decades.1,
        if info.skipped > 0 {
            format!("; {} run(s) with zero error or time are not drawn", info.skipped)
        } else {
            String::new()
        }
    );
    table(&mut s, report);
    trends(&mut s, report);
    let _ = writeln!(
        s,
        "\nRMS: distance to the reference at matched material points (each yarn sampled at fixed `u`), \
         in yarn radii. Width, height, depth: bounding-box extents in x, y, z, signed % of the \
         reference's. Energy: signed relative difference of the total potential energy. Wall time: \
         building the simulation and relaxing it."
    );
    s
}

fn reference_section(s: &mut String, report: &StudyReport, config: &StudyConfig) {
    let Some(r) = &report.reference else {
        let _ = writeln!(s, "**No reference: the study was stopped while relaxing it.**\n");
        return;
    };
    if !r.converged {
        let _ = writeln!(
            s,
            "**WARNING: the reference did NOT converge** (residual {:.3e} > tol {:.0e} after {} steps). \
             Every error below is measured against an unconverged state.\n",
            r.residual, r.tol, r.steps
        );
    }
    let _ = writeln!(
        s,
        "Reference: {}, tol {:.0e}, cap {} steps: {} after {} steps, {} Newton iterations, residual \
         {:.3e}, {:.1} s; extents {:.1} x {:.1} x {:.1} mm; energy {:.6e} J.\n",
        r.family(),
        r.tol,
        config.ref_max_steps,
        if r.converged { "converged" } else { "NOT converged" },
        r.steps,
        r.newton_iterations,
        r.residual,
        r.wall_s,
        r.extents[0] * 1e3,
        r.extents[1] * 1e3,
        r.extents[2] * 1e3,
        r.energy
    );
}

fn table(s: &mut String, report: &StudyReport) {
    let _ = writeln!(
        s,
        "| solver | EIL | tol | converged | steps | Newton | wall s | residual | RMS (radii) | width % | \
         height % | depth % | energy rel | extents mm |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &report.runs {
        let num = |v: Option<f64>, p: usize| v.map_or("-".to_string(), |v| format!("{v:.p$}"));
        let e = r.errors;
        let _ = writeln!(
            s,
            "| {} | {} | {:.0e} | {} | {} | {} | {:.1} | {:.2e} | {} | {} | {} | {} | {} | {:.1} x {:.1} x {:.1} |",
            r.solver,
            if r.eil { "on" } else { "off" },
            r.tol,
            state(r),
            r.steps,
            r.newton_iterations,
            r.wall_s,
            r.residual,
            num(e.map(|e| e.rms_radii), 3),
            num(e.map(|e| e.width_pct), 2),
            num(e.map(|e| e.height_pct), 2),
            num(e.map(|e| e.depth_pct), 1),
            e.map_or("-".to_string(), |e| format!("{:.2e}", e.energy_rel)),
            r.extents[0] * 1e3,
            r.extents[1] * 1e3,
            r.extents[2] * 1e3,
        );
    }
    for r in report.runs.iter().filter(|r| r.failure.is_some()) {
        let _ = writeln!(
            s,
            "\n{} tol {:.0e}: {}",
            r.family(),
            r.tol,
            r.failure.as_deref().unwrap_or("")
        );
    }
}

/// Per family: does the RMS error fall at every step down the ladder?
fn trends(s: &mut String, report: &StudyReport) {
    let _ = writeln!(s);
    for series in series(report) {
        let rms: Vec<f64> = series.points.iter().map(|p| p.rms_radii).collect();
        let falls = rms.windows(2).filter(|w| w[1] <= w[0]).count();
        let _ = writeln!(
            s,
            "- {}: RMS error falls at {falls} of {} tightenings of the tolerance ({}).",
            series.label,
            rms.len().saturating_sub(1),
            rms.iter().map(|v| format!("{v:.3}")).collect::<Vec<_>>().join(" -> ")
        );
    }
}
