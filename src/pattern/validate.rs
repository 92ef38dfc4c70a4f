//! Checks on the expanded fabric that no single line can see.
//!
//! - **Held loops.** A slip or tuck leaves the loop below on the needle; the
//!   next knitted row pulls it up over every held row. Past a few rows the
//!   loop is stretched beyond what yarn allows (and the simulation would start
//!   from an absurd rest shape), so long stacks are errors. A cast-on row is
//!   implied below row 1, so slipping or tucking on row 1 is fine: it holds a
//!   cast-on loop. Stacks running off the top are fine too (bind-off).
//! - **Floats.** In every row each yarn floats past the stitches it does not
//!   work (other colours, slipped stitches). A float longer than
//!   `max_float_stitches` stitches or `max_float_cm`, whichever is shorter at
//!   this gauge, snags: a warning, since knitters do it on purpose. Flat rows
//!   count floats between a yarn's stitches only (the edges turn the yarn);
//!   rounds also count the float that wraps from the last column to the first.

use std::collections::HashSet;

use super::chart::GridRow;
use super::error::{ErrorKind, Warning, WarningKind};
use super::limits::Limits;
use super::meta::MetaSpec;
use super::model::{Construction, StitchKind};
use super::source::{Pos, Result, Source};

/// Errors on over-stacked slips and tucks, column by column, bottom up.
pub(crate) fn held_loops(src: &Source, rows: &[GridRow], limits: &Limits) -> Result<()> {
    let width = rows.first().map_or(0, |r| r.stitches.len());
    for column in 0..width {
        let (mut held, mut tucks) = (0usize, 0usize);
        for row in rows {
            let (Some(stitch), Some(&pos)) = (row.stitches.get(column), row.origin.get(column)) else {
                continue;
            };
            match stitch.kind {
                StitchKind::Knit | StitchKind::Purl => (held, tucks) = (0, 0),
                StitchKind::Tuck => (held, tucks) = (held + 1, tucks + 1),
                StitchKind::SlipFront | StitchKind::SlipBack => (held, tucks) = (held + 1, 0),
            }
            if tucks > limits.max_stacked_tucks {
                return Err(src.error(
                    ErrorKind::TuckStacked {
                        count: tucks,
                        limit: limits.max_stacked_tucks,
                    },
                    pos,
                ));
            }
            if held > limits.max_held_rows {
                return Err(src.error(
                    ErrorKind::SlipStacked {
                        count: held,
                        limit: limits.max_held_rows,
                    },
                    pos,
                ));
            }
        }
    }
    Ok(())
}

/// Runs of columns each yarn of `row` skips, as (first column, length).
fn floats(row: &GridRow, yarn: usize, round: bool) -> Vec<(usize, usize)> {
    let worked: Vec<usize> = row
        .stitches
        .iter()
        .enumerate()
        .filter(|(_, s)| s.yarn == yarn && !s.is_slip())
        .map(|(c, _)| c)
        .collect();
    let mut runs: Vec<(usize, usize)> = worked
        .windows(2)
        .filter_map(|pair| match *pair {
            [a, b] if b > a + 1 => Some((a + 1, b - a - 1)),
            _ => None,
        })
        .collect();
    if round {
        if let (Some(&first), Some(&last)) = (worked.first(), worked.last()) {
            let wrap = row.stitches.len() - 1 - last + first;
            if wrap > 0 {
                runs.push(((last + 1) % row.stitches.len(), wrap));
            }
        }
    }
    runs
}

/// One warning per source place and yarn, however often a repeat copies it.
pub(crate) fn long_floats(src: &Source, rows: &[GridRow], meta: &MetaSpec, limits: &Limits) -> Vec<Warning> {
    let stitch_cm = meta.gauge.stitch_width() * 100.0;
    let round = meta.construction == Construction::Round;
    let mut seen: HashSet<(Pos, usize)> = HashSet::new();
    let mut warnings = Vec::new();
    for row in rows {
        let mut yarns: Vec<usize> = row.stitches.iter().map(|s| s.yarn).collect();
        yarns.sort_unstable();
        yarns.dedup();
        for &yarn in &yarns {
            for (start, stitches) in floats(row, yarn, round) {
                let length_cm = stitches as f64 * stitch_cm;
                if stitches <= limits.max_float_stitches && length_cm <= limits.max_float_cm {
                    continue;
                }
                let pos = row.origin.get(start).copied().unwrap_or(row.pos);
                if seen.insert((pos, yarn)) {
                    let name = meta
                        .yarns
                        .get(yarn)
                        .map_or_else(|| yarn.to_string(), |y| y.name.clone());
                    let kind = WarningKind::LongFloat {
                        yarn: name,
                        stitches,
                        length_cm,
                        limit_stitches: limits.max_float_stitches,
                        limit_cm: limits.max_float_cm,
                    };
                    warnings.push(src.warning(kind, pos));
                }
            }
        }
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pattern::model::Stitch;

    fn row(spec: &str) -> GridRow {
        // 'a'/'b': knit in yarn 0/1; 's': slip in yarn 0.
        let stitches: Vec<Stitch> = spec
            .chars()
            .map(|c| match c {
                'b' => Stitch {
                    kind: StitchKind::Knit,
                    yarn: 1,
                },
                's' => Stitch {
                    kind: StitchKind::SlipFront,
                    yarn: 0,
                },
                _ => Stitch {
                    kind: StitchKind::Knit,
                    yarn: 0,
                },
            })
            .collect();
        let origin = (0..stitches.len())
            .map(|c| Pos {
                line: 1,
                col: c + 1,
                len: 1,
            })
            .collect();
        GridRow {
            stitches,
            origin,
            pos: Pos::default(),
        }
    }

    #[test]
    fn floats_by_hand() {
        // Yarn 0 skips columns 2..=4 (b, b, s) and, in the round, wraps past 6..=7.
        let r = row("aabbsabb");
        assert_eq!(floats(&r, 0, false), vec![(2, 3)]);
        assert_eq!(floats(&r, 0, true), vec![(2, 3), (6, 2)]);
        // Yarn 1 works 2, 3, 6, 7: float over 4..=5; wrap over 0..=1.
        assert_eq!(floats(&r, 1, false), vec![(4, 2)]);
        assert_eq!(floats(&r, 1, true), vec![(4, 2), (0, 2)]);
    }

    #[test]
    fn held_loop_limits() {
        let src = Source::new("x", "t");
        let slip_column = |n: usize| (0..n).map(|_| row("s")).collect::<Vec<_>>();
        let limits = Limits::default();
        assert!(held_loops(&src, &slip_column(3), &limits).is_ok());
        let err = held_loops(&src, &slip_column(4), &limits).expect_err("four slips");
        assert_eq!(err.kind, ErrorKind::SlipStacked { count: 4, limit: 3 });
    }
}
