//! `yarn NAME:` lines: colour, size and material, in any order.
//!
//! Fields are separated by commas: `#rrggbb`, `radius N mm` or
//! `diameter N mm`, and a material (words without digits). A field whose
//! first word is `radius` or `diameter` is always a size, so `radius nan mm`
//! is a bad size, never a material. A decimal comma (`radius 0,6 mm`) would
//! split the size in two; it is recognised (a digit on each side of a
//! comma) and the error suggests `0.6`.

use nom::combinator::eof;
use nom::number::complete::double;
use nom::Parser;

use super::document::MetaLine;
use super::error::ErrorKind;
use super::source::{positive, syntax};
use super::source::{Line, Pos, Result, Source};

#[derive(Debug)]
pub(crate) struct PendingYarn {
    pub name: String,
    pub pos: Pos,
    pub color: [u8; 3],
    pub radius: Option<(f64, Pos)>,
    pub material: Option<String>,
}

fn parse_colour(src: &Source, line: Line, field: &str) -> Result<[u8; 3]> {
    let bad = || src.error(ErrorKind::BadColour(field.to_string()), line.at(field));
    let hex = field.strip_prefix('#').ok_or_else(bad)?;
    if hex.len() != 6 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(bad());
    }
    let channel = |i: usize| {
        hex.get(i..i + 2)
            .and_then(|h| u8::from_str_radix(h, 16).ok())
            .ok_or_else(bad)
    };
    Ok([channel(0)?, channel(2)?, channel(4)?])
}

pub(crate) fn parse_yarn(src: &Source, m: &MetaLine) -> Result<PendingYarn> {
    let line = m.line;
    let Some((name, pos)) = m.arg else {
        let msg = "name the yarn: `yarn MC: #d9cfc1, radius 0.75 mm`".to_string();
        return Err(src.error(ErrorKind::BadYarn(msg), m.key_pos));
    };
    let mut yarn = PendingYarn {
        name: name.to_string(),
        pos,
        color: [0xd9, 0xcf, 0xc1],
        radius: None,
        material: None,
    };
    if let Some(number) = decimal_comma(m.value) {
        let msg = format!(
            "`{number}` has a decimal comma; write `{}` (commas separate the yarn's fields)",
            number.replace(',', ".")
        );
        return Err(src.error(ErrorKind::BadYarn(msg), line.at(number)));
    }
    let mut have_colour = false;
    for raw in m.value.split(',') {
        let field = raw.trim();
        if field.is_empty() {
            return Err(syntax(
                src,
                line,
                raw,
                "a yarn field (#rrggbb, radius N mm, or a material)",
            ));
        }
        let twice = |what: &str| src.error(ErrorKind::BadYarn(format!("{what} given twice")), line.at(field));
        let first_word = field.split_whitespace().next().unwrap_or_default();
        if field.starts_with('#') {
            if have_colour {
                return Err(twice("colour"));
            }
            yarn.color = parse_colour(src, line, field)?;
            have_colour = true;
        } else if ["radius", "diameter"]
            .iter()
            .any(|w| first_word.eq_ignore_ascii_case(w))
        {
            if yarn.radius.is_some() {
                return Err(twice("size"));
            }
            yarn.radius = Some(parse_size(src, line, field)?);
        } else if field.starts_with(|c: char| c.is_ascii_alphabetic()) && !field.contains(|c: char| c.is_ascii_digit())
        {
            if yarn.material.is_some() {
                return Err(twice("material"));
            }
            yarn.material = Some(field.to_string());
        } else {
            return Err(syntax(
                src,
                line,
                raw,
                "`radius 0.75 mm`, `diameter 1.5 mm` or a material",
            ));
        }
    }
    Ok(yarn)
}

/// A number written with a decimal comma (`0,6`) in a yarn line, whose
/// fields are separated by commas; no valid field has a digit on each side
/// of a comma.
fn decimal_comma(value: &str) -> Option<&str> {
    let bytes = value.as_bytes();
    let comma = (1..bytes.len().saturating_sub(1)).find(|&i| {
        bytes.get(i) == Some(&b',')
            && bytes.get(i - 1).is_some_and(u8::is_ascii_digit)
            && bytes.get(i + 1).is_some_and(u8::is_ascii_digit)
    })?;
    let is_part = |b: &u8| b.is_ascii_digit() || *b == b'.';
    let start = bytes
        .get(..comma)?
        .iter()
        .rposition(|b| !is_part(b))
        .map_or(0, |i| i + 1);
    let end = bytes
        .get(comma + 1..)?
        .iter()
        .position(|b| !is_part(b))
        .map_or(bytes.len(), |i| comma + 1 + i);
    value.get(start..end)
}

/// `radius N mm` or `diameter N mm` (the first word already checked): the
/// radius in metres and the position of the number. Anything but a positive
/// finite number of millimetres is an error at the number.
fn parse_size(src: &Source, line: Line, field: &str) -> Result<(f64, Pos)> {
    let (which, rest) = field.split_at(field.find(char::is_whitespace).unwrap_or(field.len()));
    let body = rest.trim();
    let unit = body.len().checked_sub(2).filter(|&i| body.is_char_boundary(i));
    let number = match unit.and_then(|i| body.split_at_checked(i)) {
        Some((number, mm)) if mm.eq_ignore_ascii_case("mm") => number.trim_end(),
        _ => {
            let at = if body.is_empty() { field } else { body };
            let msg = format!(
                "give the {} in millimetres, e.g. `{} 0.75 mm`",
                which.to_ascii_lowercase(),
                which
            );
            return Err(src.error(ErrorKind::BadYarn(msg), line.at(at)));
        }
    };
    if number.is_empty() {
        return Err(syntax(src, line, body, "a number of millimetres before `mm`"));
    }
    let pos = line.at(number);
    let parsed = match (double::<&str, nom::error::Error<&str>>, eof).parse(number) {
        Ok((_, (value, _))) => value,
        Err(_) => {
            let msg = format!("`{number}` is not a number (write e.g. `{which} 0.75 mm`)");
            return Err(src.error(ErrorKind::BadYarn(msg), pos));
        }
    };
    let what = which.to_ascii_lowercase();
    let mm = positive(parsed, &what).map_err(|e| src.error(ErrorKind::BadYarn(e), pos))?;
    let radius_mm = if what == "diameter" { mm / 2.0 } else { mm };
    Ok((radius_mm * 1e-3, pos))
}

#[cfg(test)]
mod tests {
    use super::super::document::split;
    use super::*;

    fn yarn(text: &str) -> Result<PendingYarn> {
        let src = Source::new(text, "t.knit");
        let doc = split(&src)?;
        let m = doc.meta.first().expect("one metadata line");
        parse_yarn(&src, m)
    }

    #[test]
    fn yarn_fields() {
        let y = yarn("yarn CC: #FF8000, diameter 1.2 mm, merino wool").expect("yarn");
        assert_eq!((y.name.as_str(), y.color), ("CC", [255, 128, 0]));
        assert!(y.radius.is_some_and(|(r, _)| (r - 0.6e-3).abs() < 1e-12));
        assert_eq!(y.material.as_deref(), Some("merino wool"));
    }

    #[test]
    fn bad_yarn_sizes_point_at_the_number() {
        for (text, column, hint) in [
            ("yarn MC: radius nan mm", 17, "positive"),
            ("yarn MC: radius inf mm, wool", 17, "positive"),
            ("yarn MC: #ffffff, radius -1 mm", 26, "positive"),
            ("yarn MC: radius 0 mm", 17, "positive"),
            ("yarn MC: Diameter NaN mm", 19, "positive"),
            ("yarn MC: radius 0,6 mm, cotton", 17, "write `0.6`"),
            ("yarn MC: radius abc mm", 17, "not a number"),
            ("yarn MC: radius 0.6", 17, "millimetres"),
        ] {
            let err = yarn(text).expect_err(text);
            assert!(matches!(err.kind, ErrorKind::BadYarn(_)), "{text}: {err}");
            assert_eq!((err.loc.line, err.loc.column), (1, column), "{text}: {err}");
            assert!(err.to_string().contains(hint), "{text}: {err}");
        }
    }

    #[test]
    fn materials_are_words_and_sizes_are_numbers() {
        for (text, material, radius_mm) in [
            ("yarn MC: cotton", Some("cotton"), None),
            ("yarn MC: #102030, merino wool", Some("merino wool"), None),
            ("yarn MC: radius 0.6mm, wool", Some("wool"), Some(0.6)),
            ("yarn MC: RADIUS 0.5 MM", None, Some(0.5)),
            ("yarn MC: diameter 1.4 mm, nan", Some("nan"), Some(0.7)),
        ] {
            let y = yarn(text).expect(text);
            assert_eq!(y.material.as_deref(), material, "{text}");
            let radius = y.radius.map(|(r, _)| r * 1e3);
            assert_eq!(radius.is_some(), radius_mm.is_some(), "{text}");
            if let (Some(r), Some(expected)) = (radius, radius_mm) {
                assert!((r - expected).abs() < 1e-12, "{text}: {r}");
            }
        }
    }

    #[test]
    fn bad_colour_is_located() {
        let err = yarn("yarn A: #12345g").expect_err("g is not hex");
        assert!(matches!(err.kind, ErrorKind::BadColour(_)));
        assert_eq!(err.loc.column, 9);
    }
}
