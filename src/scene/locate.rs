//! Where a key is in a scene file, for the checks that need more than one
//! value (which serde_json cannot locate once the file is read).
//!
//! The rules that compare two keys (`assign.stop_fraction` below
//! `assign.safety_fraction`) run after the typed parse. Their error points
//! at the first of the named keys found in the text: scene keys are unique
//! names, so a text search for `"key":` finds the one meant.

use super::SceneError;

/// An error at the value of the first of `keys` present in `text`, or
/// without a position when none is (the values are then the defaults).
pub(super) fn at_key(text: &[u8], path: &str, keys: &[&str], message: String) -> SceneError {
    let text = String::from_utf8_lossy(text);
    match keys.iter().find_map(|k| value_offset(&text, k)) {
        Some(offset) => {
            let head = text.get(..offset).unwrap_or_default();
            let line = head.matches('\n').count() + 1;
            let line_start = head.rfind('\n').map_or(0, |i| i + 1);
            let column = head.get(line_start..).map_or(1, |h| h.chars().count() + 1);
            SceneError::Parse {
                path: path.to_string(),
                line,
                column,
                message,
            }
        }
        None => SceneError::Invalid {
            path: path.to_string(),
            message,
        },
    }
}

/// Byte offset of the value after `"key"` and its colon.
fn value_offset(text: &str, key: &str) -> Option<usize> {
    let quoted = format!("\"{key}\"");
    let mut from = 0;
    while let Some(found) = text.get(from..)?.find(&quoted) {
        let after = from + found + quoted.len();
        let rest = text.get(after..)?;
        let trimmed = rest.trim_start();
        if let Some(value) = trimmed.strip_prefix(':') {
            let value_at = text.len() - value.trim_start().len();
            return Some(value_at);
        }
        from = after;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_present_key_is_located() {
        let text = b"{\n  \"assign\": {\n    \"safety_fraction\" :  0.01\n  }\n}";
        match at_key(text, "s.json", &["stop_fraction", "safety_fraction"], "m".into()) {
            SceneError::Parse { line, column, .. } => assert_eq!((line, column), (3, 26)),
            e => panic!("{e:?}"),
        }
        // A key named in a string value is not a key.
        let text = b"{\"note\": \"stop_fraction\", \"x\": 1}";
        assert!(matches!(
            at_key(text, "s.json", &["stop_fraction"], "m".into()),
            SceneError::Invalid { .. }
        ));
    }
}
