//! First pass: split the file into metadata lines and sections.
//!
//! Layout rules (see patterns/README.md): unindented lines are `key: value`
//! metadata or a section header (`legend:`, `chart:`, `written:`); indented
//! lines belong to the section opened last. Blank lines and lines starting
//! with `#` are comments everywhere, so a chart may be spaced out freely.
//! Doing this split first lets every later stage see only its own lines.

use nom::bytes::complete::take_while1;
use nom::character::complete::{char, space0, space1};
use nom::combinator::opt;
use nom::sequence::preceded;
use nom::{IResult, Parser};

use super::error::ErrorKind;
use super::source::{Line, Pos, Result, Source};

/// `key: value` (or `yarn NAME: value`).
#[derive(Clone, Debug)]
pub(crate) struct MetaLine<'a> {
    pub line: Line<'a>,
    pub key: &'a str,
    pub key_pos: Pos,
    /// The word between key and colon, e.g. the yarn name in `yarn MC:`.
    pub arg: Option<(&'a str, Pos)>,
    /// Everything after the colon: a suffix of `line.text`.
    pub value: &'a str,
}

/// A section header and its indented body lines.
#[derive(Clone, Debug)]
pub(crate) struct Section<'a> {
    pub header: Pos,
    pub lines: Vec<Line<'a>>,
}

#[derive(Debug, Default)]
pub(crate) struct Document<'a> {
    pub meta: Vec<MetaLine<'a>>,
    pub legend: Option<Section<'a>>,
    pub chart: Option<Section<'a>>,
    pub written: Option<Section<'a>>,
}

pub(crate) fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '-'
}

/// `key [arg]:` and the rest of the line.
fn header(input: &str) -> IResult<&str, (&str, Option<&str>)> {
    let (rest, key) = take_while1(is_name_char).parse(input)?;
    let (rest, arg) = opt(preceded(space1, take_while1(is_name_char))).parse(rest)?;
    let (rest, _) = (space0, char(':')).parse(rest)?;
    Ok((rest, (key, arg)))
}

#[derive(Clone, Copy, PartialEq)]
enum Open {
    Meta,
    Legend,
    Chart,
    Written,
}

pub(crate) fn split<'a>(src: &Source<'a>) -> Result<Document<'a>> {
    let mut doc = Document::default();
    let mut open = Open::Meta;
    for &line in &src.lines {
        if line.is_ignorable() {
            continue;
        }
        if line.is_indented() {
            let section = match open {
                Open::Meta => None,
                Open::Legend => doc.legend.as_mut(),
                Open::Chart => doc.chart.as_mut(),
                Open::Written => doc.written.as_mut(),
            };
            match section {
                Some(section) => section.lines.push(line),
                None => {
                    let pos = line.pos(line.body(), 1);
                    let msg = "indented line outside a section (only legend, chart and written lines are indented)";
                    return Err(src.error(ErrorKind::Syntax(msg.into()), pos));
                }
            }
            continue;
        }
        let Ok((value, (key, arg))) = header(line.text) else {
            let msg = "expected `key: value` or a section header such as `chart:`";
            return Err(src.error(ErrorKind::Syntax(msg.into()), line.pos(line.text, 1)));
        };
        let key_pos = line.span(line.text, key);
        let arg = arg.map(|a| (a, line.at(a)));
        let section_slot = match key {
            "legend" => Some((&mut doc.legend, Open::Legend)),
            "chart" => Some((&mut doc.chart, Open::Chart)),
            "written" => Some((&mut doc.written, Open::Written)),
            _ => None,
        };
        match section_slot {
            Some((slot, which)) => {
                if slot.is_some() {
                    return Err(src.error(ErrorKind::DuplicateKey(key.into()), key_pos));
                }
                if !value.trim().is_empty() {
                    let msg = format!("`{key}:` starts a section; put its lines below it, indented");
                    return Err(src.error(ErrorKind::Syntax(msg), line.span(value.trim_start(), value.trim())));
                }
                *slot = Some(Section {
                    header: key_pos,
                    lines: Vec::new(),
                });
                open = which;
            }
            None => {
                doc.meta.push(MetaLine {
                    line,
                    key,
                    key_pos,
                    arg,
                    value,
                });
                open = Open::Meta;
            }
        }
    }
    Ok(doc)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sections_collect_indented_lines() {
        let text = "name: x\n# comment\nchart:\n  ..\n\n  ..\nwidth: 4\nlegend:\n  . = knit\n";
        let src = Source::new(text, "t");
        let doc = split(&src).expect("valid layout");
        assert_eq!(doc.meta.len(), 2);
        assert_eq!(doc.chart.as_ref().map(|s| s.lines.len()), Some(2));
        assert_eq!(doc.legend.as_ref().map(|s| s.header.line), Some(8));
    }

    #[test]
    fn yarn_argument_is_located() {
        let src = Source::new("yarn  MC : #ffffff", "t");
        let doc = split(&src).expect("valid");
        let (name, pos) = doc.meta[0].arg.expect("arg");
        assert_eq!((name, pos.col, pos.len), ("MC", 7, 2));
    }

    #[test]
    fn stray_indent_is_an_error() {
        let src = Source::new("name: x\n  oops", "t");
        let err = split(&src).expect_err("indented meta");
        assert_eq!((err.loc.line, err.loc.column), (2, 3));
    }
}
