//! Shared test fixtures: the structures every stage must handle.
#![allow(dead_code)]

use knitsim::pattern::{Construction, Pattern};
use knitsim::topology::sample::{chart_pattern, tile};

/// A named structure: stitch tile and optional colour tile, top row first.
pub type Structure = (&'static str, Vec<&'static str>, Option<Vec<&'static str>>);

/// The structures the project ships.
pub fn structures() -> Vec<Structure> {
    vec![
        ("stockinette", vec!["k"], None),
        ("garter", vec!["p", "k"], None),
        ("rib 1x1", vec!["kp"], None),
        ("rib 2x2", vec!["kkpp"], None),
        ("seed", vec!["pk", "kp"], None),
        ("linen", vec!["vk", "kv"], None),
        ("honeycomb", vec!["kkkk", "kwkw", "kkkk", "wkwk"], None),
        (
            "mosaic",
            vec!["kkkk", "kwkw", "kkkk", "wkwk"],
            Some(vec!["1111", "1111", "0000", "0000"]),
        ),
        ("tuck", vec!["kkkk", "ktkt", "kkkk", "tktk"], None),
        ("jacquard", vec!["k"], Some(vec!["0110", "1001", "0011", "1100"])),
    ]
}

pub fn pattern(t: &[&str], c: Option<&[&str]>, cons: Construction, w: usize, h: usize) -> Pattern {
    let st = tile(t, w, h);
    let st: Vec<&str> = st.iter().map(String::as_str).collect();
    let cl = c.map(|c| tile(c, w, h));
    let cl: Option<Vec<&str>> = cl.as_ref().map(|c| c.iter().map(String::as_str).collect());
    chart_pattern(&st, cl.as_deref(), cons).expect("chart")
}
