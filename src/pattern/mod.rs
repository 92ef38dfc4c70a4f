//! Pattern language: text to a validated [`Pattern`].
//!
//! A `.knit` file is metadata (`key: value`), a `legend:`, and a `chart:`
//! and/or `written:` rows; patterns/README.md is the user documentation.
//! The stages, each in its own file:
//! 1. `document`: split lines into metadata and sections (layout only);
//! 2. `meta`, `legend`: values, with defaults a knitter would assume;
//! 3. `chart` / `written`: expand repeats to fabric-view rows, keeping
//!    the source position of every stitch;
//! 4. `validate`: fabric-wide checks (held loops, floats).
//!
//! Every diagnostic points at a file, line and column (rustc-style excerpt).
//! The parser never panics: no indexing into user data, checked arithmetic
//! on counts, bounded recursion, and size [`Limits`] before allocating.

mod chart;
mod document;
mod encoding;
mod error;
mod legend;
mod limits;
mod meta;
pub mod model;
mod source;
mod validate;
mod written;
mod yarn;

use std::path::Path;

pub use error::{ErrorKind, PatternError, Site, Warning, WarningKind};
pub use limits::Limits;
pub use model::*;

use chart::GridRow;
use source::{Result, Source};

/// A successfully parsed pattern and what the knitter may want to look at.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    pub pattern: Pattern,
    pub warnings: Vec<Warning>,
    /// Each yarn's line, by yarn index, for warnings of later stages.
    pub yarn_sites: Vec<Site>,
}

/// Flat rows alternate RS (odd) and WS (even); in the round every row is RS.
pub(crate) fn side_of(number: usize, construction: Construction) -> Side {
    match construction {
        Construction::Flat if number % 2 == 0 => Side::Ws,
        _ => Side::Rs,
    }
}

/// Parses pattern text; `file` is the name used in diagnostics.
pub fn parse_str(src: &str, file: &str) -> std::result::Result<Parsed, PatternError> {
    parse_str_with(src, file, &Limits::default())
}

/// Reads and parses a pattern file.
pub fn load(path: &Path) -> std::result::Result<Parsed, PatternError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| PatternError {
        kind: ErrorKind::Io(e.to_string()),
        loc: SourceLoc {
            file: file.clone(),
            line: 0,
            column: 0,
        },
        excerpt: String::new(),
        span: 0,
    })?;
    parse_bytes(&bytes, &file)
}

/// Parses the bytes of a pattern file: UTF-8, with or without a byte-order
/// mark; a byte that is not UTF-8 is an error at its line and column.
pub fn parse_bytes(bytes: &[u8], file: &str) -> std::result::Result<Parsed, PatternError> {
    parse_str(encoding::decode(bytes, file)?, file)
}

/// [`parse_str`] with explicit limits.
///
/// A leading byte-order mark is dropped, so columns on the first line count
/// from the first visible character, as editors show them.
pub fn parse_str_with(text: &str, file: &str, limits: &Limits) -> std::result::Result<Parsed, PatternError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let src = Source::new(text, file);
    let doc = document::split(&src)?;
    let stem = Path::new(file)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("pattern");
    let (meta, mut warnings) = meta::parse(&src, &doc.meta, stem)?;
    let chart_rows = match &doc.chart {
        Some(section) => {
            let Some(legend_section) = &doc.legend else {
                return Err(src.error(ErrorKind::MissingLegend, section.header));
            };
            let (legend, legend_warnings) = legend::parse(&src, legend_section, &meta)?;
            warnings.extend(legend_warnings);
            let (rows, chart_warnings) = chart::compile(&src, section, &legend, &meta, limits)?;
            warnings.extend(chart_warnings);
            Some(rows)
        }
        None => None,
    };
    let written_rows = match &doc.written {
        Some(section) => Some(written::compile(&src, section, &meta, limits)?),
        None => None,
    };
    let rows = match (chart_rows, written_rows) {
        (Some(chart), Some(written)) => {
            agree(&src, &chart, &written)?;
            chart
        }
        (Some(rows), None) | (None, Some(rows)) => rows,
        (None, None) => return Err(src.error(ErrorKind::MissingChart, src.start())),
    };
    validate::held_loops(&src, &rows, limits)?;
    warnings.extend(validate::long_floats(&src, &rows, &meta, limits));
    for (index, (yarn, &pos)) in meta.yarns.iter().zip(&meta.yarn_pos).enumerate() {
        if !rows.iter().any(|r| r.stitches.iter().any(|s| s.yarn == index)) {
            warnings.push(src.warning(WarningKind::UnusedYarn(yarn.name.clone()), pos));
        }
    }
    let yarn_sites = meta.yarn_pos.iter().map(|&pos| src.site(pos)).collect();
    Ok(Parsed {
        pattern: assemble(&src, meta, rows),
        warnings,
        yarn_sites,
    })
}

/// When a file gives both a chart and written rows, they must say the same.
fn agree(src: &Source, chart: &[GridRow], written: &[GridRow]) -> Result<()> {
    let first_row = written.first().map_or(src.start(), |r| r.pos);
    let (cw, ww) = (
        chart.first().map_or(0, |r| r.stitches.len()),
        written.first().map_or(0, |r| r.stitches.len()),
    );
    if chart.len() != written.len() || cw != ww {
        let kind = ErrorKind::ChartWrittenSize {
            chart: (cw, chart.len()),
            written: (ww, written.len()),
        };
        return Err(src.error(kind, first_row));
    }
    for (r, (c_row, w_row)) in chart.iter().zip(written).enumerate() {
        for (column, ((c, w), &pos)) in c_row
            .stitches
            .iter()
            .zip(&w_row.stitches)
            .zip(&w_row.origin)
            .enumerate()
        {
            if c != w {
                let kind = ErrorKind::ChartWrittenMismatch {
                    row: r + 1,
                    column: column + 1,
                    chart: *c,
                    written: *w,
                };
                return Err(src.error(kind, pos));
            }
        }
    }
    Ok(())
}

fn assemble(src: &Source, meta: meta::MetaSpec, grid: Vec<GridRow>) -> Pattern {
    let width = grid.first().map_or(0, |r| r.stitches.len());
    let rows: Vec<Row> = grid
        .into_iter()
        .enumerate()
        .map(|(index, row)| Row {
            number: index + 1,
            side: side_of(index + 1, meta.construction),
            stitches: row.stitches,
            source: SourceLoc {
                file: src.file.to_string(),
                line: row.pos.line,
                column: row.pos.col,
            },
        })
        .collect();
    let meta = Meta {
        name: meta.name,
        gauge: meta.gauge,
        yarns: meta.yarns,
        construction: meta.construction,
        width,
        height: rows.len(),
        looseness: meta.looseness,
    };
    Pattern { meta, rows }
}

#[cfg(test)]
mod tests;
