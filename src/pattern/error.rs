//! Errors and warnings that point into the pattern file.
//!
//! A knitter fixing a chart needs to see *where*: every diagnostic carries a
//! [`SourceLoc`] and the offending source line, and renders like rustc with a
//! caret under the column. The message kinds are separate enums so tests (and
//! tools) can match on the kind instead of on wording.

use std::fmt;

use super::model::{SourceLoc, Stitch};

/// What went wrong. The `Display` text is the one-line message.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ErrorKind {
    #[error("cannot read the pattern file: {0}")]
    Io(String),
    #[error("the pattern file is not UTF-8: {0}")]
    Encoding(String),
    #[error("syntax error: {0}")]
    Syntax(String),
    #[error("unknown metadata key '{0}' (expected name, gauge, yarn <NAME>, construction, width, height, looseness, legend, chart or written)")]
    UnknownKey(String),
    #[error("'{0}' is given twice")]
    DuplicateKey(String),
    #[error("bad gauge: {0}")]
    BadGauge(String),
    #[error("bad number: {0}")]
    BadNumber(String),
    #[error("bad colour literal '{0}' (expected #rrggbb)")]
    BadColour(String),
    #[error("bad yarn: {0}")]
    BadYarn(String),
    #[error("unknown yarn '{0}' (declare it with `yarn {0}: ...`)")]
    UnknownYarn(String),
    #[error("yarn '{0}' is declared twice")]
    DuplicateYarn(String),
    #[error("unknown stitch '{0}' (expected knit, purl, slip wyif, slip wyib or tuck)")]
    UnknownStitch(String),
    #[error("the chart has no legend (add a `legend:` section)")]
    MissingLegend,
    #[error("legend entry for '{0}' names no stitch (write e.g. `{0} = knit`)")]
    EmptyLegendEntry(char),
    #[error("symbol '{0}' is defined twice in the legend")]
    DuplicateSymbol(char),
    #[error("'{0}' cannot be a chart symbol (reserved for repeats, row yarns and comments)")]
    ReservedSymbol(char),
    #[error("unknown symbol '{0}' (not in the legend)")]
    UnknownSymbol(char),
    #[error("no chart (add a `chart:` or a `written:` section)")]
    MissingChart,
    #[error("ragged chart: this row has {found} stitches, the top row has {expected}")]
    RaggedRow { expected: usize, found: usize },
    #[error("bad stitch repeat: {0}")]
    BadRepeat(String),
    #[error("repeat brackets differ from the row above (columns {expected:?}, here {found:?})")]
    MisalignedRepeat {
        expected: (usize, usize),
        found: (usize, usize),
    },
    #[error("the {what} repeat does not fit: {detail}")]
    RepeatDoesNotFit { what: &'static str, detail: String },
    #[error("stitch count mismatch: row {row} gives {found} stitches, the width is {expected}")]
    StitchCount { row: usize, expected: usize, found: usize },
    #[error("row {row} is a {actual} row here, not {claimed}")]
    WrongSide {
        row: usize,
        claimed: &'static str,
        actual: &'static str,
    },
    #[error("row {0} is given twice")]
    DuplicateRow(usize),
    #[error("row {0} is missing from the written rows")]
    MissingRow(usize),
    #[error("the width is needed to expand '{0}' (add `width:`)")]
    WidthNeeded(String),
    #[error("too large: {0}")]
    TooLarge(String),
    #[error("{count} rows slipped or tucked in a row in this column (at most {limit}; the held loop would tear)")]
    SlipStacked { count: usize, limit: usize },
    #[error("{count} tucks stacked in this column (at most {limit})")]
    TuckStacked { count: usize, limit: usize },
    #[error("chart is {} x {} stitches, written rows are {} x {}", chart.0, chart.1, written.0, written.1)]
    ChartWrittenSize {
        chart: (usize, usize),
        written: (usize, usize),
    },
    #[error("chart and written rows disagree at row {row}, column {column}: chart {chart:?}, written {written:?}")]
    ChartWrittenMismatch {
        row: usize,
        column: usize,
        chart: Stitch,
        written: Stitch,
    },
}

/// A located, renderable error.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", render("error", &self.kind.to_string(), &self.loc, &self.excerpt, self.span))]
pub struct PatternError {
    pub kind: ErrorKind,
    pub loc: SourceLoc,
    /// The source line `loc.line` (empty when there is none, e.g. I/O errors).
    pub excerpt: String,
    /// Characters to underline from `loc.column` (at least one caret).
    pub span: usize,
}

/// Things a knitter may want to fix but which still knit.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WarningKind {
    #[error("yarn '{yarn}' floats past {stitches} stitches ({length_cm:.1} cm; more than {limit_stitches} stitches or {limit_cm:.1} cm snags)")]
    LongFloat {
        yarn: String,
        stitches: usize,
        length_cm: f64,
        limit_stitches: usize,
        limit_cm: f64,
    },
    #[error("the yarn of a slip legend entry is ignored: a slip makes no loop, the row's working yarn floats past it")]
    SlipYarnIgnored,
    #[error("legend symbol '{0}' is never used in the chart")]
    UnusedSymbol(char),
    #[error("yarn '{0}' is declared but never used")]
    UnusedYarn(String),
    #[error(
        "yarn {yarn} jams at {jam_sts:.1} sts x {jam_rows:.1} rows / 10 cm; the pattern asks for {sts:.1} x {rows:.1} \
         (its loops are made longer than the gauge asks, so the fabric will come out larger)"
    )]
    YarnJams {
        yarn: String,
        jam_sts: f64,
        jam_rows: f64,
        sts: f64,
        rows: f64,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    pub kind: WarningKind,
    pub loc: SourceLoc,
    pub excerpt: String,
    pub span: usize,
}

/// Where a warning about a whole line points: a yarn line, for checks
/// that later stages make (`app::load_fabric` checks each yarn against the
/// rest-length model).
#[derive(Clone, Debug, PartialEq)]
pub struct Site {
    pub loc: SourceLoc,
    pub excerpt: String,
    pub span: usize,
}

impl Site {
    pub fn warning(&self, kind: WarningKind) -> Warning {
        Warning {
            kind,
            loc: self.loc.clone(),
            excerpt: self.excerpt.clone(),
            span: self.span,
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&render(
            "warning",
            &self.kind.to_string(),
            &self.loc,
            &self.excerpt,
            self.span,
        ))
    }
}

/// Longest excerpt shown, in characters; a longer line (a chart row of
/// thousands of symbols) is cut to this many around the caret.
const EXCERPT_WIDTH: usize = 80;
/// Characters kept before the caret when a long line is cut.
const EXCERPT_LEAD: usize = 30;
const CUT: &str = "...";

/// The part of `excerpt` shown: the whole line, or a window of
/// [`EXCERPT_WIDTH`] characters around `column` with `...` where it was cut.
/// Returns the text, the caret's 1-based column in it and the span kept.
fn window(excerpt: &str, column: usize, span: usize) -> (String, usize, usize) {
    let chars: Vec<char> = excerpt.chars().collect();
    let n = chars.len();
    if n <= EXCERPT_WIDTH {
        return (excerpt.to_string(), column, span);
    }
    let caret = column.saturating_sub(1).min(n);
    let start = caret.saturating_sub(EXCERPT_LEAD).min(n - EXCERPT_WIDTH);
    let end = (start + EXCERPT_WIDTH).min(n);
    let mut text = String::new();
    let mut col = caret - start + 1;
    if start > 0 {
        text.push_str(CUT);
        col += CUT.len();
    }
    text.extend(chars.get(start..end).unwrap_or_default());
    if end < n {
        text.push_str(CUT);
    }
    (text, col, span.min(end.saturating_sub(caret)).max(1))
}

/// rustc-style excerpt: message, `--> file:line:col`, the line, carets.
/// The location is always the true one; only the excerpt may be cut.
fn render(level: &str, message: &str, loc: &SourceLoc, excerpt: &str, span: usize) -> String {
    if loc.line == 0 {
        return format!("{level}: {message}\n --> {}", loc.file);
    }
    let number = loc.line.to_string();
    let pad = " ".repeat(number.len());
    let (excerpt, column, span) = window(excerpt, loc.column, span);
    // Tabs are copied so the caret lines up whatever the terminal's tab width.
    let lead: String = excerpt
        .chars()
        .take(column.saturating_sub(1))
        .map(|c| if c == '\t' { '\t' } else { ' ' })
        .collect();
    let carets = "^".repeat(span.max(1));
    format!(
        "{level}: {message}\n{pad}--> {}:{}:{}\n{pad} |\n{number} | {excerpt}\n{pad} | {lead}{carets}",
        loc.file, loc.line, loc.column
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_stay_small() {
        // clippy::result_large_err: keep `Result<_, PatternError>` cheap to return.
        assert!(
            std::mem::size_of::<PatternError>() <= 128,
            "{}",
            std::mem::size_of::<PatternError>()
        );
    }

    #[test]
    fn caret_sits_under_the_column() {
        let err = PatternError {
            kind: ErrorKind::UnknownSymbol('x'),
            loc: SourceLoc {
                file: "patterns/foo.knit".into(),
                line: 12,
                column: 5,
            },
            excerpt: "  ..x..".into(),
            span: 1,
        };
        let text = err.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "error: unknown symbol 'x' (not in the legend)");
        assert_eq!(lines[1], "  --> patterns/foo.knit:12:5");
        assert_eq!(lines[3], "12 |   ..x..");
        // The caret is under the 'x': same byte offset in the two lines.
        assert_eq!(lines[4].find('^'), lines[3].find('x'));
    }

    #[test]
    fn tabs_keep_alignment() {
        let w = Warning {
            kind: WarningKind::UnusedSymbol('o'),
            loc: SourceLoc {
                file: "f".into(),
                line: 3,
                column: 3,
            },
            excerpt: "\t\to".into(),
            span: 1,
        };
        assert!(w.to_string().ends_with("3 | \t\to\n  | \t\t^"));
    }

    fn long_line_error(column: usize) -> String {
        let mut row: Vec<char> = vec!['o'; 5000];
        row[column - 1] = 'x';
        PatternError {
            kind: ErrorKind::UnknownSymbol('x'),
            loc: SourceLoc {
                file: "f".into(),
                line: 9,
                column,
            },
            excerpt: row.into_iter().collect(),
            span: 1,
        }
        .to_string()
    }

    #[test]
    fn long_lines_are_cut_around_the_caret() {
        for column in [1, 20, 2500, 4990, 5000] {
            let text = long_line_error(column);
            let lines: Vec<&str> = text.lines().collect();
            assert!(lines[1].ends_with(&format!("f:9:{column}")), "{text}");
            assert!(lines.iter().all(|l| l.len() <= EXCERPT_WIDTH + 20), "{text}");
            assert_eq!(lines[3].matches('x').count(), 1, "{text}");
            assert_eq!(lines[4].find('^'), lines[3].find('x'), "{text}");
            assert_eq!(lines[3].starts_with("9 | ..."), column > EXCERPT_LEAD + 1, "{text}");
            assert_eq!(lines[3].ends_with("..."), column < 5000 - 50, "{text}");
        }
    }
}
