//! The legend: one chart symbol per line, named in RS (fabric) view.
//!
//! `v = slip wyif` means "the float shows on the RS", whatever row it is on;
//! the WS instruction (sl wyib) is derived by `Stitch::worked`. An entry may
//! fix a yarn (`A = knit, yarn CC`) for jacquard; entries without one use the
//! row's yarn. Slips never take an entry's yarn: a slip makes no loop, and the
//! yarn that passes it is whichever yarn the row is worked in.

use nom::branch::alt;
use nom::bytes::complete::{tag_no_case, take_while1};
use nom::character::complete::{char, space0, space1};
use nom::combinator::{eof, opt, value};
use nom::sequence::preceded;
use nom::{IResult, Parser};

use super::document::{is_name_char, Section};
use super::error::{ErrorKind, Warning, WarningKind};
use super::meta::MetaSpec;
use super::model::StitchKind;
use super::source::{located, Pos, Result, Source};

/// Characters with a meaning of their own in chart lines.
pub(crate) const RESERVED: [char; 4] = ['[', ']', '|', '#'];

#[derive(Clone, Debug)]
pub(crate) struct Entry {
    pub symbol: char,
    pub kind: StitchKind,
    /// Index into `Meta::yarns`; `None`: the row's yarn.
    pub yarn: Option<usize>,
    pub pos: Pos,
}

#[derive(Clone, Debug, Default)]
pub(crate) struct Legend {
    pub entries: Vec<Entry>,
}

impl Legend {
    pub fn get(&self, symbol: char) -> Option<&Entry> {
        self.entries.iter().find(|e| e.symbol == symbol)
    }
}

/// Stitch names as a knitter writes them in a key, RS view.
pub(crate) fn stitch_name(input: &str) -> IResult<&str, StitchKind> {
    let slip = || (alt((tag_no_case("slip"), tag_no_case("sl"))), space1);
    alt((
        value(StitchKind::Knit, alt((tag_no_case("knit"), tag_no_case("k")))),
        value(StitchKind::Purl, alt((tag_no_case("purl"), tag_no_case("p")))),
        value(StitchKind::SlipFront, preceded(slip(), tag_no_case("wyif"))),
        value(StitchKind::SlipBack, preceded(slip(), tag_no_case("wyib"))),
        value(StitchKind::Tuck, alt((tag_no_case("tuck"), tag_no_case("tk")))),
    ))
    .parse(input)
}

pub(crate) fn parse(src: &Source, section: &Section, meta: &MetaSpec) -> Result<(Legend, Vec<Warning>)> {
    let mut legend = Legend::default();
    let mut warnings = Vec::new();
    for &line in &section.lines {
        let body = line.body();
        let mut chars = body.chars();
        let Some(symbol) = chars.next() else { continue };
        let sym_pos = line.pos(body, 1);
        if RESERVED.contains(&symbol) {
            return Err(src.error(ErrorKind::ReservedSymbol(symbol), sym_pos));
        }
        if legend.get(symbol).is_some() {
            return Err(src.error(ErrorKind::DuplicateSymbol(symbol), sym_pos));
        }
        let after = chars.as_str();
        let Ok((definition, _)) = (space0::<&str, nom::error::Error<&str>>, char('=')).parse(after) else {
            if after.trim().is_empty() {
                return Err(src.error(ErrorKind::EmptyLegendEntry(symbol), sym_pos));
            }
            let msg = "expected `=` after the one-character symbol".to_string();
            return Err(src.error(ErrorKind::Syntax(msg), line.at(after.trim_start())));
        };
        let (stitch_part, tail) = definition.split_at(definition.find(',').unwrap_or(definition.len()));
        let stitch_text = stitch_part.trim();
        if stitch_text.is_empty() {
            return Err(src.error(ErrorKind::EmptyLegendEntry(symbol), sym_pos));
        }
        let Ok((_, (kind, _))) = (stitch_name, eof).parse(stitch_text) else {
            return Err(src.error(ErrorKind::UnknownStitch(stitch_text.into()), line.at(stitch_text)));
        };
        let yarn_clause = opt((
            char(','),
            space0,
            tag_no_case("yarn"),
            space1,
            located(line, take_while1(is_name_char)),
        ));
        let Ok((_, (clause, _, _))) = (yarn_clause, space0, eof).parse(tail) else {
            let msg = "expected `, yarn NAME` or the end of the entry".to_string();
            return Err(src.error(ErrorKind::Syntax(msg), line.at(tail.trim())));
        };
        let mut yarn = None;
        if let Some((_, _, _, _, (name, name_pos))) = clause {
            let index = meta
                .yarn_index(name)
                .ok_or_else(|| src.error(ErrorKind::UnknownYarn(name.into()), name_pos))?;
            if matches!(kind, StitchKind::SlipFront | StitchKind::SlipBack) {
                warnings.push(src.warning(WarningKind::SlipYarnIgnored, name_pos));
            } else {
                yarn = Some(index);
            }
        }
        legend.entries.push(Entry {
            symbol,
            kind,
            yarn,
            pos: sym_pos,
        });
    }
    Ok((legend, warnings))
}

#[cfg(test)]
mod tests {
    use super::super::{document::split, meta};
    use super::*;

    fn legend(text: &str) -> Result<(Legend, Vec<Warning>)> {
        let src = Source::new(text, "t");
        let doc = split(&src)?;
        let (m, _) = meta::parse(&src, &doc.meta, "t")?;
        parse(&src, doc.legend.as_ref().expect("legend section"), &m)
    }

    #[test]
    fn names_and_yarns() {
        let text = "yarn MC: #000000\nyarn CC: #ffffff\nlegend:\n  . = knit\n  - = p\n  v = sl wyif\n  V = slip wyib\n  T = tuck\n  A = k, yarn CC\n";
        let (l, w) = legend(text).expect("valid legend");
        let kinds: Vec<StitchKind> = l.entries.iter().map(|e| e.kind).collect();
        use StitchKind::*;
        assert_eq!(kinds, vec![Knit, Purl, SlipFront, SlipBack, Tuck, Knit]);
        assert_eq!(l.get('A').and_then(|e| e.yarn), Some(1));
        assert!(w.is_empty());
    }

    #[test]
    fn knitt_is_not_knit() {
        let err = legend("legend:\n  . = knitt").expect_err("unknown");
        assert_eq!(err.kind, ErrorKind::UnknownStitch("knitt".into()));
        assert_eq!(err.loc.column, 7);
    }

    #[test]
    fn slip_yarn_is_a_warning() {
        let (l, w) = legend("yarn B: #111111\nlegend:\n  v = slip wyib, yarn B").expect("valid");
        assert_eq!(l.entries[0].yarn, None);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].loc.column, 23);
    }

    #[test]
    fn duplicates_and_empties() {
        let err = legend("legend:\n  . = knit\n  . = purl").expect_err("dup");
        assert_eq!(
            (err.kind, err.loc.line, err.loc.column),
            (ErrorKind::DuplicateSymbol('.'), 3, 3)
        );
        let err = legend("legend:\n  x =  ").expect_err("empty");
        assert_eq!(err.kind, ErrorKind::EmptyLegendEntry('x'));
    }
}
