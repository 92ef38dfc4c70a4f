//! State checks: is a relaxed fabric a state the model can stand behind?
//!
//! The relaxer's own stopping test only says that the free forces are small
//! relative to the axial stiffness (docs/RELAX.md, "Stopping test"). It
//! cannot see a state that is in equilibrium but broken, so these checks
//! look at the geometry itself, independently of the simulator's code
//! paths (`segments` shares nothing with `crate::contact`):
//!
//! - **Non-finite values**: NaN or infinite node positions or material
//!   coordinates `u`. Must be 0.
//! - **Overlaps**: pairs of real segments (between consecutive non-EIL
//!   points of a yarn) whose centre lines are closer than
//!   [`Limits::overlap_fraction`] (one half) of the sum of their radii and
//!   that nothing joins. Yarns this deep inside each other have passed
//!   through or are about to; the thickness barrier diverges long before
//!   (docs/MODEL.md, "Thickness contact"). Must be 0 when thickness contact
//!   is on; without it the simulator does not keep yarns apart, and the
//!   count is only reported. Pairs that may legitimately be that close are
//!   skipped, as the simulator skips them: pairs sharing a node; pairs of
//!   one yarn less than the sum of their radii apart in rest arc length
//!   (the filtered neighbours); pairs within the exclusion radius of the two
//!   sides of one persistent contact, where the two centre lines meet at
//!   the contact node by design.
//! - **Axial strain** `|dx| / du - 1` over real segments, largest in
//!   magnitude. Bounded by [`Limits::max_strain`], 10%: the stretch energy
//!   is linear elasticity in the strain, a small-strain model; knitting
//!   yarns break at roughly 10% (cotton) to 30% (wool) and a relaxed swatch
//!   under its own weight carries nowhere near that (the default relaxed
//!   stockinette stays well under 1%). A real segment whose `du` is not
//!   positive has no rest length: its strain is infinite.

pub mod segments;
pub mod verdict;

pub use verdict::{NotConverged, RunStatus};

use crate::sim::SimParams;
use crate::topology::Fabric;
use std::fmt;

/// The bounds a relaxed state must meet (see the module docs for why).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Largest allowed `| |dx| / du - 1 |` on a real segment.
    pub max_strain: f64,
    /// Two segments overlap when their centre lines are closer than this
    /// fraction of the sum of their radii.
    pub overlap_fraction: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_strain: 0.10,
            overlap_fraction: 0.5,
        }
    }
}

/// What the checks measured on one state.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct StateChecks {
    /// NaN or infinite coordinates among node positions and `u`.
    pub non_finite: usize,
    /// Overlapping segment pairs (see the module docs).
    pub overlaps: usize,
    /// Largest `| |dx| / du - 1 |` over real segments (infinite for a real
    /// segment without rest length, NaN never: a NaN segment counts as
    /// non-finite instead).
    pub max_strain: f64,
    /// Smallest centre-line distance of a checked pair over the sum of the
    /// pair's radii (infinite when no pair came within reach).
    pub min_gap_ratio: f64,
    /// Where the deepest overlapping pair is: the mean of its four end
    /// points (m), to find it in an exported state.
    pub deepest_overlap_at: Option<[f64; 3]>,
}

impl std::fmt::Display for StateChecks {
    /// The run log's line: `0 NaN/inf, 0 overlapping segment pairs, largest axial strain 0.05%`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} NaN/inf, {} overlapping segment pairs, largest axial strain {:.2}%",
            self.non_finite,
            self.overlaps,
            100.0 * self.max_strain
        )?;
        if let Some(at) = self.deepest_overlap_at {
            write!(
                f,
                "; deepest overlap at ({:.1}, {:.1}, {:.1}) mm",
                1e3 * at[0],
                1e3 * at[1],
                1e3 * at[2]
            )?;
        }
        Ok(())
    }
}

/// Why a state is rejected.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rejection {
    NonFinite(usize),
    Overlaps(usize),
    Strain(f64),
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Rejection::NonFinite(n) => write!(f, "{n} NaN/inf coordinates"),
            Rejection::Overlaps(n) => write!(f, "{n} overlapping segment pairs"),
            Rejection::Strain(s) => write!(f, "axial strain {:.1}% beyond the bound", 100.0 * s),
        }
    }
}

impl StateChecks {
    /// The first bound the state breaks, if any; overlaps count only when
    /// thickness contact is on (`contact`).
    pub fn rejection(&self, limits: &Limits, contact: bool) -> Option<Rejection> {
        if self.non_finite > 0 {
            Some(Rejection::NonFinite(self.non_finite))
        } else if contact && self.overlaps > 0 {
            Some(Rejection::Overlaps(self.overlaps))
        } else if self.max_strain.is_nan() || self.max_strain > limits.max_strain {
            Some(Rejection::Strain(self.max_strain))
        } else {
            None
        }
    }
}

/// One real segment: its nodes, yarn, `u` range and radius.
struct Seg {
    nodes: [usize; 2],
    yarn: usize,
    u: (f64, f64),
    radius: f64,
}

/// Runs every check on `f` (a compiled fabric or a simulation snapshot:
/// points sorted by `u`, EIL flags set) with the radii and exclusion radius
/// `params` simulates it with.
pub fn check_state(f: &Fabric, params: &SimParams, limits: &Limits) -> StateChecks {
    let radii = params.yarn_radii(f);
    let thickest = radii.iter().copied().fold(0.0, f64::max);
    let cp = params.contact.clone().unwrap_or_default();
    let exclusion = cp.eol_exclusion * cp.thickness_for(thickest);
    let mut out = StateChecks {
        non_finite: f
            .nodes
            .iter()
            .flat_map(|n| n.x.iter())
            .filter(|v| !v.is_finite())
            .count()
            + f.yarns
                .iter()
                .flat_map(|y| &y.points)
                .filter(|p| !p.u.is_finite())
                .count(),
        min_gap_ratio: f64::INFINITY,
        ..StateChecks::default()
    };
    let segs = real_segments(f, &radii);
    for s in &segs {
        let (a, b) = (f.nodes[s.nodes[0]].x, f.nodes[s.nodes[1]].x);
        let l = (b - a).norm();
        let du = s.u.1 - s.u.0;
        if !(l.is_finite() && du.is_finite()) {
            continue;
        }
        let strain = if du > 0.0 { (l / du - 1.0).abs() } else { f64::INFINITY };
        out.max_strain = out.max_strain.max(strain);
    }
    if out.non_finite > 0 {
        // Distances between NaN points mean nothing.
        return out;
    }
    // Contact sides: (yarn, u, 2 contact + side).
    let sides: Vec<(usize, f64, usize)> = f
        .contacts
        .iter()
        .enumerate()
        .flat_map(|(c, k)| {
            [(k.front, 2 * c), (k.back, 2 * c + 1)].map(|(p, code)| (p.yarn, f.yarns[p.yarn].points[p.point].u, code))
        })
        .collect();
    let near: Vec<Vec<usize>> = segs
        .iter()
        .map(|s| {
            let (lo, hi) = (s.u.0 - exclusion, s.u.1 + exclusion);
            let mut n: Vec<usize> = sides
                .iter()
                .filter(|c| c.0 == s.yarn && c.1 >= lo && c.1 <= hi)
                .map(|c| c.2)
                .collect();
            n.sort_unstable();
            n
        })
        .collect();
    let joined = |i: usize, j: usize| near[i].iter().any(|c| near[j].binary_search(&(c ^ 1)).is_ok());
    let x: Vec<_> = f.nodes.iter().map(|n| n.x).collect();
    let pairs: Vec<[usize; 2]> = segs.iter().map(|s| s.nodes).collect();
    let sum = |i: usize, j: usize| segs[i].radius + segs[j].radius;
    for (i, j, d) in segments::close_pairs(&x, &pairs, sum) {
        let (a, b) = (&segs[i], &segs[j]);
        let same_yarn_near = a.yarn == b.yarn && (b.u.0 - a.u.1).max(a.u.0 - b.u.1) < sum(i, j);
        if a.nodes.iter().any(|n| b.nodes.contains(n)) || same_yarn_near || joined(i, j) {
            continue;
        }
        let ratio = d / sum(i, j);
        if ratio < limits.overlap_fraction {
            out.overlaps += 1;
            if ratio < out.min_gap_ratio {
                let mean = (x[a.nodes[0]] + x[a.nodes[1]] + x[b.nodes[0]] + x[b.nodes[1]]) / 4.0;
                out.deepest_overlap_at = Some([mean.x, mean.y, mean.z]);
            }
        }
        out.min_gap_ratio = out.min_gap_ratio.min(ratio);
    }
    out
}

/// The segments between consecutive non-EIL points of every yarn.
fn real_segments(f: &Fabric, radii: &[f64]) -> Vec<Seg> {
    let mut out = Vec::new();
    for (y, yarn) in f.yarns.iter().enumerate() {
        let real: Vec<_> = yarn.points.iter().filter(|p| !p.eil).collect();
        for w in real.windows(2) {
            out.push(Seg {
                nodes: [w[0].node, w[1].node],
                yarn: y,
                u: (w[0].u, w[1].u),
                radius: radii[y],
            });
        }
    }
    out
}

#[cfg(test)]
mod tests;
