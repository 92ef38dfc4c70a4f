//! Patterns built in code from small character charts, for tests, examples
//! and benchmarks (the text format proper lives in [`crate::pattern`]).
//!
//! A chart is drawn as a knitter reads it: **top row first**, leftmost
//! column first, in fabric view (what the RS shows). Stitches: `k` knit,
//! `p` purl, `v` slip with the float on the RS, `w` slip with the float on
//! the WS, `t` tuck. An optional colour chart of the same shape holds one
//! digit per stitch: the yarn index.

use crate::pattern::{Construction, Gauge, Meta, Pattern, Row, Side, SourceLoc, Stitch, StitchKind, YarnSpec};
use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum ChartError {
    #[error("the chart is empty")]
    Empty,
    #[error("chart line {line} has {found} stitches, expected {expected}")]
    Ragged { line: usize, found: usize, expected: usize },
    #[error("chart line {line}, column {col}: unknown symbol {symbol:?}")]
    Symbol { line: usize, col: usize, symbol: char },
    #[error("the colour chart does not have the same shape as the stitch chart")]
    ColourShape,
}

/// Default yarns: 1 mm diameter in distinct colours. At the default gauge
/// (4.5 mm stitches) that is a stitch of 4.5 d, close to Peirce's jammed
/// 4 d but looser, so Munden's loop length (17 mm) is above the jam floor
/// (16.6 mm) and looseness acts.
pub fn yarn(index: usize) -> YarnSpec {
    const COLOURS: [[u8; 3]; 4] = [[200, 60, 50], [240, 235, 220], [40, 80, 160], [60, 140, 70]];
    YarnSpec {
        name: format!("yarn {index}"),
        color: COLOURS[index % COLOURS.len()],
        radius: 0.5e-3,
        material: None,
    }
}

fn kind(symbol: char) -> Option<StitchKind> {
    Some(match symbol {
        'k' => StitchKind::Knit,
        'p' => StitchKind::Purl,
        'v' => StitchKind::SlipFront,
        'w' => StitchKind::SlipBack,
        't' => StitchKind::Tuck,
        _ => return None,
    })
}

/// A pattern from a stitch chart and an optional colour chart (both top row
/// first). Flat rows alternate RS (row 1) and WS; round rows are all RS.
/// Gauge 22 stitches and 30 rows per 10 cm, looseness 1.
pub fn chart_pattern(
    chart: &[&str],
    colours: Option<&[&str]>,
    construction: Construction,
) -> Result<Pattern, ChartError> {
    let width = chart.first().map_or(0, |l| l.chars().count());
    if width == 0 {
        return Err(ChartError::Empty);
    }
    if let Some(c) = colours {
        let same = c.len() == chart.len() && c.iter().all(|l| l.chars().count() == width);
        if !same {
            return Err(ChartError::ColourShape);
        }
    }
    let mut rows = Vec::with_capacity(chart.len());
    let mut yarns_used = 1;
    for (i, line) in chart.iter().enumerate().rev() {
        let found = line.chars().count();
        if found != width {
            return Err(ChartError::Ragged {
                line: i + 1,
                found,
                expected: width,
            });
        }
        let colour_line: Vec<usize> = match colours {
            Some(c) => c[i]
                .chars()
                .map(|ch| ch.to_digit(10).map_or(0, |d| d as usize))
                .collect(),
            None => vec![0; width],
        };
        let mut stitches = Vec::with_capacity(width);
        for (col, symbol) in line.chars().enumerate() {
            let kind = kind(symbol).ok_or(ChartError::Symbol {
                line: i + 1,
                col,
                symbol,
            })?;
            let yarn = colour_line[col];
            yarns_used = yarns_used.max(yarn + 1);
            stitches.push(Stitch { kind, yarn });
        }
        let number = rows.len() + 1;
        let side = match construction {
            Construction::Flat if number % 2 == 0 => Side::Ws,
            _ => Side::Rs,
        };
        rows.push(Row {
            number,
            side,
            stitches,
            source: SourceLoc {
                file: "<chart>".into(),
                line: i + 1,
                column: 1,
            },
        });
    }
    Ok(Pattern {
        meta: Meta {
            name: "chart".into(),
            gauge: Gauge {
                stitches_per_10cm: 22.0,
                rows_per_10cm: 30.0,
            },
            yarns: (0..yarns_used).map(yarn).collect(),
            construction,
            width,
            height: rows.len(),
            looseness: 1.0,
        },
        rows,
    })
}

/// Repeats a tile (top row first) to `width` x `height` stitches, aligned at
/// the bottom left as knitting repeats are. An empty tile gives knit rows.
pub fn tile(tile: &[&str], width: usize, height: usize) -> Vec<String> {
    if tile.is_empty() || tile.iter().any(|l| l.is_empty()) {
        return vec!["k".repeat(width); height];
    }
    let th = tile.len();
    let rows: Vec<Vec<char>> = tile.iter().map(|l| l.chars().collect()).collect();
    (0..height)
        .map(|top_index| {
            let from_bottom = height - 1 - top_index;
            let row = &rows[th - 1 - from_bottom % th];
            (0..width).map(|c| row[c % row.len()]).collect()
        })
        .collect()
}
