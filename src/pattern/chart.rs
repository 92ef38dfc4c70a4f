//! The chart: a grid of one-character symbols, drawn as seen from the RS.
//!
//! Charts are read as knitters read them: the last line in the file is row 1
//! (bottom), the leftmost symbol is column 0. Spaces between symbols are
//! ignored so a chart can be spaced out. One `[ ... ]` pair marks the stitch
//! repeat; the symbols outside it are edge stitches, knitted once. The pair
//! may be drawn on any rows (usually just the top one) but must sit at the
//! same columns wherever it is drawn. Without brackets the whole chart is the
//! repeat. Vertically the whole chart repeats to `height`. A trailing
//! `| NAME` gives the row's yarn, used by stitches whose legend entry names
//! none and by slips (the yarn that floats past them).

use nom::branch::alt;
use nom::bytes::complete::take_while1;
use nom::character::complete::{char, satisfy, space0};
use nom::combinator::opt;
use nom::multi::many0;
use nom::sequence::preceded;
use nom::{IResult, Parser};

use super::document::{is_name_char, Section};
use super::error::{ErrorKind, Warning, WarningKind};
use super::legend::{Legend, RESERVED};
use super::limits::Limits;
use super::meta::MetaSpec;
use super::model::Stitch;
use super::source::{located, Line, Pos, Result, Source};

/// One expanded row, fabric view, with where each stitch came from.
#[derive(Clone, Debug)]
pub(crate) struct GridRow {
    pub stitches: Vec<Stitch>,
    pub origin: Vec<Pos>,
    pub pos: Pos,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Token {
    Open,
    Close,
    Symbol(char),
}

fn token(input: &str) -> IResult<&str, Token> {
    let symbol = satisfy(|c: char| !c.is_whitespace() && !RESERVED.contains(&c));
    alt((
        char('[').map(|_| Token::Open),
        char(']').map(|_| Token::Close),
        symbol.map(Token::Symbol),
    ))
    .parse(input)
}

/// A chart line as drawn, before the legend is applied.
struct Drawn<'a> {
    line: Line<'a>,
    cells: Vec<(char, Pos)>,
    /// Cells before `[` and cells before `]`, with the bracket positions.
    repeat: Option<((usize, usize), Pos)>,
    yarn: Option<(&'a str, Pos)>,
}

fn read_line<'a>(src: &Source, line: Line<'a>) -> Result<Drawn<'a>> {
    let body = line.body();
    let yarn_tail = opt(preceded(
        (space0, char('|'), space0),
        located(line, take_while1(is_name_char)),
    ));
    let parsed: IResult<&str, _> = (many0(preceded(space0, located(line, token))), yarn_tail, space0).parse(body);
    let Ok((rest, (tokens, yarn, _))) = parsed else {
        return Err(src.error(ErrorKind::Syntax("unreadable chart line".into()), line.pos(body, 1)));
    };
    if let Some(bad) = rest.chars().next() {
        let kind = match bad {
            '|' => ErrorKind::Syntax("expected a yarn name after `|`".into()),
            c if RESERVED.contains(&c) => ErrorKind::ReservedSymbol(c),
            _ => ErrorKind::Syntax("unexpected text after the row yarn".into()),
        };
        return Err(src.error(kind, line.pos(rest, 1)));
    }
    let mut drawn = Drawn {
        line,
        cells: Vec::new(),
        repeat: None,
        yarn,
    };
    let mut open: Option<(usize, Pos)> = None;
    let bad = |msg: &str, pos| src.error(ErrorKind::BadRepeat(msg.into()), pos);
    for (tok, pos) in tokens {
        match tok {
            Token::Symbol(c) => drawn.cells.push((c, pos)),
            Token::Open if open.is_some() || drawn.repeat.is_some() => return Err(bad("only one `[` per row", pos)),
            Token::Open => open = Some((drawn.cells.len(), pos)),
            Token::Close => {
                let (start, open_pos) = open.take().ok_or_else(|| bad("`]` without a `[` before it", pos))?;
                if start == drawn.cells.len() {
                    return Err(bad("the repeat is empty", open_pos));
                }
                drawn.repeat = Some(((start, drawn.cells.len()), open_pos));
            }
        }
    }
    if let Some((_, pos)) = open {
        return Err(bad("`[` is never closed with `]`", pos));
    }
    if drawn.cells.is_empty() {
        return Err(src.error(
            ErrorKind::Syntax("chart row without stitches".into()),
            line.pos(body, 1),
        ));
    }
    Ok(drawn)
}

/// Expanded columns: chart column for each fabric column.
fn columns(chart_width: usize, repeat: (usize, usize), width: usize) -> Vec<usize> {
    let (left, end) = repeat;
    let right = chart_width - end;
    let span = end - left;
    (0..width)
        .map(|c| {
            if c < left {
                c
            } else if c >= width - right {
                chart_width - (width - c)
            } else {
                left + (c - left) % span
            }
        })
        .collect()
}

pub(crate) fn compile(
    src: &Source,
    section: &Section,
    legend: &Legend,
    meta: &MetaSpec,
    limits: &Limits,
) -> Result<(Vec<GridRow>, Vec<Warning>)> {
    let drawn = section
        .lines
        .iter()
        .map(|&l| read_line(src, l))
        .collect::<Result<Vec<_>>>()?;
    let Some(top) = drawn.first() else {
        return Err(src.error(ErrorKind::MissingChart, section.header));
    };
    let chart_width = top.cells.len();
    let mut repeat: Option<((usize, usize), Pos)> = None;
    for row in &drawn {
        let found = row.cells.len();
        if found != chart_width {
            let pos = match row.cells.get(chart_width) {
                Some(&(_, extra)) => extra,
                None => row
                    .cells
                    .last()
                    .map_or(row.line.pos(row.line.body(), 1), |&(_, p)| Pos { col: p.col + 1, ..p }),
            };
            return Err(src.error(
                ErrorKind::RaggedRow {
                    expected: chart_width,
                    found,
                },
                pos,
            ));
        }
        if let Some((found, pos)) = row.repeat {
            match repeat {
                Some((expected, _)) if expected != found => {
                    return Err(src.error(ErrorKind::MisalignedRepeat { expected, found }, pos))
                }
                _ => repeat = Some((found, pos)),
            }
        }
    }
    let span = repeat.map_or((0, chart_width), |(r, _)| r);
    let edges = chart_width - (span.1 - span.0);
    let (width, width_pos) = meta.width.unwrap_or((chart_width, section.header));
    if width > limits.max_width {
        return Err(src.error(
            ErrorKind::TooLarge(format!("width {width} (at most {})", limits.max_width)),
            width_pos,
        ));
    }
    if width < edges || (width - edges) % (span.1 - span.0) != 0 {
        let detail = format!(
            "width {width} minus {edges} edge stitches is not a multiple of the {}-stitch repeat",
            span.1 - span.0
        );
        return Err(src.error(ErrorKind::RepeatDoesNotFit { what: "stitch", detail }, width_pos));
    }
    let chart_height = drawn.len();
    let (height, height_pos) = meta.height.unwrap_or((chart_height, section.header));
    if height > limits.max_height {
        return Err(src.error(
            ErrorKind::TooLarge(format!("height {height} (at most {})", limits.max_height)),
            height_pos,
        ));
    }
    if height % chart_height != 0 {
        let detail = format!("height {height} is not a multiple of the {chart_height}-row chart");
        return Err(src.error(ErrorKind::RepeatDoesNotFit { what: "row", detail }, height_pos));
    }
    // Apply the legend once per drawn cell, bottom row first.
    let mut used = vec![false; legend.entries.len()];
    let mut chart_rows = Vec::with_capacity(chart_height);
    for row in drawn.iter().rev() {
        let row_yarn = match row.yarn {
            Some((name, pos)) => meta
                .yarn_index(name)
                .ok_or_else(|| src.error(ErrorKind::UnknownYarn(name.into()), pos))?,
            None => 0,
        };
        let mut stitches = Vec::with_capacity(chart_width);
        for &(symbol, pos) in &row.cells {
            let index = legend.entries.iter().position(|e| e.symbol == symbol);
            let entry = index
                .and_then(|i| legend.entries.get(i))
                .ok_or_else(|| src.error(ErrorKind::UnknownSymbol(symbol), pos))?;
            if let Some(flag) = index.and_then(|i| used.get_mut(i)) {
                *flag = true;
            }
            let stitch = Stitch {
                kind: entry.kind,
                yarn: row_yarn,
            };
            let yarn = if stitch.is_slip() {
                row_yarn
            } else {
                entry.yarn.unwrap_or(row_yarn)
            };
            stitches.push((Stitch { yarn, ..stitch }, pos));
        }
        chart_rows.push((stitches, row.cells.first().map_or(section.header, |&(_, p)| p)));
    }
    let warnings = legend
        .entries
        .iter()
        .zip(&used)
        .filter(|(_, &u)| !u)
        .map(|(e, _)| src.warning(WarningKind::UnusedSymbol(e.symbol), e.pos))
        .collect();
    let cols = columns(chart_width, span, width);
    let rows = (0..height)
        .filter_map(|r| chart_rows.get(r % chart_height))
        .map(|(cells, pos)| {
            let picked: Vec<(Stitch, Pos)> = cols.iter().filter_map(|&c| cells.get(c).copied()).collect();
            GridRow {
                stitches: picked.iter().map(|s| s.0).collect(),
                origin: picked.iter().map(|s| s.1).collect(),
                pos: *pos,
            }
        })
        .collect();
    Ok((rows, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_keep_edges_and_cycle_the_repeat() {
        // Chart `a[bc]d` to width 8: a b c b c b c d.
        assert_eq!(columns(4, (1, 3), 8), vec![0, 1, 2, 1, 2, 1, 2, 3]);
        // No brackets: the whole chart repeats.
        assert_eq!(columns(2, (0, 2), 6), vec![0, 1, 0, 1, 0, 1]);
    }

    #[test]
    fn tokens_skip_spaces_and_see_brackets() {
        let src = Source::new("  . [v .] . | CC", "t");
        let drawn = read_line(&src, src.lines[0]).expect("valid line");
        assert_eq!(drawn.cells.len(), 4);
        assert_eq!(drawn.repeat.map(|r| r.0), Some((1, 3)));
        assert_eq!(drawn.yarn.map(|(n, p)| (n, p.col)), Some(("CC", 15)));
    }

    #[test]
    fn bracket_errors() {
        for (text, col) in [("  .].", 4), ("  [..", 3), ("  [.[.]]", 5), ("  .[].", 4)] {
            let src = Source::new(text, "t");
            let err = read_line(&src, src.lines[0]).err().expect(text);
            assert!(matches!(err.kind, ErrorKind::BadRepeat(_)), "{text}");
            assert_eq!(err.loc.column, col, "{text}");
        }
    }
}
