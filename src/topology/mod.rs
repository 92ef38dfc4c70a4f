//! From a pattern to yarn-level topology: the [`Fabric`].
//!
//! The compiler runs in three stages (and an optional fourth), one file each:
//! 1. [`knit_graph`]: simulate the needles: which loop is pulled through
//!    which, which loops are held (slips, tucks), and how each yarn piece
//!    travels along the rows (passes, floats, cut-and-rejoin, carries).
//! 2. [`geometry`] (with [`layout`]): a starting shape in which every contact
//!    node is shared by its two yarns and no other two segments come closer
//!    than a yarn diameter ([`mod@clearance`] checks it).
//! 3. [`assemble`] (with [`rest_length`]): yarns as sorted `(u, x)` lists,
//!    `u` from the gauge's loop length, and the contacts with their front
//!    and back yarn points. Yarn radii are model (effective) radii from
//!    here on ([`rest_length`], "yarn model").
//! 4. [`thin`] (opt-in, `CompileOptions::shape_gap`): drop shape points
//!    closer than a few yarn diameters to a contact.
//!
//! Contacts per structure (docs/MODEL.md, "Stitch contact layout"):
//! - knit/purl child through each parent head: 2 stitch contacts (left and
//!   right leg) of 2 nodes each, partners of each other: 4 [`ContactKind::Stitch`]
//!   nodes per parent. A knit child is `front`, a purl child `back`.
//! - float (slip or colourwork strand) over a column: one
//!   [`ContactKind::Float`] node per leg of every loop spanning that row.
//! - tuck: one [`ContactKind::Tuck`] node per leg of the loop it sits on,
//!   the held loop in front; the next row's child then has two parents.
//!
//! The cast-on (row 0) is one pass of plain loops in the yarn that starts
//! row 1. Loops left on the needles after the last row stay open.

pub mod align;
pub mod assemble;
pub mod clearance;
pub mod error;
pub mod fabric;
pub mod geometry;
pub mod jitter;
pub mod knit_graph;
pub mod layers;
pub mod layout;
pub mod measure;
pub mod options;
pub mod passes;
pub mod path;
pub mod rest_length;
pub mod sample;
pub mod stack;
pub mod stats;
pub mod thin;
pub mod weave;

pub use clearance::{clearance, ClearanceOptions, ClearanceReport, Violation};
pub use error::TopologyError;
pub use fabric::*;
pub use layout::LayoutOptions;
pub use measure::{MeasuredGauge, StitchGrid};
pub use options::CompileOptions;
pub use stack::{stack_layers, stack_layers_mapped};
pub use stats::{stats, Stats};
pub use thin::thin_shape_points;

use crate::pattern::Pattern;

/// Compiles a pattern into yarns, nodes and persistent contacts.
pub fn compile(p: &Pattern, opts: &CompileOptions) -> Result<Fabric, TopologyError> {
    opts.validate()?;
    if !(p.meta.looseness.is_finite() && p.meta.looseness > 0.0) {
        return Err(TopologyError::BadLooseness(p.meta.looseness));
    }
    let graph = knit_graph::build(p, opts)?;
    let on_needle = graph.loops.iter().map(|l| l.slot + 1).max().unwrap_or(1);
    let mut specs: Vec<usize> = graph.passes.iter().map(|pass| pass.spec).collect();
    specs.sort_unstable();
    specs.dedup();
    // Everything past the graph sees the model (effective) yarn radii.
    let meta = rest_length::effective_meta(&p.meta, opts);
    let lay = layout::Layout::new(&meta, &opts.layout, on_needle, specs.len())?;
    let geo = geometry::Geometry::new(&graph, &lay);
    let mut fabric = assemble::assemble(&graph, &lay, geo, &meta, opts)?;
    thin::thin_shape_points(&mut fabric, opts.shape_gap);
    Ok(fabric)
}
