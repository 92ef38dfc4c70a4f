//! The parser must never panic: random bytes and random edits of valid
//! patterns may fail to parse, but only with an error at a line and column.

use knitsim::pattern::{parse_bytes, parse_str};
use proptest::prelude::*;

const SEEDS: [&str; 6] = [
    include_str!("../patterns/linen-stitch.knit"),
    include_str!("../patterns/mosaic.knit"),
    include_str!("../patterns/jacquard.knit"),
    include_str!("../patterns/tuck.knit"),
    include_str!("../patterns/garter.knit"),
    include_str!("../patterns/fig3-long-slip.knit"),
];

/// Characters that matter to the grammar, so mutations hit interesting paths.
const ALPHABET: &[char] = &[
    '[', ']', '|', '#', ':', ',', '.', '-', '=', ' ', '\t', '\n', '0', '1', '9', 'k', 'p', 'v', 'x', 'T', 'n', 'a',
    'é', '(', ')', 'R', 'S', 'W',
];

#[derive(Clone, Debug)]
enum Edit {
    Delete(usize),
    Insert(usize, char),
    Replace(usize, char),
    SwapLines(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let ch = prop::sample::select(ALPHABET);
    prop_oneof![
        any::<usize>().prop_map(Edit::Delete),
        (any::<usize>(), ch.clone()).prop_map(|(i, c)| Edit::Insert(i, c)),
        (any::<usize>(), ch).prop_map(|(i, c)| Edit::Replace(i, c)),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Edit::SwapLines(a, b)),
    ]
}

fn apply(text: &str, edit: &Edit) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    let n = chars.len().max(1);
    match *edit {
        Edit::Delete(i) if !chars.is_empty() => {
            chars.remove(i % n);
        }
        Edit::Insert(i, c) => chars.insert(i % (chars.len() + 1), c),
        Edit::Replace(i, c) if !chars.is_empty() => chars[i % n] = c,
        Edit::SwapLines(a, b) => {
            let mut lines: Vec<&str> = text.lines().collect();
            if !lines.is_empty() {
                let len = lines.len();
                lines.swap(a % len, b % len);
            }
            return lines.join("\n");
        }
        _ => {}
    }
    chars.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse_str(&text, "fuzz.knit");
    }

    #[test]
    fn random_bytes_fail_inside_the_file(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        // Not UTF-8 included: the error still has a line and column in the file.
        if let Err(err) = parse_bytes(&bytes, "fuzz.knit") {
            let lines = bytes.split(|&b| b == b'\n').count();
            prop_assert!(err.loc.line >= 1 && err.loc.line <= lines && err.loc.column >= 1, "{err}");
            let at = format!("fuzz.knit:{}:{}", err.loc.line, err.loc.column);
            prop_assert!(err.to_string().contains(&at), "{err}");
        }
    }

    #[test]
    fn mutated_patterns_never_panic(seed in 0..SEEDS.len(), edits in prop::collection::vec(edit(), 1..8)) {
        let text = edits.iter().fold(SEEDS[seed].to_string(), |t, e| apply(&t, e));
        if let Err(err) = parse_str(&text, "fuzz.knit") {
            // Errors must point inside the file (or at its first line).
            prop_assert!(err.loc.line >= 1 && err.loc.line <= text.lines().count().max(1), "{err}");
            let _ = err.to_string();
        }
    }

    #[test]
    fn grammar_soup_never_panics(chars in prop::collection::vec(prop::sample::select(ALPHABET), 0..300)) {
        let body: String = chars.into_iter().collect();
        for prefix in ["legend:\n  . = knit\nchart:\n  ", "width: 6\nwritten:\n  Row 1: ", ""] {
            let _ = parse_str(&format!("{prefix}{body}"), "soup.knit");
        }
    }
}
