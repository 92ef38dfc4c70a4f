//! Why a pattern cannot be compiled into yarn topology.
//!
//! Every variant names the row and column as the knitter counts them
//! (1-based rows, 0-based columns from the left as drawn), so the CLI can
//! point at the chart cell that is at fault.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum TopologyError {
    #[error("the pattern has no stitches (width {width}, {rows} rows)")]
    Empty { width: usize, rows: usize },
    #[error("row {row} has {found} stitches, expected {expected}")]
    RowWidth { row: usize, expected: usize, found: usize },
    #[error("row {row}, column {col}: yarn {yarn} is not declared (the pattern has {declared} yarns)")]
    UnknownYarn {
        row: usize,
        col: usize,
        yarn: usize,
        declared: usize,
    },
    #[error("gauge must be positive and finite (stitches {stitches}, rows {rows} per 10 cm)")]
    BadGauge { stitches: f64, rows: f64 },
    #[error("yarn {yarn} has radius {radius} m; it must be positive and finite")]
    BadRadius { yarn: usize, radius: f64 },
    #[error("looseness {0} must be positive and finite")]
    BadLooseness(f64),
    #[error("row {row} is a WS row, but a pattern in the round is worked from the RS only")]
    WsRowInRound { row: usize },
    #[error(
        "row {row}, column {col}: the needle would hold {loops} loops (at most {max}); \
         too many tucks on one stitch"
    )]
    NeedleOverfull {
        row: usize,
        col: usize,
        loops: usize,
        max: usize,
    },
    #[error(
        "row {row}, column {col}: a loop would be held (slipped or tucked over) for {rows} rows \
         (at most {max}); it cannot stretch that far"
    )]
    HeldTooLong {
        row: usize,
        col: usize,
        rows: usize,
        max: usize,
    },
    /// A bug in the compiler, reported instead of panicking.
    #[error("internal topology error: {0}")]
    Internal(String),
    #[error("compile option `{name}` = {value} is out of range: {why}")]
    BadOption {
        name: &'static str,
        value: f64,
        why: &'static str,
    },
}
