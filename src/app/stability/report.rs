//! The suite's outputs: `stability.md` (a table and a summary for people)
//! and `stability.csv` (one row per case, for scripts), both written
//! atomically (`io::write_atomic`).

use super::{CaseOutcome, CaseRow, SuiteOptions};
use crate::app::checks::Limits;
use crate::io::{write_atomic, IoError};
use std::io::Write;
use std::path::Path;

#[derive(Debug, thiserror::Error)]
pub enum StabilityError {
    #[error("cannot create output directory {path}")]
    OutDir { path: String, source: std::io::Error },
    #[error(transparent)]
    Io(#[from] IoError),
}

/// Writes `dir/stability.md` and `dir/stability.csv`.
pub fn write_report(dir: &Path, opts: &SuiteOptions, rows: &[CaseRow]) -> Result<(), StabilityError> {
    write_atomic(&dir.join("stability.csv"), |w: &mut dyn Write| csv(w, rows))?;
    write_atomic(&dir.join("stability.md"), |w: &mut dyn Write| markdown(w, opts, rows))?;
    Ok(())
}

fn csv(w: &mut dyn Write, rows: &[CaseRow]) -> std::io::Result<()> {
    writeln!(
        w,
        "case,contact,max_steps,outcome,reason,steps,newton_iterations,residual,max_eil,\
         non_finite,overlaps,min_gap_ratio,max_strain,checks_pass,wall_s"
    )?;
    for r in rows {
        writeln!(
            w,
            "\"{}\",{},{},{},\"{}\",{},{},{:.6e},{},{},{},{:.4},{:.6e},{},{:.3}",
            r.name.replace('"', "'"),
            r.contact,
            r.max_steps,
            r.outcome.label(),
            r.outcome.detail().replace('"', "'").replace('\n', " "),
            r.steps,
            r.newton_iterations,
            r.residual,
            r.max_eil,
            r.checks.non_finite,
            r.checks.overlaps,
            r.checks.min_gap_ratio,
            r.checks.max_strain,
            r.checks_pass(),
            r.wall_s
        )?;
    }
    Ok(())
}

fn markdown(w: &mut dyn Write, opts: &SuiteOptions, rows: &[CaseRow]) -> std::io::Result<()> {
    let (n, steps) = opts.size_and_steps();
    let limits = Limits::default();
    writeln!(w, "# Stability suite{}\n", if opts.quick { " (quick)" } else { "" })?;
    writeln!(
        w,
        "Command: `knitsim stability{}`. Machine: {}.\n",
        if opts.quick { " --quick" } else { "" },
        crate::app::study::machine_description()
    )?;
    writeln!(
        w,
        "Cases: a {n}x{n} stockinette swatch (24 sts / 10 cm, yarn radius 0.75 mm) unless named \
         otherwise, thickness contact `filtered` on unless marked off, relaxed by `knitsim relax`'s \
         job with the direct solver and default options except the step cap: {steps} steps \
         (5 for the long strip and column), stopped after a wall-time cap per case (shown in the \
         reason when it hit). Stiffness factors multiply the defaults (`ks` = 100 N, \
         `kb` = 1e-7 N m^2, gravity 9.81 m/s^2 with the gravity term on).\n"
    )?;
    writeln!(
        w,
        "Checks on the final state (`app::checks`): NaN/inf coordinates (must be 0); overlapping \
         segment pairs, centre lines closer than {} of the sum of their radii (must be 0 with \
         contact on); largest axial strain `| |dx|/du - 1 |` over real segments (must stay below \
         {:.0}%). `gap` is the smallest centre-line distance of a checked pair over the sum of \
         its radii. `residual` is the relaxer's stopping quantity (largest free force over the \
         force scale, docs/RELAX.md, \"Stopping test\"; tolerance {}). A run whose final state \
         fails a check is reported not converged. A case that ended in an error has no final \
         state: `-`.\n",
        limits.overlap_fraction,
        100.0 * limits.max_strain,
        crate::sim::RelaxOptions::default().tol
    )?;
    writeln!(
        w,
        "| case | contact | outcome | steps | Newton | residual | NaN | overlaps | gap | strain | wall s | reason |"
    )?;
    writeln!(w, "|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    for r in rows {
        // A case that ended in an error or a panic has no final state to
        // measure: its measured columns are left empty.
        let measured = matches!(r.outcome, CaseOutcome::Converged | CaseOutcome::NotConverged(_));
        let cols = if measured {
            format!(
                "{} | {} | {:.2e} | {} | {} | {:.2} | {:.2}%",
                r.steps,
                r.newton_iterations,
                r.residual,
                r.checks.non_finite,
                r.checks.overlaps,
                r.checks.min_gap_ratio,
                100.0 * r.checks.max_strain
            )
        } else {
            "- | - | - | - | - | - | -".to_string()
        };
        writeln!(
            w,
            "| {} | {} | {} | {cols} | {:.1} | {} |",
            r.name,
            if r.contact { "on" } else { "off" },
            r.outcome.label(),
            r.wall_s,
            r.outcome.detail().replace('|', "/").replace('\n', " ")
        )?;
    }
    let count = |f: fn(&CaseOutcome) -> bool| rows.iter().filter(|r| f(&r.outcome)).count();
    let total: f64 = rows.iter().map(|r| r.wall_s).sum();
    writeln!(
        w,
        "\n{} cases: {} converged, {} not converged, {} errors, {} panics; rows with NaN: {}; \
         rows called converged whose state fails a check: {}. Total wall time {:.0} s.",
        rows.len(),
        count(|o| matches!(o, CaseOutcome::Converged)),
        count(|o| matches!(o, CaseOutcome::NotConverged(_))),
        count(|o| matches!(o, CaseOutcome::Error(_))),
        count(|o| matches!(o, CaseOutcome::Panic(_))),
        rows.iter().filter(|r| r.checks.non_finite > 0).count(),
        rows.iter()
            .filter(|r| r.outcome == CaseOutcome::Converged && !r.checks_pass())
            .count(),
        total
    )
}
