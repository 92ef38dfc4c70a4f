//! Source lines and positions.
//!
//! The format is line oriented, so the parser works one line at a time and
//! nom sees only that line. A position is recovered from the unparsed rest of
//! the line (always a suffix of it), which keeps nom's plain `&str` input and
//! still gives exact columns. Columns count characters, not bytes, so a
//! caret lands under a non-ASCII symbol correctly.

use nom::{IResult, Parser};

use super::error::{ErrorKind, PatternError, Site, Warning, WarningKind};
use super::model::SourceLoc;

/// A 1-based line/column with the number of characters to underline.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub(crate) struct Pos {
    pub line: usize,
    pub col: usize,
    pub len: usize,
}

/// One source line: its 1-based number and its text (no line terminator).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Line<'a> {
    pub number: usize,
    pub text: &'a str,
}

impl<'a> Line<'a> {
    /// Position of `rest`, a suffix of this line, spanning `len` characters.
    pub fn pos(&self, rest: &str, len: usize) -> Pos {
        let offset = self.text.len().saturating_sub(rest.len());
        let col = self.text.get(..offset).map_or(offset, |head| head.chars().count()) + 1;
        Pos {
            line: self.number,
            col,
            len,
        }
    }

    /// Position of `rest` spanning the characters of `token`.
    pub fn span(&self, rest: &str, token: &str) -> Pos {
        self.pos(rest, token.chars().count())
    }

    /// Position of `token`, a sub-slice of this line, spanning its characters.
    pub fn at(&self, token: &str) -> Pos {
        let offset = (token.as_ptr() as usize).saturating_sub(self.text.as_ptr() as usize);
        let rest = self.text.get(offset..).unwrap_or("");
        self.pos(rest, token.chars().count())
    }

    /// Text after the leading whitespace.
    pub fn body(&self) -> &'a str {
        self.text.trim_start()
    }

    pub fn is_indented(&self) -> bool {
        self.text.starts_with([' ', '\t'])
    }

    /// Blank lines and lines whose first visible character is `#`.
    pub fn is_ignorable(&self) -> bool {
        let body = self.body();
        body.is_empty() || body.starts_with('#')
    }
}

/// The file being parsed: its name for locations and its lines for excerpts.
pub(crate) struct Source<'a> {
    pub file: &'a str,
    pub lines: Vec<Line<'a>>,
}

impl<'a> Source<'a> {
    pub fn new(text: &'a str, file: &'a str) -> Self {
        let lines = text
            .lines()
            .enumerate()
            .map(|(i, text)| Line { number: i + 1, text })
            .collect();
        Source { file, lines }
    }

    fn excerpt(&self, line: usize) -> String {
        line.checked_sub(1)
            .and_then(|i| self.lines.get(i))
            .map_or_else(String::new, |l| l.text.to_string())
    }

    fn loc(&self, pos: Pos) -> SourceLoc {
        SourceLoc {
            file: self.file.to_string(),
            line: pos.line,
            column: pos.col,
        }
    }

    pub fn error(&self, kind: ErrorKind, pos: Pos) -> PatternError {
        PatternError {
            kind,
            loc: self.loc(pos),
            excerpt: self.excerpt(pos.line),
            span: pos.len,
        }
    }

    /// Where `pos` is, for a warning that a later stage may raise.
    pub fn site(&self, pos: Pos) -> Site {
        Site {
            loc: self.loc(pos),
            excerpt: self.excerpt(pos.line),
            span: pos.len,
        }
    }

    pub fn warning(&self, kind: WarningKind, pos: Pos) -> Warning {
        Warning {
            kind,
            loc: self.loc(pos),
            excerpt: self.excerpt(pos.line),
            span: pos.len,
        }
    }

    /// Where "the whole file" errors point: the first line.
    pub fn start(&self) -> Pos {
        Pos {
            line: 1,
            col: 1,
            len: 1,
        }
    }
}

/// Wraps a nom parser so that it also returns the position of what it consumed.
pub(crate) fn located<'a, O, P>(line: Line<'a>, mut parser: P) -> impl FnMut(&'a str) -> IResult<&'a str, (O, Pos)>
where
    P: Parser<&'a str, Output = O, Error = nom::error::Error<&'a str>>,
{
    move |input: &'a str| {
        let (rest, out) = parser.parse(input)?;
        let used = input.len().saturating_sub(rest.len());
        let len = input.get(..used).map_or(used, |s| s.chars().count());
        Ok((rest, (out, line.pos(input, len))))
    }
}

/// Shorthand for a located result inside the parser.
pub(crate) type Result<T> = std::result::Result<T, PatternError>;

/// A syntax error at the first token of `at` (or its start when blank):
/// "expected {expected}".
pub(super) fn syntax(src: &Source, line: Line, at: &str, expected: &str) -> PatternError {
    let token = at.trim();
    let pos = if token.is_empty() {
        line.pos(at, 1)
    } else {
        line.at(token)
    };
    src.error(ErrorKind::Syntax(format!("expected {expected}")), pos)
}

/// `value` when it is a positive finite number, else a message naming `what`.
pub(super) fn positive(value: f64, what: &str) -> std::result::Result<f64, String> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(format!("{what} must be a positive number, got {value}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_count_characters() {
        let line = Line {
            number: 4,
            text: "  ·x",
        };
        let rest = &line.text[4..]; // after two spaces and the two-byte '·'
        assert_eq!(rest, "x");
        assert_eq!(
            line.pos(rest, 1),
            Pos {
                line: 4,
                col: 4,
                len: 1
            }
        );
    }

    #[test]
    fn excerpt_is_the_line() {
        let src = Source::new("a\r\nbcd\n", "f.knit");
        let err = src.error(
            ErrorKind::MissingChart,
            Pos {
                line: 2,
                col: 2,
                len: 1,
            },
        );
        assert_eq!(err.excerpt, "bcd");
        assert_eq!((err.loc.line, err.loc.column), (2, 2));
    }
}
