//! `summary.json`: the few numbers a knitter and a reviewer read first.
//!
//! The measured gauge and the finished size come from the relaxed state
//! (`topology::measure`), next to the gauge the pattern declares; the
//! stopping quantity, its tolerance and its force scale say how far the
//! state is from equilibrium (docs/RELAX.md, "Stopping test"); energy,
//! steps, Newton iterations, wall time and the checks of the final state
//! (crossed yarns, NaN, strain) complete the record. The same
//! numbers make the final line of `knitsim relax`.

use super::checks::StateChecks;
use crate::io::{write_atomic, IoError};
use crate::pattern::Gauge;
use crate::sim::{ForceScale, RelaxReport};
use crate::solver::assembly::timing::TermTimes;
use crate::topology::{Fabric, MeasuredGauge, StitchGrid};
use serde::Serialize;
use std::io::Write;
use std::path::Path;

/// Bounding-box extents of a state (m): width (x), height (y), depth (z).
pub fn extents(f: &Fabric) -> [f64; 3] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for n in &f.nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(n.x[k]);
            hi[k] = hi[k].max(n.x[k]);
        }
    }
    [0, 1, 2].map(|k| if hi[k] >= lo[k] { hi[k] - lo[k] } else { 0.0 })
}

/// What one relaxation ended with.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub pattern: String,
    /// The gauge the pattern declares (stitches and rows per 10 cm).
    pub declared_gauge: Gauge,
    /// The gauge the relaxed state measures in its middle; `None` for
    /// fabrics without a stitch grid (in the round, not from a pattern).
    pub measured_gauge: Option<MeasuredGauge>,
    /// Finished size (mm): width along the courses, height along the
    /// wales, depth across the fabric (`StitchGrid::extents`), so a swatch
    /// that turned in space measures as it would laid square; the lab
    /// frame's bounding box for fabrics without a stitch grid.
    pub finished_size_mm: [f64; 3],
    pub converged: bool,
    pub cancelled: bool,
    /// Largest free force over the force scale, and the tolerance it was
    /// tested against.
    pub stopping_quantity: f64,
    pub tolerance: f64,
    pub force_scale: ForceScale,
    /// Potential energy of the relaxed state (J).
    pub energy: f64,
    pub steps: usize,
    pub newton_iterations: usize,
    pub wall_s: f64,
    /// The independent checks of the final state (`app::checks`): NaN or
    /// infinite coordinates, overlapping (crossed) segment pairs, largest
    /// axial strain.
    pub checks: StateChecks,
    /// Seconds per stencil set (the active terms) and in the linear solver.
    pub term_seconds: TermTimes,
}

impl Summary {
    pub fn new(
        state: &Fabric,
        grid: &StitchGrid,
        r: &RelaxReport,
        tol: f64,
        energy: f64,
        wall_s: f64,
        checks: StateChecks,
    ) -> Self {
        Summary {
            pattern: state.meta.name.clone(),
            declared_gauge: state.meta.gauge,
            measured_gauge: grid.measure(state),
            finished_size_mm: grid.extents(state).unwrap_or_else(|| extents(state)).map(|e| e * 1e3),
            converged: r.converged,
            cancelled: r.cancelled,
            stopping_quantity: r.residual,
            tolerance: tol,
            force_scale: r.force_scale,
            energy,
            steps: r.steps,
            newton_iterations: r.newton_iterations,
            wall_s,
            checks,
            term_seconds: r.term_seconds.clone(),
        }
    }

    /// One line for a terminal: measured against declared gauge, and size.
    pub fn gauge_line(&self) -> String {
        let [w, h, d] = self.finished_size_mm;
        let size = format!("{w:.1} x {h:.1} x {d:.1} mm");
        let declared = format!(
            "{:.1} x {:.1}",
            self.declared_gauge.stitches_per_10cm, self.declared_gauge.rows_per_10cm
        );
        match &self.measured_gauge {
            Some(g) => format!(
                "gauge {:.1} sts x {:.1} rows / 10 cm (pattern: {declared}); size {size}",
                g.stitches_per_10cm, g.rows_per_10cm
            ),
            None => format!("gauge not measurable (pattern: {declared}); size {size}"),
        }
    }

    /// Writes the summary as pretty JSON, atomically.
    pub fn write(&self, path: &Path) -> Result<(), IoError> {
        write_atomic(path, |w: &mut dyn Write| {
            serde_json::to_writer_pretty(&mut *w, self).map_err(std::io::Error::other)?;
            writeln!(w)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extents_of_the_crossing_fixture() {
        let f = crate::io::fixtures::crossing();
        let e = extents(&f);
        let xs: Vec<f64> = f.nodes.iter().map(|n| n.x.x).collect();
        let span = xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
        assert!((e[0] - span).abs() < 1e-15);
        assert!(e.iter().all(|v| *v >= 0.0));
    }
}
