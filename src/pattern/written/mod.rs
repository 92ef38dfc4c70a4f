//! Written rows: the instructions as worked, turned into fabric view.
//!
//! A written row lists what the knitter does in working order: on a RS row
//! the first instruction is the rightmost column, on a WS row the leftmost,
//! and a WS `p1` is a RS-view knit. That swap is the inverse of
//! [`Stitch::worked`], so a written pattern and its chart compile to equal
//! rows. Rows repeat as *instructions* (garter is "knit every row"), so the
//! fabric view of a repeated row is derived with the side it lands on.
//!
//! Stitch counts are planned before anything is expanded: `to end` and
//! `to last N sts` are solved from the width, every count uses checked
//! arithmetic, and only a row that sums to the width is materialised.

mod syntax;

use super::chart::GridRow;
use super::error::ErrorKind;
use super::limits::Limits;
use super::meta::MetaSpec;
use super::model::{Side, Stitch, StitchKind, Worked};
use super::source::{Pos, Result, Source};
use super::{document::Section, side_of};
use syntax::{row_line, Count, Item, RowLine};

/// The RS-view stitch that `worked` on `side` produces (inverse of `Stitch::worked`).
pub(crate) fn fabric_kind(worked: Worked, side: Side) -> StitchKind {
    match (worked, side) {
        (Worked::Knit, Side::Rs) | (Worked::Purl, Side::Ws) => StitchKind::Knit,
        (Worked::Purl, Side::Rs) | (Worked::Knit, Side::Ws) => StitchKind::Purl,
        (Worked::SlipWyif, Side::Rs) | (Worked::SlipWyib, Side::Ws) => StitchKind::SlipFront,
        (Worked::SlipWyib, Side::Rs) | (Worked::SlipWyif, Side::Ws) => StitchKind::SlipBack,
        (Worked::Tuck, _) => StitchKind::Tuck,
    }
}

fn too_large(src: &Source, pos: Pos) -> super::error::PatternError {
    src.error(ErrorKind::TooLarge("stitch count overflows".into()), pos)
}

fn item_pos(item: &Item) -> Pos {
    match item {
        Item::Op { pos, .. } | Item::Group { pos, .. } => *pos,
    }
}

/// Stitches in one repetition of `item`; open counts are only allowed at the top level.
fn unit(src: &Source, item: &Item) -> Result<usize> {
    let Item::Group { items, .. } = item else { return Ok(1) };
    items.iter().try_fold(0usize, |sum, inner| {
        let (Item::Op {
            count: Count::Times(n), ..
        }
        | Item::Group {
            count: Count::Times(n), ..
        }) = inner
        else {
            let msg = "`to end` / `to last` only at the outer level of a row".to_string();
            return Err(src.error(ErrorKind::BadRepeat(msg), item_pos(inner)));
        };
        unit(src, inner)?
            .checked_mul(*n)
            .and_then(|s| sum.checked_add(s))
            .ok_or_else(|| too_large(src, item_pos(inner)))
    })
}

/// How many times each top-level item is worked so the row spans `width`.
/// Returns the repetitions and the resulting stitch count.
fn plan(src: &Source, items: &[Item], width: Option<usize>) -> Result<(Vec<usize>, usize)> {
    let units = items.iter().map(|i| unit(src, i)).collect::<Result<Vec<_>>>()?;
    let whole_row = matches!(items, [Item::Op { bare: true, .. }]);
    let count = |item: &Item| match item {
        _ if whole_row => Count::UntilLeft(0),
        Item::Op { count, .. } | Item::Group { count, .. } => *count,
    };
    let mut open: Option<(usize, usize)> = None;
    let mut fixed = 0usize;
    let mut reps = Vec::with_capacity(items.len());
    for (index, (item, &unit)) in items.iter().zip(&units).enumerate() {
        match count(item) {
            Count::Times(n) => {
                let stitches = unit.checked_mul(n).ok_or_else(|| too_large(src, item_pos(item)))?;
                fixed = fixed
                    .checked_add(stitches)
                    .ok_or_else(|| too_large(src, item_pos(item)))?;
                reps.push(n);
            }
            Count::UntilLeft(left) => {
                if open.is_some() {
                    let msg = "only one `to end` / `to last` per row".to_string();
                    return Err(src.error(ErrorKind::BadRepeat(msg), item_pos(item)));
                }
                open = Some((index, left));
                reps.push(0);
            }
        }
    }
    let Some((index, left)) = open else {
        return Ok((reps, fixed));
    };
    let item = items.get(index).ok_or_else(|| too_large(src, Pos::default()))?;
    let width = width.ok_or_else(|| src.error(ErrorKind::WidthNeeded("to end".into()), item_pos(item)))?;
    let before: usize = items
        .iter()
        .zip(&reps)
        .zip(&units)
        .take(index)
        .map(|((_, r), u)| r * u)
        .sum();
    let unit = units.get(index).copied().unwrap_or(0);
    if unit == 0 {
        let msg = "a repeat `to end` must work at least one stitch".to_string();
        return Err(src.error(ErrorKind::BadRepeat(msg), item_pos(item)));
    }
    let available = width.saturating_sub(before.saturating_add(left));
    if available % unit != 0 {
        let detail = format!("{available} stitches are left for a {unit}-stitch repeat");
        return Err(src.error(ErrorKind::RepeatDoesNotFit { what: "stitch", detail }, item_pos(item)));
    }
    if let Some(r) = reps.get_mut(index) {
        *r = available / unit;
    }
    Ok((reps, fixed + available))
}

fn emit(item: &Item, reps: usize, out: &mut Vec<(Worked, Pos)>) {
    for _ in 0..reps {
        match item {
            Item::Op { worked, pos, .. } => out.push((*worked, *pos)),
            Item::Group { items, .. } => {
                for inner in items {
                    if let Item::Op {
                        count: Count::Times(n), ..
                    }
                    | Item::Group {
                        count: Count::Times(n), ..
                    } = inner
                    {
                        emit(inner, *n, out);
                    }
                }
            }
        }
    }
}

/// One pattern row in working order, before sides are applied.
struct WorkedRow {
    stitches: Vec<(Worked, Pos)>,
    yarn: usize,
    pos: Pos,
}

fn lines<'a>(src: &Source, section: &'a Section) -> Result<Vec<RowLine<'a>>> {
    section
        .lines
        .iter()
        .map(|&line| {
            row_line(line).map_err(|f| {
                let pos = line.pos(f.at, 1);
                src.error(ErrorKind::Syntax(format!("expected {}", f.expected)), pos)
            })
        })
        .collect()
}

/// Compiles the `written:` section to `height` fabric rows of `width` stitches.
pub(crate) fn compile(src: &Source, section: &Section, meta: &MetaSpec, limits: &Limits) -> Result<Vec<GridRow>> {
    let parsed = lines(src, section)?;
    let mut table: Vec<Option<&RowLine>> = Vec::new();
    for row in &parsed {
        for &(first, last, pos) in &row.rows {
            if first == 0 || last > limits.max_height {
                let msg = format!("row numbers run from 1 to {}", limits.max_height);
                return Err(src.error(ErrorKind::TooLarge(msg), pos));
            }
            if table.len() < last {
                table.resize(last, None);
            }
            for number in first..=last {
                if let Some(slot) = table.get_mut(number - 1) {
                    if slot.is_some() {
                        return Err(src.error(ErrorKind::DuplicateRow(number), pos));
                    }
                    *slot = Some(row);
                }
                let actual = side_of(number, meta.construction);
                if let Some((claimed, side_pos)) = row.side {
                    let actual = if actual == Side::Rs { "RS" } else { "WS" };
                    if !claimed.eq_ignore_ascii_case(actual) {
                        let claimed = if actual == "RS" { "WS" } else { "RS" };
                        return Err(src.error(
                            ErrorKind::WrongSide {
                                row: number,
                                claimed,
                                actual,
                            },
                            side_pos,
                        ));
                    }
                }
            }
        }
    }
    if let Some(missing) = table.iter().position(Option::is_none) {
        return Err(src.error(ErrorKind::MissingRow(missing + 1), section.header));
    }
    let rows: Vec<&RowLine> = table.into_iter().flatten().collect();
    let Some(first) = rows.first() else {
        return Err(src.error(ErrorKind::MissingChart, section.header));
    };
    let width = match meta.width {
        Some((w, _)) => w,
        None => plan(src, &first.items, None)?.1,
    };
    if width == 0 || width > limits.max_width {
        let pos = meta.width.map_or(first.label_pos, |(_, p)| p);
        return Err(src.error(
            ErrorKind::TooLarge(format!("width {width} (1 to {})", limits.max_width)),
            pos,
        ));
    }
    let mut worked_rows = Vec::with_capacity(rows.len());
    for (index, row) in rows.iter().enumerate() {
        let (reps, found) = plan(src, &row.items, Some(width))?;
        if found != width {
            let kind = ErrorKind::StitchCount {
                row: index + 1,
                expected: width,
                found,
            };
            return Err(src.error(kind, row.label_pos));
        }
        let mut stitches = Vec::with_capacity(width);
        for (item, &r) in row.items.iter().zip(&reps) {
            emit(item, r, &mut stitches);
        }
        let yarn = match row.yarn {
            Some((name, pos)) => meta
                .yarn_index(name)
                .ok_or_else(|| src.error(ErrorKind::UnknownYarn(name.into()), pos))?,
            None => 0,
        };
        worked_rows.push(WorkedRow {
            stitches,
            yarn,
            pos: row.label_pos,
        });
    }
    let period = worked_rows.len();
    let (height, height_pos) = meta.height.unwrap_or((period, section.header));
    if height > limits.max_height {
        return Err(src.error(
            ErrorKind::TooLarge(format!("height {height} (at most {})", limits.max_height)),
            height_pos,
        ));
    }
    if height % period != 0 {
        let detail = format!("height {height} is not a multiple of the {period} written rows");
        return Err(src.error(ErrorKind::RepeatDoesNotFit { what: "row", detail }, height_pos));
    }
    let grid = (0..height)
        .filter_map(|r| worked_rows.get(r % period).map(|w| (r, w)))
        .map(|(r, w)| {
            let side = side_of(r + 1, meta.construction);
            let mut cells: Vec<(Stitch, Pos)> = w
                .stitches
                .iter()
                .map(|&(worked, pos)| {
                    (
                        Stitch {
                            kind: fabric_kind(worked, side),
                            yarn: w.yarn,
                        },
                        pos,
                    )
                })
                .collect();
            // Working order to chart order: a RS row starts at the right edge.
            if side == Side::Rs {
                cells.reverse();
            }
            GridRow {
                stitches: cells.iter().map(|c| c.0).collect(),
                origin: cells.iter().map(|c| c.1).collect(),
                pos: w.pos,
            }
        })
        .collect();
    Ok(grid)
}

#[cfg(test)]
mod tests;
