//! Where things go in the starting geometry: pitches and shape constants.
//!
//! Flat coordinates: RS faces +z, columns along +x (column `c` spans
//! `[c w, (c+1) w]`), rows along +y. Row `r` (0 = cast-on) interlocks with
//! its parents at `y = r h`: that is where its feet pass through the heads
//! below. Every length that keeps yarns apart is a multiple of the yarn
//! diameter `d` (the largest in the pattern), every length that places
//! stitches is a fraction of the pitches.
//!
//! Why the pitches may exceed the gauge: in the centre-line model two yarns
//! meet only at their shared contact nodes and must otherwise stay a
//! diameter apart, which needs room (see the derivation in
//! [`super::geometry`]). Real knits are close to jammed (Peirce: about 4 d
//! per stitch), so the starting layout uses `max(gauge, minimum)` pitches.
//! The rest lengths still come from the gauge: relaxation pulls the fabric to
//! its real size.
//!
//! In the round the flat layout is sheared so that each row climbs one row
//! height over one turn (the yarn spirals, no jog at the seam), then wrapped
//! on a cylinder whose *innermost* layer has circumference `width * w`, so
//! wrapping only ever stretches distances, never shrinks them.

use super::error::TopologyError;
use crate::pattern::{Construction, Meta};
use crate::topology::Vec3;

/// Shape constants of the starting geometry, in yarn diameters `d` unless
/// stated. Defaults are the smallest round values for which every shipped
/// structure keeps non-contact segments at least `d` apart (the clearance
/// tests in `tests/topology_clearance.rs` check them).
#[derive(Clone, Debug, PartialEq)]
pub struct LayoutOptions {
    /// Smallest stitch width (x pitch).
    pub min_stitch_width: f64,
    /// Smallest row height (y pitch).
    pub min_row_height: f64,
    /// Legs, heads and sinkers sit this far off the mid-plane (`z = 0`,
    /// where all contact nodes lie).
    pub leg_z: f64,
    /// Depth of the first float layer; each further pass of the same row
    /// floats `float_layer` deeper so crossing colours miss each other.
    pub float_z: f64,
    pub float_layer: f64,
    /// Extent of the shared segment of a stitch contact along x and along y
    /// (the arc where the head wraps the leg).
    pub wrap_step: f64,
    /// How far below its interlock a row's sinkers hang.
    pub sinker_drop: f64,
    /// How far above its interlock a head's apex rises.
    pub apex_rise: f64,
    /// Where a float crosses a leg, the leg bends away from the float this
    /// far above and below the crossing.
    pub float_bend: f64,
    /// ... and this far to the other side of the mid-plane, so the bend
    /// points stay a diameter from the crossing node.
    pub float_bend_z: f64,
    /// Where a float meets a loop, the yarn drops this far below the float
    /// at the float's depth before heading to the loop's foot.
    pub float_drop: f64,
    /// ... and this far sideways, towards the loop.
    pub float_drop_shift: f64,
    /// Vertical spread between floats of different passes on one leg.
    pub float_spread: f64,
    /// A tuck loop lies this far behind the loop it is on: same outline,
    /// stacked towards the WS (its head nodes too). The child pulled through
    /// both heads runs about this far between them, and must run more than
    /// one thickness, with room for its sticking contacts to creep: the
    /// contact filter (docs/MODEL.md, "Thickness contact") counts two heads
    /// linked through the child within one thickness of yarn as neighbours,
    /// and lets them sink into each other.
    pub tuck_depth: f64,
    /// Distance of the innermost edge strand from the fabric edge (flat).
    pub edge_gap: f64,
    /// Spacing of the strands of different yarns at an edge, in x and z.
    pub carry_spacing: f64,
    /// Smallest tube radius in the round.
    pub min_tube_radius: f64,
}

impl Default for LayoutOptions {
    fn default() -> Self {
        Self {
            min_stitch_width: 4.6,
            min_row_height: 3.6,
            leg_z: 0.7,
            float_z: 1.8,
            float_layer: 1.2,
            wrap_step: 0.35,
            sinker_drop: 0.8,
            apex_rise: 0.8,
            float_bend: 0.5,
            float_bend_z: 0.95,
            float_spread: 1.1,
            float_drop: 1.0,
            float_drop_shift: 0.4,
            tuck_depth: 2.4,
            edge_gap: 1.3,
            carry_spacing: 1.2,
            min_tube_radius: 6.0,
        }
    }
}

impl LayoutOptions {
    pub(crate) fn validate(&self) -> Result<(), TopologyError> {
        let all = [
            ("layout.min_stitch_width", self.min_stitch_width),
            ("layout.min_row_height", self.min_row_height),
            ("layout.leg_z", self.leg_z),
            ("layout.float_z", self.float_z),
            ("layout.float_layer", self.float_layer),
            ("layout.wrap_step", self.wrap_step),
            ("layout.sinker_drop", self.sinker_drop),
            ("layout.apex_rise", self.apex_rise),
            ("layout.float_bend", self.float_bend),
            ("layout.float_bend_z", self.float_bend_z),
            ("layout.float_spread", self.float_spread),
            ("layout.float_drop", self.float_drop),
            ("layout.float_drop_shift", self.float_drop_shift),
            ("layout.tuck_depth", self.tuck_depth),
            ("layout.edge_gap", self.edge_gap),
            ("layout.carry_spacing", self.carry_spacing),
            ("layout.min_tube_radius", self.min_tube_radius),
        ];
        for (name, value) in all {
            if !(value.is_finite() && value >= 0.0) {
                return Err(TopologyError::BadOption {
                    name,
                    value,
                    why: "must be finite and non-negative",
                });
            }
        }
        Ok(())
    }
}

/// The resolved layout of one pattern: pitches and shape lengths in metres.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    pub columns: usize,
    /// Gauge pitches (what the rest lengths use).
    pub gauge_w: f64,
    pub gauge_h: f64,
    /// Layout pitches (what the positions use).
    pub w: f64,
    pub h: f64,
    /// Largest yarn diameter.
    pub d: f64,
    pub leg_z: f64,
    pub float_z: f64,
    pub float_layer: f64,
    pub wrap_step: f64,
    pub sinker_drop: f64,
    pub apex_rise: f64,
    pub float_bend: f64,
    pub float_bend_z: f64,
    pub float_spread: f64,
    pub float_drop: f64,
    pub float_drop_shift: f64,
    pub tuck_depth: f64,
    pub edge_gap: f64,
    pub carry_spacing: f64,
    pub round: bool,
    /// Deepest z used (yarn ends in the round), for the cylinder map.
    pub z_min: f64,
}

impl Layout {
    /// Resolves the pitches for a pattern whose needles hold at most
    /// `max_on_needle` loops and that uses `float_layers` yarns (each floats
    /// in its own layer).
    pub fn new(
        meta: &Meta,
        opts: &LayoutOptions,
        max_on_needle: usize,
        float_layers: usize,
    ) -> Result<Self, TopologyError> {
        let g = meta.gauge;
        if !(g.stitches_per_10cm.is_finite()
            && g.stitches_per_10cm > 0.0
            && g.rows_per_10cm.is_finite()
            && g.rows_per_10cm > 0.0)
        {
            return Err(TopologyError::BadGauge {
                stitches: g.stitches_per_10cm,
                rows: g.rows_per_10cm,
            });
        }
        let mut radius: f64 = 0.0;
        for (yarn, spec) in meta.yarns.iter().enumerate() {
            if !(spec.radius.is_finite() && spec.radius > 0.0) {
                return Err(TopologyError::BadRadius {
                    yarn,
                    radius: spec.radius,
                });
            }
            radius = radius.max(spec.radius);
        }
        if radius == 0.0 {
            return Err(TopologyError::BadRadius { yarn: 0, radius });
        }
        let d = 2.0 * radius;
        let tuck_layers = max_on_needle.saturating_sub(1) as f64 * opts.tuck_depth;
        let round = meta.construction == Construction::Round;
        let columns = meta.width.max(1);
        let extra_layers = float_layers.saturating_sub(1) as f64;
        let float_depth = opts.float_z + extra_layers * opts.float_layer;
        let z_min = -(float_depth.max(opts.leg_z + tuck_layers) + opts.carry_spacing) * d;
        let mut w = g.stitch_width().max(opts.min_stitch_width * d);
        if round {
            let tube = std::f64::consts::TAU * opts.min_tube_radius * d / columns as f64;
            w = w.max(tube);
        }
        let h = g.row_height().max(opts.min_row_height * d);
        Ok(Self {
            columns,
            gauge_w: g.stitch_width(),
            gauge_h: g.row_height(),
            w,
            h,
            d,
            leg_z: opts.leg_z * d,
            float_z: opts.float_z * d,
            float_layer: opts.float_layer * d,
            wrap_step: opts.wrap_step * d,
            sinker_drop: opts.sinker_drop * d,
            apex_rise: opts.apex_rise * d,
            float_bend: opts.float_bend * d,
            float_bend_z: opts.float_bend_z * d,
            float_spread: opts.float_spread * d,
            float_drop: opts.float_drop * d,
            float_drop_shift: opts.float_drop_shift * d,
            tuck_depth: opts.tuck_depth * d,
            edge_gap: opts.edge_gap * d,
            carry_spacing: opts.carry_spacing * d,
            round,
            z_min,
        })
    }

    pub fn x_center(&self, col: usize) -> f64 {
        (col as f64 + 0.5) * self.w
    }
    pub fn x_boundary(&self, boundary: usize) -> f64 {
        boundary as f64 * self.w
    }
    /// Where row `row` passes through the heads below it.
    pub fn y_interlock(&self, row: usize) -> f64 {
        row as f64 * self.h
    }
    /// Half spacing of the legs of a loop.
    pub fn leg_offset(&self) -> f64 {
        0.25 * self.w
    }
    /// How far behind a loop in needle slot `slot` is pushed (tucks).
    pub fn slot_depth(&self, slot: usize) -> f64 {
        slot as f64 * self.tuck_depth
    }
    /// Height of a float in row `row` that is the `rank`-th float over its
    /// column: mid-row for the first, lower for later ones so two floats on
    /// one leg cross it at different heights.
    pub fn y_float(&self, row: usize, rank: usize) -> f64 {
        (row as f64 + 0.5) * self.h - rank as f64 * self.float_spread
    }
    /// Depth of a float of pass `index` on `side` (+1 front, -1 back).
    pub fn z_float(&self, index: usize, side: f64) -> f64 {
        side * (self.float_z + index as f64 * self.float_layer)
    }
    /// Ratio of rest to layout length for yarn with no better model (edge
    /// turns, carried strands): undo the layout expansion.
    pub fn connector_scale(&self) -> f64 {
        (self.gauge_w / self.w).min(self.gauge_h / self.h)
    }

    /// Maps a flat-layout point to its place in the fabric (identity when flat).
    pub fn place(&self, p: Vec3) -> Vec3 {
        if !self.round {
            return p;
        }
        let circumference = self.columns as f64 * self.w;
        let climb = self.h * (circumference - p.x) / circumference;
        let theta = std::f64::consts::TAU * p.x / circumference;
        let r_inner = circumference / std::f64::consts::TAU;
        let radius = r_inner + (p.z - self.z_min);
        Vec3::new(radius * theta.sin(), p.y + climb, radius * theta.cos())
    }
}
