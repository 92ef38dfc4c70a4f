//! Counts a designer wants to see (`knitsim --stats`): what the chart asks
//! for, and what the compiled fabric contains.
//!
//! Stitch and float counts come from the pattern alone, so they also check
//! the compiler: a float is a maximal run of columns, within one row, where a
//! yarn used in that row makes no loop (slipped stitches, or another
//! colour's stitches). Runs do not wrap around a tube's seam. Contact counts
//! and lengths come from the fabric.

use super::fabric::{ContactKind, Fabric};
use crate::pattern::{Pattern, StitchKind};
use std::fmt;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Continuous yarn pieces.
    pub yarns: usize,
    pub knit: usize,
    pub purl: usize,
    pub slip_front: usize,
    pub slip_back: usize,
    pub tuck: usize,
    /// Every loop in the fabric: the chart's knit, purl and tuck loops plus
    /// the cast-on.
    pub loops: usize,
    pub cast_on_loops: usize,
    pub contact_nodes: usize,
    pub stitch_contacts: usize,
    pub float_contacts: usize,
    pub tuck_contacts: usize,
    pub layer_contacts: usize,
    /// Sewing stitches between layers.
    pub seam_contacts: usize,
    pub floats: usize,
    /// Longest float in each chart row (bottom first), in stitches; 0 when
    /// the row has none.
    pub longest_float_per_row: Vec<usize>,
    /// Sum of the yarns' rest lengths, metres.
    pub rest_length: f64,
}

impl Stats {
    /// The longest float anywhere, in stitches.
    pub fn longest_float(&self) -> usize {
        self.longest_float_per_row.iter().copied().max().unwrap_or(0)
    }
}

/// Floats in a row: (count, longest run).
fn row_floats(row: &crate::pattern::Row) -> (usize, usize) {
    let mut yarns: Vec<usize> = row.stitches.iter().map(|s| s.yarn).collect();
    yarns.sort_unstable();
    yarns.dedup();
    let (mut count, mut longest) = (0, 0);
    for y in yarns {
        let mut run = 0;
        for st in &row.stitches {
            let loop_here = st.yarn == y && !st.is_slip();
            if loop_here {
                run = 0;
            } else {
                if run == 0 {
                    count += 1;
                }
                run += 1;
                longest = longest.max(run);
            }
        }
    }
    (count, longest)
}

pub fn stats(p: &Pattern, f: &Fabric) -> Stats {
    let mut s = Stats {
        yarns: f.yarns.len(),
        cast_on_loops: p.meta.width,
        contact_nodes: f.contacts.len(),
        rest_length: f.yarns.iter().map(|y| y.rest_length).sum(),
        ..Stats::default()
    };
    for row in &p.rows {
        for st in &row.stitches {
            match st.kind {
                StitchKind::Knit => s.knit += 1,
                StitchKind::Purl => s.purl += 1,
                StitchKind::SlipFront => s.slip_front += 1,
                StitchKind::SlipBack => s.slip_back += 1,
                StitchKind::Tuck => s.tuck += 1,
            }
        }
        let (count, longest) = row_floats(row);
        s.floats += count;
        s.longest_float_per_row.push(longest);
    }
    s.loops = s.knit + s.purl + s.tuck + s.cast_on_loops;
    for c in &f.contacts {
        match c.kind {
            ContactKind::Stitch => s.stitch_contacts += 1,
            ContactKind::Float => s.float_contacts += 1,
            ContactKind::Tuck => s.tuck_contacts += 1,
            ContactKind::Layer => s.layer_contacts += 1,
            ContactKind::Seam => s.seam_contacts += 1,
        }
    }
    s
}

impl fmt::Display for Stats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rows: [(&str, String); 15] = [
            ("yarn pieces", self.yarns.to_string()),
            ("knit", self.knit.to_string()),
            ("purl", self.purl.to_string()),
            ("slip, yarn in front", self.slip_front.to_string()),
            ("slip, yarn in back", self.slip_back.to_string()),
            ("tuck", self.tuck.to_string()),
            (
                "loops (incl. cast-on)",
                format!("{} ({})", self.loops, self.cast_on_loops),
            ),
            ("contact nodes", self.contact_nodes.to_string()),
            ("  stitch", self.stitch_contacts.to_string()),
            ("  float", self.float_contacts.to_string()),
            ("  tuck", self.tuck_contacts.to_string()),
            ("  layer", self.layer_contacts.to_string()),
            ("  seam", self.seam_contacts.to_string()),
            (
                "floats (longest)",
                format!("{} ({} sts)", self.floats, self.longest_float()),
            ),
            ("rest yarn length", format!("{:.3} m", self.rest_length)),
        ];
        let width = rows.iter().map(|r| r.0.len()).max().unwrap_or(0);
        for (name, value) in rows {
            writeln!(f, "{name:<width$}  {value:>12}")?;
        }
        Ok(())
    }
}
