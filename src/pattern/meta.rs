//! Metadata lines: name, gauge, yarns, construction, size, looseness.
//!
//! Defaults are what a knitter leaves out: one cream main-colour yarn called
//! `MC`, a worsted-ish gauge of 24 sts x 32 rows, flat, normal tension, and
//! the chart's own size. A yarn without a radius gets 0.18 stitch widths, so
//! the yarn diameter is about a third of a stitch (0.75 mm at 24 sts / 10 cm),
//! which is the proportion of a plain stockinette in a matching yarn.
//! Numbers go through nom's `double`, which accepts `nan` and `inf`; those are
//! rejected here, with the caret on the number.

use nom::branch::alt;
use nom::bytes::complete::{tag, tag_no_case};
use nom::character::complete::{char, digit1, space0, space1};
use nom::combinator::{eof, opt};
use nom::number::complete::double;
use nom::Parser;

use super::document::MetaLine;
use super::error::{ErrorKind, Warning};
use super::model::{Construction, Gauge, YarnSpec};
use super::source::{located, positive, syntax, Pos, Result, Source};
use super::yarn::{parse_yarn, PendingYarn};

/// Yarn radius when a pattern gives none, in stitch widths.
const DEFAULT_RADIUS_PER_STITCH: f64 = 0.18;

/// Metadata with the source positions later stages point errors at.
#[derive(Clone, Debug)]
pub(crate) struct MetaSpec {
    pub name: String,
    pub gauge: Gauge,
    pub yarns: Vec<YarnSpec>,
    /// Where each yarn was declared (the file start for the default yarn).
    pub yarn_pos: Vec<Pos>,
    pub construction: Construction,
    pub width: Option<(usize, Pos)>,
    pub height: Option<(usize, Pos)>,
    pub looseness: f64,
}

impl MetaSpec {
    pub fn yarn_index(&self, name: &str) -> Option<usize> {
        self.yarns.iter().position(|y| y.name == name)
    }
}

fn parse_gauge(src: &Source, m: &MetaLine) -> Result<Gauge> {
    let line = m.line;
    let sts_word = opt((
        space1,
        alt((tag_no_case("stitches"), tag_no_case("sts"), tag_no_case("st"))),
    ));
    let rows_word = opt((space1, alt((tag_no_case("rows"), tag_no_case("row")))));
    let per_10cm = opt((space0, char('/'), space0, tag("10"), space0, tag_no_case("cm")));
    let mut grammar = (
        space0,
        located(line, double),
        sts_word,
        space0,
        alt((char('x'), char(','), char('×'))),
        space0,
        located(line, double),
        rows_word,
        per_10cm,
        space0,
        eof,
    );
    let Ok((_, (_, (sts, sts_pos), _, _, _, _, (rows, rows_pos), _, _, _, _))) = grammar.parse(m.value) else {
        return Err(syntax(src, line, m.value, "a gauge like `24 sts x 32 rows / 10 cm`"));
    };
    let sts = positive(sts, "stitches per 10 cm").map_err(|e| src.error(ErrorKind::BadGauge(e), sts_pos))?;
    let rows = positive(rows, "rows per 10 cm").map_err(|e| src.error(ErrorKind::BadGauge(e), rows_pos))?;
    Ok(Gauge {
        stitches_per_10cm: sts,
        rows_per_10cm: rows,
    })
}

fn parse_count(src: &Source, m: &MetaLine) -> Result<(usize, Pos)> {
    let mut grammar = (space0, located(m.line, digit1), space0, eof);
    let Ok((_, (_, (digits, pos), _, _))) = grammar.parse(m.value) else {
        return Err(syntax(src, m.line, m.value, "a whole number, at least 1"));
    };
    match digits.parse::<usize>() {
        Ok(n) if n > 0 => Ok((n, pos)),
        _ => Err(src.error(ErrorKind::BadNumber(format!("{} must be at least 1", m.key)), pos)),
    }
}

fn parse_looseness(src: &Source, m: &MetaLine) -> Result<f64> {
    let word = m.value.trim();
    match word.to_ascii_lowercase().as_str() {
        "loose" => return Ok(1.2),
        "normal" => return Ok(1.0),
        "tight" => return Ok(0.85),
        _ => {}
    }
    let Ok((_, (_, (value, pos), _, _))) = (space0, located(m.line, double), space0, eof).parse(m.value) else {
        return Err(syntax(src, m.line, m.value, "loose, normal, tight or a number above 0"));
    };
    positive(value, "looseness").map_err(|e| src.error(ErrorKind::BadNumber(e), pos))
}

fn parse_construction(src: &Source, m: &MetaLine) -> Result<Construction> {
    match m.value.trim().to_ascii_lowercase().as_str() {
        "flat" => Ok(Construction::Flat),
        "round" | "in the round" => Ok(Construction::Round),
        _ => Err(syntax(src, m.line, m.value, "`flat` or `round`")),
    }
}

/// Reads all metadata lines; `default_name` is used when there is no `name:`.
pub(crate) fn parse(src: &Source, lines: &[MetaLine], default_name: &str) -> Result<(MetaSpec, Vec<Warning>)> {
    let mut seen: Vec<&str> = Vec::new();
    let mut name = None;
    let mut gauge = Gauge {
        stitches_per_10cm: 24.0,
        rows_per_10cm: 32.0,
    };
    let mut pending: Vec<PendingYarn> = Vec::new();
    let mut construction = Construction::Flat;
    let (mut width, mut height, mut looseness) = (None, None, 1.0);
    for m in lines {
        if m.key != "yarn" {
            if seen.contains(&m.key) {
                return Err(src.error(ErrorKind::DuplicateKey(m.key.into()), m.key_pos));
            }
            seen.push(m.key);
            if let Some((_, pos)) = m.arg {
                return Err(src.error(
                    ErrorKind::Syntax(format!("`{}` takes no name before the colon", m.key)),
                    pos,
                ));
            }
        }
        match m.key {
            "name" => match m.value.trim() {
                "" => return Err(syntax(src, m.line, m.value, "a name")),
                text => name = Some(text.to_string()),
            },
            "gauge" => gauge = parse_gauge(src, m)?,
            "yarn" => {
                let yarn = parse_yarn(src, m)?;
                if pending.iter().any(|y| y.name == yarn.name) {
                    return Err(src.error(ErrorKind::DuplicateYarn(yarn.name), yarn.pos));
                }
                pending.push(yarn);
            }
            "construction" => construction = parse_construction(src, m)?,
            "width" => width = Some(parse_count(src, m)?),
            "height" => height = Some(parse_count(src, m)?),
            "looseness" => looseness = parse_looseness(src, m)?,
            other => return Err(src.error(ErrorKind::UnknownKey(other.into()), m.key_pos)),
        }
    }
    if pending.is_empty() {
        let pos = src.start();
        pending.push(PendingYarn {
            name: "MC".into(),
            pos,
            color: [0xd9, 0xcf, 0xc1],
            radius: None,
            material: None,
        });
    }
    let stitch = gauge.stitch_width();
    let warnings = Vec::new();
    let mut yarns = Vec::new();
    let mut yarn_pos = Vec::new();
    for y in pending {
        let (radius, size_pos) = y.radius.unwrap_or((DEFAULT_RADIUS_PER_STITCH * stitch, y.pos));
        let (diameter_mm, stitch_mm) = (2e3 * radius, 1e3 * stitch);
        if diameter_mm >= stitch_mm {
            let msg = format!("diameter {diameter_mm:.2} mm does not fit in a {stitch_mm:.2} mm stitch (see gauge)");
            return Err(src.error(ErrorKind::BadYarn(msg), size_pos));
        }
        yarns.push(YarnSpec {
            name: y.name,
            color: y.color,
            radius,
            material: y.material,
        });
        yarn_pos.push(y.pos);
    }
    let name = name.unwrap_or_else(|| default_name.to_string());
    let spec = MetaSpec {
        name,
        gauge,
        yarns,
        yarn_pos,
        construction,
        width,
        height,
        looseness,
    };
    Ok((spec, warnings))
}

#[cfg(test)]
mod tests {
    use super::super::document::split;
    use super::*;

    fn meta(text: &str) -> Result<MetaSpec> {
        let src = Source::new(text, "t.knit");
        let doc = split(&src)?;
        parse(&src, &doc.meta, "t").map(|(m, _)| m)
    }

    #[test]
    fn gauge_forms() {
        for text in [
            "gauge: 22 sts x 30 rows / 10 cm",
            "gauge: 22x30",
            "gauge: 22 stitches, 30 rows",
        ] {
            let g = meta(text).expect(text).gauge;
            assert_eq!((g.stitches_per_10cm, g.rows_per_10cm), (22.0, 30.0), "{text}");
        }
    }

    #[test]
    fn nan_gauge_points_at_the_number() {
        let err = meta("gauge: 22 x nan").expect_err("NaN rows");
        assert!(matches!(err.kind, ErrorKind::BadGauge(_)));
        assert_eq!((err.loc.column, err.span), (13, 3));
    }

    #[test]
    fn default_yarn_scales_with_gauge() {
        let m = meta("gauge: 20 x 28").expect("defaults");
        // 0.18 of a 5 mm stitch.
        assert!((m.yarns[0].radius - 0.9e-3).abs() < 1e-12);
        assert_eq!(m.looseness, 1.0);
    }

    #[test]
    fn looseness_words_and_numbers() {
        assert_eq!(meta("looseness: tight").expect("tight").looseness, 0.85);
        assert_eq!(meta("looseness: 1.1").expect("number").looseness, 1.1);
        assert!(meta("looseness: -1").is_err());
        assert!(meta("looseness: inf").is_err());
    }
}
