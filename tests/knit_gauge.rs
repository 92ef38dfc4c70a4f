//! A swatch measures its gauge: the contract a design tool keeps with a
//! knitter. Stockinette at a fingering, a DK and a chunky gauge, each with its default
//! yarn, relaxed with the default settings, measures within 10% of the
//! gauge it was knitted at (counted in the middle of the swatch,
//! `topology::measure`); a yarn too thick for its gauge is named, with the
//! file, line and column of its `yarn` line.

mod common;

use knitsim::app::load_fabric;
use knitsim::topology::CompileOptions;

/// Measured (stitches, rows) per 10 cm of the relaxed swatch.
fn measured(gauge: &str) -> (f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let (state, grid) = common::relaxed_swatch(&common::swatch_file(dir.path(), gauge, "", "  .\n"));
    let g = grid.measure(&state).expect("a stockinette swatch has a stitch grid");
    println!("{gauge}: measured {:.1} x {:.1}", g.stitches_per_10cm, g.rows_per_10cm);
    (g.stitches_per_10cm, g.rows_per_10cm)
}

fn assert_within_10_percent(gauge: &str, sts: f64, rows: f64) {
    let (s, r) = measured(gauge);
    assert!(
        (s / sts - 1.0).abs() <= 0.10,
        "{gauge}: measured {s:.1} stitches per 10 cm"
    );
    assert!(
        (r / rows - 1.0).abs() <= 0.10,
        "{gauge}: measured {r:.1} rows per 10 cm"
    );
}

#[test]
fn dk_stockinette_measures_its_gauge() {
    assert_within_10_percent("22 sts x 30 rows", 22.0, 30.0);
}

#[test]
fn fingering_stockinette_measures_its_gauge() {
    assert_within_10_percent("32 sts x 44 rows", 32.0, 44.0);
}

#[test]
fn chunky_stockinette_measures_its_gauge() {
    assert_within_10_percent("14 sts x 20 rows", 14.0, 20.0);
}

#[test]
fn a_yarn_too_thick_for_its_gauge_is_named_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    // A 1.5 mm (radius) yarn cannot knit 32 stitches per 10 cm.
    let path = common::swatch_file(dir.path(), "32 sts x 44 rows", ", radius 1.5 mm", "  .\n");
    let loaded = load_fabric(&path, &CompileOptions::default()).unwrap();
    let jam: Vec<String> = loaded
        .warnings
        .iter()
        .map(|w| w.to_string())
        .filter(|w| w.contains("jams at"))
        .collect();
    assert_eq!(jam.len(), 1, "{:?}", loaded.warnings);
    let w = &jam[0];
    assert!(
        w.contains("yarn MC jams at") && w.contains("the pattern asks for 32.0 x 44.0"),
        "{w}"
    );
    assert!(w.contains(&format!("{}:3:6", path.display())), "{w}");
    // The jam gauge it names is looser than the one asked for.
    let sts: f64 = w
        .split("jams at ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!(sts < 32.0, "{w}");
}
