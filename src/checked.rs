//! Range checks on scene numbers, run while the JSON is read.
//!
//! serde_json knows the line and column only while it is reading, so a value
//! that is a number but not a usable one (a zero stiffness, a negative
//! radius) is refused right there: the fields of the scene's parameter types
//! name these functions in `#[serde(deserialize_with = ...)]`, and the error
//! they return comes out of `serde_json` with the position of the value.
//! JSON itself has no NaN or infinity; `"nan"` (a string) is a type error
//! and `1e999` is out of range, both also located by serde_json.

use std::fmt;

use serde::de::{Deserializer, Error, Unexpected, Visitor};

/// A JSON number; the messages say "a number" rather than Rust's `f64`, and
/// a string that spells NaN or infinity is told why it cannot be one.
struct Number;

impl Visitor<'_> for Number {
    type Value = f64;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number")
    }

    fn visit_f64<E: Error>(self, v: f64) -> Result<f64, E> {
        Ok(v)
    }

    fn visit_i64<E: Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }

    fn visit_u64<E: Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }

    fn visit_str<E: Error>(self, v: &str) -> Result<f64, E> {
        match v.trim().parse::<f64>() {
            Ok(x) if !x.is_finite() => Err(E::custom(format!(
                "expected a finite number, got the string {v:?} (JSON has no NaN or infinity)"
            ))),
            _ => Err(E::invalid_type(Unexpected::Str(v), &self)),
        }
    }
}

/// A number, by the messages of [`Number`].
pub fn number<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    d.deserialize_any(Number)
}

fn checked<'de, D: Deserializer<'de>>(d: D, ok: fn(f64) -> bool, what: &str) -> Result<f64, D::Error> {
    let v = number(d)?;
    if ok(v) {
        Ok(v)
    } else {
        Err(D::Error::custom(format!("expected {what}, got {v}")))
    }
}

/// A finite number above zero (stiffnesses, radii, densities).
pub fn positive<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    checked(d, |v| v.is_finite() && v > 0.0, "a number above 0")
}

/// A finite number, zero or above (friction coefficients, fractions that
/// may switch a feature off).
pub fn non_negative<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    checked(d, |v| v.is_finite() && v >= 0.0, "a number, 0 or above")
}

/// `null`, or a number checked by `$inner`.
macro_rules! optional {
    ($(#[$doc:meta])* $name:ident, $inner:ident, $what:literal) => {
        $(#[$doc])*
        pub fn $name<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
            struct Optional;
            impl<'de> Visitor<'de> for Optional {
                type Value = Option<f64>;
                fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                    f.write_str($what)
                }
                fn visit_none<E: Error>(self) -> Result<Self::Value, E> {
                    Ok(None)
                }
                fn visit_unit<E: Error>(self) -> Result<Self::Value, E> {
                    Ok(None)
                }
                fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
                    $inner(d).map(Some)
                }
            }
            d.deserialize_option(Optional)
        }
    };
}

optional!(
    /// `null` or a finite number above zero.
    optional_positive,
    positive,
    "null or a number above 0"
);
optional!(
    /// `null` or a finite number, zero or above.
    optional_non_negative,
    non_negative,
    "null or a number, 0 or above"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    struct T {
        #[serde(deserialize_with = "positive")]
        a: f64,
        #[serde(deserialize_with = "non_negative")]
        b: f64,
    }

    #[test]
    fn out_of_range_values_are_errors_at_the_value() {
        let ok: T = serde_json::from_str(r#"{"a": 1.5, "b": 0}"#).unwrap();
        assert_eq!((ok.a, ok.b), (1.5, 0.0));
        let e = serde_json::from_str::<T>("{\n  \"a\": 0,\n  \"b\": 1\n}").unwrap_err();
        assert_eq!((e.line(), e.column()), (2, 8), "{e}");
        assert!(e.to_string().contains("expected a number above 0, got 0"), "{e}");
        let e = serde_json::from_str::<T>(r#"{"a": 1, "b": -0.5}"#).unwrap_err();
        assert_eq!((e.line(), e.column()), (1, 19), "{e}");
    }

    #[test]
    fn strings_and_other_types_are_not_numbers() {
        let e = serde_json::from_str::<T>(r#"{"a": "nan", "b": 1}"#).unwrap_err();
        assert!(e.to_string().contains("JSON has no NaN or infinity"), "{e}");
        assert_eq!(e.line(), 1, "{e}");
        let e = serde_json::from_str::<T>(r#"{"a": 1, "b": "-Infinity"}"#).unwrap_err();
        assert!(e.to_string().contains("JSON has no NaN or infinity"), "{e}");
        let e = serde_json::from_str::<T>(r#"{"a": true, "b": 1}"#).unwrap_err();
        assert!(
            e.to_string()
                .contains("invalid type: boolean `true`, expected a number"),
            "{e}"
        );
        let e = serde_json::from_str::<T>(r#"{"a": "1", "b": 1}"#).unwrap_err();
        assert!(e.to_string().contains("expected a number"), "{e}");
    }
}
