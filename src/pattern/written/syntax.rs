//! Written-row grammar (KnitSpeak-like), one row instruction per line:
//!
//! ```text
//! Row 1 (RS): k1, [sl1 wyif, k1] to last st, k1.
//! Rows 2 and 4 (WS), with CC: purl.
//! Rows 5-8: [k2, p2] to end.
//! ```
//!
//! nom parses the tokens; the comma lists and brackets are walked by hand so
//! that a failure points at the item that is wrong rather than at wherever
//! nom's backtracking gave up. Brackets nest at most [`MAX_DEPTH`] deep: the
//! grammar is recursive and the parser must not overflow the stack on
//! adversarial input.

use nom::branch::alt;
use nom::bytes::complete::{tag_no_case, take_while1};
use nom::character::complete::{char, digit1, space0, space1};
use nom::combinator::{eof, opt, value};
use nom::sequence::{delimited, preceded};
use nom::{IResult, Parser};

use super::super::document::is_name_char;
use super::super::model::Worked;
use super::super::source::{located, Line, Pos};

const MAX_DEPTH: usize = 4;

/// How many times an instruction or bracket is worked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Count {
    Times(usize),
    /// Repeat until this many stitches are left (`to end` leaves 0).
    UntilLeft(usize),
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Item {
    /// `bare`: written without a count (`purl.`), which alone on a row means
    /// across the whole row.
    Op {
        worked: Worked,
        count: Count,
        bare: bool,
        pos: Pos,
    },
    Group {
        items: Vec<Item>,
        count: Count,
        pos: Pos,
    },
}

#[derive(Clone, Debug)]
pub(crate) struct RowLine<'a> {
    pub label_pos: Pos,
    /// Inclusive row-number ranges with the position of their first number.
    pub rows: Vec<(usize, usize, Pos)>,
    pub side: Option<(&'a str, Pos)>,
    pub yarn: Option<(&'a str, Pos)>,
    pub items: Vec<Item>,
}

/// A parse failure: where, and what was expected there.
#[derive(Debug)]
pub(crate) struct Fail<'a> {
    pub at: &'a str,
    pub expected: String,
}

type Step<'a, T> = std::result::Result<(&'a str, T), Fail<'a>>;

fn fail<'a, T>(at: &'a str, expected: &str) -> std::result::Result<T, Fail<'a>> {
    Err(Fail {
        at,
        expected: expected.to_string(),
    })
}

fn number(input: &str) -> IResult<&str, usize> {
    digit1.map_res(str::parse::<usize>).parse(input)
}

fn to_clause(input: &str) -> IResult<&str, Count> {
    let stitches = alt((
        tag_no_case("stitches"),
        tag_no_case("stitch"),
        tag_no_case("sts"),
        tag_no_case("st"),
    ));
    let last =
        (tag_no_case("last"), space1, opt((number, space1)), stitches).map(|(_, _, n, _)| n.map_or(1, |(n, _)| n));
    preceded(
        (tag_no_case("to"), space1),
        alt((
            value(Count::UntilLeft(0), tag_no_case("end")),
            last.map(Count::UntilLeft),
        )),
    )
    .parse(input)
}

fn times_clause(input: &str) -> IResult<&str, Count> {
    alt((
        (number, space0, tag_no_case("times")).map(|(n, _, _)| Count::Times(n)),
        value(Count::Times(2), tag_no_case("twice")),
        value(Count::Times(1), tag_no_case("once")),
        to_clause,
    ))
    .parse(input)
}

/// A stitch instruction as worked on the needle, with its optional count.
fn op(input: &str) -> IResult<&str, (Worked, Option<usize>)> {
    let word = |long: &'static str, short: &'static str| alt((tag_no_case(long), tag_no_case(short)));
    let wy = alt((
        value(Worked::SlipWyif, tag_no_case("wyif")),
        value(Worked::SlipWyib, tag_no_case("wyib")),
    ));
    alt((
        (word("knit", "k"), opt(number)).map(|(_, n)| (Worked::Knit, n)),
        (word("purl", "p"), opt(number)).map(|(_, n)| (Worked::Purl, n)),
        (word("slip", "sl"), opt(number), space1, wy).map(|(_, n, _, w)| (w, n)),
        (word("tuck", "tk"), opt(number)).map(|(_, n)| (Worked::Tuck, n)),
    ))
    .parse(input)
}

struct Walker<'a> {
    line: Line<'a>,
}

impl<'a> Walker<'a> {
    fn items(&self, input: &'a str, depth: usize) -> Step<'a, Vec<Item>> {
        let (mut rest, first) = self.item(input, depth)?;
        let mut items = vec![first];
        while let Ok((after, _)) = (space0::<&str, nom::error::Error<&str>>, char(','), space0).parse(rest) {
            let (next, item) = self.item(after, depth)?;
            items.push(item);
            rest = next;
        }
        Ok((rest, items))
    }

    fn item(&self, input: &'a str, depth: usize) -> Step<'a, Item> {
        let pos = self.line.pos(input, 1);
        if let Ok((inside, _)) = (char::<&str, nom::error::Error<&str>>('['), space0).parse(input) {
            if depth >= MAX_DEPTH {
                return fail(input, &format!("at most {MAX_DEPTH} nested brackets"));
            }
            let (rest, items) = self.items(inside, depth + 1)?;
            let Ok((rest, _)) = (space0::<&str, nom::error::Error<&str>>, char(']')).parse(rest) else {
                return fail(rest.trim_start(), "`,` or `]`");
            };
            let Ok((rest, count)) = preceded(space0, times_clause).parse(rest) else {
                return fail(rest.trim_start(), "`N times`, `to end` or `to last N sts` after `]`");
            };
            return Ok((rest, Item::Group { items, count, pos }));
        }
        let expected = "an instruction such as k2, p1, sl1 wyif, sl1 wyib, tuck or [k1, p1] 3 times";
        let Ok((rest, ((worked, n), op_pos))) = located(self.line, op).parse(input) else {
            return fail(input, expected);
        };
        if rest.starts_with(|c: char| c.is_alphanumeric()) {
            return fail(input, expected);
        }
        let (rest, until) = opt(preceded(space1, to_clause)).parse(rest).unwrap_or((rest, None));
        let count = match (n, until) {
            (Some(_), Some(_)) => return fail(input, "a count or `to end`, not both"),
            (Some(n), None) => Count::Times(n),
            (None, Some(until)) => until,
            (None, None) => Count::Times(1),
        };
        Ok((
            rest,
            Item::Op {
                worked,
                count,
                bare: n.is_none() && until.is_none(),
                pos: op_pos,
            },
        ))
    }

    /// `Row 1`, `Rows 2 and 4`, `Rows 3-6, 9`: inclusive ranges.
    fn numbers(&self, input: &'a str) -> Step<'a, Vec<(usize, usize, Pos)>> {
        let mut rows = Vec::new();
        let mut rest = input;
        loop {
            let dash = preceded((space0, char('-'), space0), number);
            let range: IResult<&str, _> = (located(self.line, number), opt(dash)).parse(rest);
            let Ok((after, ((first, pos), last))) = range else {
                return fail(rest, "a row number");
            };
            let last = last.unwrap_or(first);
            if last < first {
                return fail(rest, "a rising range such as 3-6");
            }
            rows.push((first, last, pos));
            rest = after;
            let comma = (space0, char(','), space0, opt((tag_no_case("and"), space1))).map(|_| ());
            let and = (space1, tag_no_case("and"), space1).map(|_| ());
            // A separator counts only if a number follows: `Rows 3-4, with CC:`.
            let separator: IResult<&str, ()> = alt((comma, and)).parse(rest);
            match separator {
                Ok((after, ())) if after.starts_with(|c: char| c.is_ascii_digit()) => rest = after,
                _ => return Ok((rest, rows)),
            }
        }
    }

    fn row(&self, input: &'a str) -> Step<'a, RowLine<'a>> {
        let label = (alt((tag_no_case("rows"), tag_no_case("row"))), space1);
        let Ok((rest, (_, label_pos))) = located(self.line, label).parse(input) else {
            return fail(input, "`Row N:` or `Rows N-M:`");
        };
        let (rest, rows) = self.numbers(rest)?;
        let side = preceded(
            space0,
            delimited(
                char('('),
                located(self.line, alt((tag_no_case("RS"), tag_no_case("WS")))),
                char(')'),
            ),
        );
        let (rest, side) = opt(side).parse(rest).unwrap_or((rest, None));
        let with = (
            space0,
            opt(char(',')),
            space0,
            alt((tag_no_case("with"), tag_no_case("in"))),
            space1,
        );
        let yarn = preceded(with, located(self.line, take_while1(is_name_char)));
        let (rest, yarn) = opt(yarn).parse(rest).unwrap_or((rest, None));
        let Ok((rest, _)) = (space0::<&str, nom::error::Error<&str>>, char(':'), space0).parse(rest) else {
            return fail(rest.trim_start(), "`:` after the row label");
        };
        let (rest, items) = self.items(rest, 0)?;
        let Ok((rest, _)) = (space0::<&str, nom::error::Error<&str>>, opt(char('.')), space0, eof).parse(rest) else {
            return fail(rest.trim_start(), "`,` or the end of the row");
        };
        Ok((
            rest,
            RowLine {
                label_pos: Pos { len: 1, ..label_pos },
                rows,
                side,
                yarn,
                items,
            },
        ))
    }
}

/// Parses one written-row line.
pub(crate) fn row_line<'a>(line: Line<'a>) -> std::result::Result<RowLine<'a>, Fail<'a>> {
    Walker { line }.row(line.body()).map(|(_, row)| row)
}
