//! Reading a scene must never panic: random edits of a valid scene (flipped
//! bytes, truncation, numbers replaced by NaN, infinities, negatives or
//! values of another type) either still read or fail with an error that
//! names the file, line and column.

use knitsim::scene::{parse_params, SceneError, Shape};
use knitsim::sim::SimParams;
use proptest::prelude::*;
use std::path::Path;

const SEED: &str = r#"{
  "rod": {"radius": 0.0006, "ks": 80.0, "kb": 2e-7, "rho": 0.0005, "mu": 0.25, "kf": 1000},
  "radii": "uniform",
  "assign": {"safety_fraction": 0.1, "stop_fraction": 0.05, "close_fraction": 1e-5},
  "terms": {"gravity": true, "friction": false},
  "obstacles": [
    {"type": "sphere", "center": [0.0, 0.0, -0.05], "radius": 0.05},
    {"type": "plane", "point": [0, 0, -0.1], "normal": [0, 0.2, 1]},
    {"type": "box", "center": [0, 0, -0.2], "half_extents": [0.1, 0.1, 0.05]}
  ],
  "obstacle_stiffness": 1e5,
  "contact": {"mode": "penalty", "thickness": 0.0012, "penalty_stiffness": 1000},
  "separation": {"kinds": ["Layer"], "min_pull": 0.01}
}
"#;

/// Replacements for a number: bad values, values of other types, edge cases.
const VALUES: &[&str] = &[
    "\"nan\"",
    "\"NaN\"",
    "\"inf\"",
    "\"-infinity\"",
    "nan",
    "NaN",
    "-1",
    "0",
    "-0.0",
    "1e999",
    "-1e999",
    "1e-320",
    "true",
    "null",
    "{}",
    "[]",
    "[0, 0, 0]",
    "\"x\"",
    "1.5",
    "12345678901234567890123",
];

#[derive(Clone, Debug)]
enum Edit {
    Flip(usize, u8),
    Truncate(usize),
    Delete(usize),
    Insert(usize, u8),
    /// The `n`-th number in the text becomes `VALUES[v]`.
    Number(usize, usize),
    /// The `n`-th number in the text becomes this one.
    Float(usize, f64),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Edit::Flip(i, b)),
        any::<usize>().prop_map(Edit::Truncate),
        any::<usize>().prop_map(Edit::Delete),
        (any::<usize>(), prop::sample::select(b"{}[]\",:-.0e9 tn".as_slice())).prop_map(|(i, b)| Edit::Insert(i, b)),
        (any::<usize>(), 0..VALUES.len()).prop_map(|(n, v)| Edit::Number(n, v)),
        (any::<usize>(), any::<f64>()).prop_map(|(n, x)| Edit::Float(n, x)),
    ]
}

/// Byte ranges of the numbers in `text`.
fn numbers(text: &[u8]) -> Vec<(usize, usize)> {
    let is_number = |b: u8| b.is_ascii_digit() || b"+-.eE".contains(&b);
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        if text[i].is_ascii_digit() || text[i] == b'-' {
            let start = i;
            while i < text.len() && is_number(text[i]) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

fn apply(mut text: Vec<u8>, edit: &Edit) -> Vec<u8> {
    let n = text.len().max(1);
    let replace = |mut text: Vec<u8>, k: usize, value: &str| {
        let spans = numbers(&text);
        if let Some(&(a, b)) = spans.get(k % spans.len().max(1)) {
            text.splice(a..b, value.bytes());
        }
        text
    };
    match *edit {
        Edit::Flip(i, b) if !text.is_empty() => text[i % n] ^= b,
        Edit::Truncate(i) => text.truncate(i % n),
        Edit::Delete(i) if !text.is_empty() => {
            text.remove(i % n);
        }
        Edit::Insert(i, b) => text.insert(i % (text.len() + 1), b),
        Edit::Number(k, v) => return replace(text, k, VALUES[v]),
        Edit::Float(k, x) => return replace(text, k, &format!("{x:?}")),
        _ => {}
    }
    text
}

/// What a scene that reads must hold: usable physical values.
fn usable(p: &SimParams) -> bool {
    let r = &p.rod;
    let positive = [r.radius, r.ks, r.kb, r.rho, r.kc_factor, p.obstacle_stiffness];
    let obstacles = p.obstacles.iter().all(|s| match s {
        Shape::Sphere { radius, .. } => radius.is_finite() && *radius > 0.0,
        Shape::Plane { normal, .. } => normal.iter().any(|v| *v != 0.0),
        Shape::Box { half_extents, .. } => half_extents.iter().all(|v| v.is_finite() && *v > 0.0),
        Shape::Cylinder { axis, radius, .. } => axis.iter().any(|v| *v != 0.0) && radius.is_finite() && *radius > 0.0,
        Shape::Mesh { mesh, scale, .. } => !mesh.triangles.is_empty() && *scale > 0.0,
    });
    positive.iter().all(|v| v.is_finite() && *v > 0.0) && r.mu.is_finite() && r.mu >= 0.0 && obstacles
}

/// Ok with usable values, or an error at `scene.json:line:column` inside
/// the file.
fn check(text: &[u8]) -> Result<(), TestCaseError> {
    let lines = text.split(|&b| b == b'\n').count();
    match parse_params(text, Path::new("scene.json")) {
        Ok(p) => prop_assert!(usable(&p), "{p:?}\n{}", String::from_utf8_lossy(text)),
        Err(SceneError::Parse { line, column, .. }) if line >= 1 && line <= lines && column <= text.len() + 1 => {}
        Err(e) => prop_assert!(false, "not located: {e}\n{}", String::from_utf8_lossy(text)),
    }
    Ok(())
}

#[test]
fn the_seed_scene_reads() {
    let p = parse_params(SEED.as_bytes(), Path::new("scene.json")).expect("the seed is valid");
    assert_eq!(p.obstacles.len(), 3);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_read_or_fail_at_a_line_and_column(edits in prop::collection::vec(edit(), 1..6)) {
        let text = edits.iter().fold(SEED.as_bytes().to_vec(), apply);
        check(&text)?;
    }

    #[test]
    fn one_replaced_number_reads_or_fails_at_a_line_and_column(k in 0usize..64, v in 0..VALUES.len()) {
        let text = apply(SEED.as_bytes().to_vec(), &Edit::Number(k, v));
        check(&text)?;
    }

    #[test]
    fn random_bytes_read_or_fail_at_a_line_and_column(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        check(&bytes)?;
    }
}
