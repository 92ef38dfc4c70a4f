//! The compiled chart: what the parser hands to the topology compiler.
//!
//! Everything here is in *fabric view*: stitches are named as they look from
//! the right side (RS), columns are numbered left to right as the chart is
//! drawn, rows bottom to top. Repeats are already expanded. What the knitter
//! actually works on a WS row (purl for a RS knit, slip wyib for a RS-front
//! float) is derived by [`Stitch::worked`], never stored, so a chart and its
//! written form cannot disagree.

use serde::{Deserialize, Serialize};

/// A parsed, validated and fully expanded pattern.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pattern {
    pub meta: Meta,
    /// Rows bottom first. Every row has `meta.width` stitches.
    pub rows: Vec<Row>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Meta {
    pub name: String,
    pub gauge: Gauge,
    /// Yarns by index; [`Stitch::yarn`] points in here.
    pub yarns: Vec<YarnSpec>,
    pub construction: Construction,
    /// Stitches per row after repeats are expanded.
    pub width: usize,
    /// Rows after row repeats are expanded.
    pub height: usize,
    /// Rest-length scale: 1.0 normal, below 1 tight, above 1 loose.
    /// `tight` = 0.85, `normal` = 1.0, `loose` = 1.2.
    pub looseness: f64,
}

/// Stitches and rows per 10 cm, as printed on a ball band.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Gauge {
    pub stitches_per_10cm: f64,
    pub rows_per_10cm: f64,
}

impl Gauge {
    /// Stitch width in metres.
    pub fn stitch_width(&self) -> f64 {
        0.1 / self.stitches_per_10cm
    }
    /// Row height in metres.
    pub fn row_height(&self) -> f64 {
        0.1 / self.rows_per_10cm
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct YarnSpec {
    pub name: String,
    /// sRGB colour.
    pub color: [u8; 3],
    /// Yarn radius in metres (patterns write millimetres).
    pub radius: f64,
    pub material: Option<String>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Construction {
    /// Back and forth: RS rows worked right to left, WS rows left to right.
    Flat,
    /// In the round: every row is RS, worked right to left; the result is a tube.
    Round,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Side {
    Rs,
    Ws,
}

/// One chart row, fabric view.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// 1-based row number as a knitter counts (after row repeats are expanded).
    pub number: usize,
    pub side: Side,
    /// Index 0 is the leftmost column as drawn (seen from the RS).
    pub stitches: Vec<Stitch>,
    /// Where the row came from, for error messages downstream.
    pub source: SourceLoc,
}

impl Row {
    /// Columns in the order the knitter works them.
    pub fn work_order(&self) -> Box<dyn Iterator<Item = usize>> {
        let n = self.stitches.len();
        match self.side {
            Side::Rs => Box::new((0..n).rev()),
            Side::Ws => Box::new(0..n),
        }
    }
}

/// A stitch as it appears from the right side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Stitch {
    pub kind: StitchKind,
    /// The yarn that forms the loop (knit, purl, tuck), or, for a slip, the
    /// working yarn that floats past it.
    pub yarn: usize,
}

/// Stitch kinds in fabric view (as seen from the RS).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum StitchKind {
    /// A V on the RS: the new loop is pulled through its parent towards the RS.
    Knit,
    /// A bump on the RS: the new loop is pulled through towards the WS.
    Purl,
    /// Slipped, the float lies on the RS face (sl wyif on a RS row).
    SlipFront,
    /// Slipped, the float lies on the WS face (sl wyib on a RS row).
    SlipBack,
    /// The yarn is laid over the needle as an extra loop, not pulled through.
    Tuck,
}

/// What the knitter does on the needle for a stitch on a given side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Worked {
    Knit,
    Purl,
    SlipWyif,
    SlipWyib,
    Tuck,
}

impl Stitch {
    /// The instruction the knitter follows, derived from the fabric view.
    pub fn worked(&self, side: Side) -> Worked {
        match (self.kind, side) {
            (StitchKind::Knit, Side::Rs) | (StitchKind::Purl, Side::Ws) => Worked::Knit,
            (StitchKind::Purl, Side::Rs) | (StitchKind::Knit, Side::Ws) => Worked::Purl,
            (StitchKind::SlipFront, Side::Rs) | (StitchKind::SlipBack, Side::Ws) => Worked::SlipWyif,
            (StitchKind::SlipBack, Side::Rs) | (StitchKind::SlipFront, Side::Ws) => Worked::SlipWyib,
            (StitchKind::Tuck, _) => Worked::Tuck,
        }
    }

    pub fn is_slip(&self) -> bool {
        matches!(self.kind, StitchKind::SlipFront | StitchKind::SlipBack)
    }
}

/// A place in a source file (1-based line and column).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SourceLoc {
    pub file: String,
    pub line: usize,
    pub column: usize,
}
