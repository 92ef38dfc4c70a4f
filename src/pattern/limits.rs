//! The size and shape limits a pattern must keep ([`Limits`]): checked
//! while the chart and written rows are expanded (sizes) and on the
//! expanded rows (held loops, floats; `validate`).

/// Limits the parser enforces. `Default` gives the documented values.
#[derive(Clone, Debug, PartialEq)]
pub struct Limits {
    /// Consecutive rows a column may be slipped or tucked (held) before it is
    /// knitted again. Three rows is already a long slip (the long slips of *Robust
    /// Eulerian-on-Lagrangian Rods*, Fig. 3).
    pub max_held_rows: usize,
    /// Consecutive tucks in a column; tuck loops pile up on the needle.
    pub max_stacked_tucks: usize,
    /// Floats longer than this many stitches draw a warning ...
    pub max_float_stitches: usize,
    /// ... and so do floats longer than this, in centimetres.
    pub max_float_cm: f64,
    /// Largest width and height accepted, to keep a typo from allocating
    /// millions of stitches.
    pub max_width: usize,
    pub max_height: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_held_rows: 3,
            max_stacked_tucks: 1,
            max_float_stitches: 5,
            max_float_cm: 2.5,
            max_width: 1000,
            max_height: 1000,
        }
    }
}
