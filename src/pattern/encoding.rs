//! Bytes to text: a pattern file is UTF-8.
//!
//! Editors on some systems still save Latin-1 (or another 8-bit code page),
//! and a single `×` in a gauge line is then one byte that is not UTF-8. The
//! file is refused, but like every other diagnostic the error points at the
//! line and column of that byte, so the knitter can find and retype it. A
//! UTF-8 byte-order mark is valid UTF-8 and is dropped later, by the parser
//! (`parse_str` accepts text with or without one).

use super::error::{ErrorKind, PatternError};
use super::model::SourceLoc;

/// The text of `bytes`, or an error at the first byte that is not UTF-8.
pub(crate) fn decode<'a>(bytes: &'a [u8], file: &str) -> Result<&'a str, PatternError> {
    std::str::from_utf8(bytes).map_err(|e| not_utf8(bytes, e.valid_up_to(), file))
}

fn not_utf8(bytes: &[u8], bad: usize, file: &str) -> PatternError {
    let (before, after) = bytes.split_at(bad.min(bytes.len()));
    let line_start = before.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    // `before` is valid UTF-8, so its last line counts in characters.
    let head = before.get(line_start..).unwrap_or_default();
    let column = String::from_utf8_lossy(head).chars().count() + 1;
    let line_end = after.iter().position(|&b| b == b'\n').map_or(bytes.len(), |i| bad + i);
    let text = bytes.get(line_start..line_end).unwrap_or_default();
    // The bad byte shows as one U+FFFD, so the caret stays under it.
    let excerpt = String::from_utf8_lossy(text).trim_end_matches('\r').to_string();
    let byte = after.first().copied().unwrap_or_default();
    let latin1 = if byte >= 0xa0 {
        format!(" ('{}' in Latin-1)", char::from(byte))
    } else {
        String::new()
    };
    PatternError {
        kind: ErrorKind::Encoding(format!("byte 0x{byte:02X}{latin1} here; save the file as UTF-8")),
        loc: SourceLoc {
            file: file.to_string(),
            line,
            column,
        },
        excerpt,
        span: 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_latin1_byte_is_located() {
        let bytes = b"name: x\ngauge: 24 sts \xd7 32 rows / 10 cm\n";
        let err = decode(bytes, "f.knit").expect_err("0xD7 alone is not UTF-8");
        assert!(matches!(err.kind, ErrorKind::Encoding(_)), "{err}");
        assert_eq!((err.loc.line, err.loc.column), (2, 15));
        assert_eq!(err.excerpt, "gauge: 24 sts \u{fffd} 32 rows / 10 cm");
        assert!(err.to_string().contains("0xD7 ('×' in Latin-1)"), "{err}");
    }

    #[test]
    fn columns_count_the_characters_before_the_byte() {
        let err = decode(b"\xc3\xa9\xc3\xa9\xff\r\nnext", "f").expect_err("0xFF");
        assert_eq!((err.loc.line, err.loc.column), (1, 3));
        assert_eq!(err.excerpt, "éé\u{fffd}");
        assert_eq!(decode(b"ok\n", "f").ok(), Some("ok\n"));
    }
}
