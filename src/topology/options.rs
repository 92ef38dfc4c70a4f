//! Compile parameters: the rest-length model and the needle limits.
//!
//! The initial shape (pitches, z offsets) has its own struct,
//! [`LayoutOptions`], since it only affects the
//! starting geometry while these constants set the relaxed fabric.

use super::error::TopologyError;
use super::layout::LayoutOptions;

/// How a [`Pattern`](crate::pattern::Pattern) becomes a
/// [`Fabric`](super::Fabric). See [`super::rest_length`] for the formulas.
#[derive(Clone, Debug, PartialEq)]
pub struct CompileOptions {
    /// Munden's course constant `k_c = cpc * l` (courses per unit length times
    /// loop length). Dry-relaxed plain knit: 5.0 (docs/MODEL.md, "Real-fabric references").
    pub munden_kc: f64,
    /// Munden's wale constant `k_w = wpc * l`. Dry-relaxed plain knit: 3.8.
    pub munden_kw: f64,
    /// Floor on the loop length in model (effective) yarn diameters: the
    /// tightest real knits have loops of about 12 yarn diameters, and no
    /// gauge makes a loop shorter. A pattern whose gauge asks for less
    /// gets a warning naming the tightest gauge its yarn reaches.
    pub jammed_loop_diameters: f64,
    /// Model radius over the radius a `yarn` line states. A yarn's stated
    /// size is its free, uncompressed thickness; inside a knit it is
    /// squashed and its fibres nest, so the centre-line model, whose yarns
    /// are incompressible tubes, uses an effective radius this much
    /// smaller (see [`super::rest_length`], "yarn model").
    pub yarn_compression: f64,
    /// Loop length over Munden's `sqrt(k_c k_w w h)`: calibrates the loop
    /// length so that the simulator's own relaxed stockinette measures the
    /// gauge it was compiled for (Munden's constants describe real yarn,
    /// not this model's).
    pub loop_calibration: f64,
    /// A slip-stitch float's rest length is `w * (1 + slip_float_slack)`:
    /// it spans one stitch and bows around the elongated loop's legs.
    /// *Robust Eulerian-on-Lagrangian Rods* tunes exactly this to change how relaxed slip patterns look.
    pub slip_float_slack: f64,
    /// Same for a stranded-colourwork float over one stitch. Knitters keep
    /// strands loose so the fabric does not pucker.
    pub strand_float_slack: f64,
    /// Loops one needle may hold at once (a held loop plus tucks on it).
    pub max_loops_on_needle: usize,
    /// Rows one loop may span, the row it was made in included (a stitch
    /// slipped once spans 2). Longer slips would not stretch that far.
    pub max_rows_per_loop: usize,
    /// Drop the layout's shape points closer than this many yarn diameters
    /// (in rest length) to a contact or pin on their yarn; 0 keeps them all
    /// (the default). See [`super::thin`]: fewer unknowns and faster
    /// float-pattern relaxation, at a measured change of the relaxed shape.
    pub shape_gap: f64,
    /// The starting geometry.
    pub layout: LayoutOptions,
}

impl Default for CompileOptions {
    fn default() -> Self {
        Self {
            munden_kc: 5.0,
            munden_kw: 3.8,
            jammed_loop_diameters: 12.0,
            yarn_compression: 0.6,
            loop_calibration: 0.72,
            slip_float_slack: 0.15,
            strand_float_slack: 0.10,
            max_loops_on_needle: 2,
            max_rows_per_loop: 4,
            shape_gap: 0.0,
            layout: LayoutOptions::default(),
        }
    }
}

impl CompileOptions {
    pub(crate) fn validate(&self) -> Result<(), TopologyError> {
        let positive = [
            ("munden_kc", self.munden_kc),
            ("munden_kw", self.munden_kw),
            ("jammed_loop_diameters", self.jammed_loop_diameters),
            ("yarn_compression", self.yarn_compression),
            ("loop_calibration", self.loop_calibration),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(TopologyError::BadOption {
                    name,
                    value,
                    why: "must be positive and finite",
                });
            }
        }
        for (name, value) in [
            ("slip_float_slack", self.slip_float_slack),
            ("strand_float_slack", self.strand_float_slack),
        ] {
            if !(value.is_finite() && value > -0.5) {
                return Err(TopologyError::BadOption {
                    name,
                    value,
                    why: "must be finite and above -0.5",
                });
            }
        }
        if !(self.shape_gap.is_finite() && self.shape_gap >= 0.0) {
            return Err(TopologyError::BadOption {
                name: "shape_gap",
                value: self.shape_gap,
                why: "must be finite and not negative",
            });
        }
        if self.max_loops_on_needle == 0 || self.max_loops_on_needle > 2 {
            return Err(TopologyError::BadOption {
                name: "max_loops_on_needle",
                value: self.max_loops_on_needle as f64,
                why: "the layout places 1 or 2 loops per needle",
            });
        }
        if self.max_rows_per_loop == 0 {
            return Err(TopologyError::BadOption {
                name: "max_rows_per_loop",
                value: 0.0,
                why: "a loop spans at least its own row",
            });
        }
        self.layout.validate()
    }
}
