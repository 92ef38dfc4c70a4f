//! A swatch measures its gauge: the contract a design tool keeps with a
//! knitter. Stockinette at a fingering, a DK and a chunky gauge, each with its default
//! yarn, relaxed with the default settings, measures within 10% of the
//! gauge it was knitted at (counted in the middle of the swatch,
//! `topology::measure`); a yarn too thick for its gauge is named, with the
//! file, line and column of its `yarn` line.

use knitsim::app::load_fabric;
use knitsim::sim::{relax, RelaxOptions, Simulation};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::{CompileOptions, StitchGrid};

fn swatch(dir: &std::path::Path, gauge: &str, yarn: &str) -> std::path::PathBuf {
    let text = format!(
        "name: swatch\ngauge: {gauge} / 10 cm\nyarn MC: #ffffff{yarn}\nwidth: 12\nheight: 12\n\n\
         legend:\n  . = knit\n\nchart:\n  .\n"
    );
    let path = dir.join("swatch.knit");
    std::fs::write(&path, text).unwrap();
    path
}

/// Measured (stitches, rows) per 10 cm of the relaxed swatch.
fn measured(gauge: &str) -> (f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let loaded = load_fabric(&swatch(dir.path(), gauge, ""), &CompileOptions::default()).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let grid = StitchGrid::of(&loaded.fabric);
    let params = knitsim::scene::params_for(&loaded.fabric, None).unwrap();
    let mut sim = Simulation::new(
        loaded.fabric,
        params,
        LinearSolver::direct(),
        RelaxOptions::default().h_initial,
    );
    // The gauge is counted in the middle of the swatch, which has settled
    // long before the edge roll that the last decades of the default
    // tolerance finish (docs/RELAX.md, "What the default tolerance means").
    let opts = RelaxOptions {
        tol: 0.1,
        ..RelaxOptions::default()
    };
    let report = relax(&mut sim, opts, None, &mut |_, _| {}, &mut |_, _| {}).unwrap();
    assert!(report.converged, "{report:?}");
    let g = grid
        .measure(&sim.snapshot())
        .expect("a stockinette swatch has a stitch grid");
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
    let path = swatch(dir.path(), "32 sts x 44 rows", ", radius 1.5 mm");
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
