//! Whole-parser tests: the shipped patterns, chart/written equivalence and
//! the WS swap. Expected values are hand counts from the charts.

use std::path::{Path, PathBuf};

use super::*;

fn shipped() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("patterns/ exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "knit"))
        .collect();
    files.sort();
    files
}

fn load_shipped(name: &str) -> Pattern {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns").join(name);
    load(&path).unwrap_or_else(|e| panic!("{e}")).pattern
}

#[test]
fn every_shipped_pattern_parses_cleanly() {
    let files = shipped();
    assert_eq!(files.len(), 14, "{files:?}");
    for path in files {
        let parsed = load(&path).unwrap_or_else(|e| panic!("{e}"));
        let warnings: Vec<String> = parsed.warnings.iter().map(|w| w.to_string()).collect();
        assert!(warnings.is_empty(), "{}: {warnings:#?}", path.display());
        let p = &parsed.pattern;
        assert_eq!(p.rows.len(), p.meta.height, "{}", path.display());
        let stitches: usize = p.rows.iter().map(|r| r.stitches.len()).sum();
        assert_eq!(stitches, p.meta.width * p.meta.height, "{}", path.display());
        for (i, row) in p.rows.iter().enumerate() {
            assert_eq!(row.number, i + 1);
            let expected = match (p.meta.construction, i % 2) {
                (Construction::Flat, 1) => Side::Ws,
                _ => Side::Rs,
            };
            assert_eq!(row.side, expected, "{} row {}", path.display(), i + 1);
            assert!(row.stitches.iter().all(|s| s.yarn < p.meta.yarns.len()));
        }
        // Sizes stay simulation-friendly and yarns thinner than a stitch.
        assert!(
            (12..=24).contains(&p.meta.width) && (12..=24).contains(&p.meta.height),
            "{}",
            path.display()
        );
        for yarn in &p.meta.yarns {
            assert!(
                2.0 * yarn.radius < 0.5 * p.meta.gauge.stitch_width(),
                "{}",
                path.display()
            );
        }
    }
}

#[test]
fn rib_columns_by_hand() {
    let p = load_shipped("rib-2x2.knit");
    // `[. . - -] . .` to 18: four repeats then two edge knits.
    let row: String = p.rows[5]
        .stitches
        .iter()
        .map(|s| if s.kind == StitchKind::Knit { 'k' } else { 'p' })
        .collect();
    assert_eq!(row, "kkppkkppkkppkkppkk");
    assert_eq!(p.meta.yarns[0].radius, 0.7e-3);
}

#[test]
fn garter_alternates_in_fabric_view_but_is_always_knitted() {
    let p = load_shipped("garter.knit");
    for row in &p.rows {
        let expected = if row.side == Side::Rs {
            StitchKind::Knit
        } else {
            StitchKind::Purl
        };
        assert!(row.stitches.iter().all(|s| s.kind == expected));
        assert!(row.stitches.iter().all(|s| s.worked(row.side) == Worked::Knit));
    }
}

#[test]
fn mosaic_slips_take_the_row_yarn() {
    let p = load_shipped("mosaic.knit");
    // Row 3 (`. [. V . .] . | CC`): everything is CC, column 2 is slipped.
    let row = &p.rows[2];
    assert!(row.stitches.iter().all(|s| s.yarn == 1));
    assert_eq!(row.stitches[2].kind, StitchKind::SlipBack);
    assert_eq!(row.stitches[1].kind, StitchKind::Knit);
    // Row 1 is MC.
    assert!(p.rows[0].stitches.iter().all(|s| s.yarn == 0));
}

#[test]
fn jacquard_legend_yarn_overrides_the_row_yarn() {
    let p = load_shipped("jacquard.knit");
    // Row 3 from the bottom is `x x x x x .`.
    let yarns: Vec<usize> = p.rows[2].stitches.iter().take(6).map(|s| s.yarn).collect();
    assert_eq!(yarns, vec![1, 1, 1, 1, 1, 0]);
}

const LINEN_HEAD: &str = "width: 20\nheight: 4\n";

#[test]
fn written_linen_equals_chart_linen() {
    let chart = format!("{LINEN_HEAD}legend:\n  . = knit\n  v = slip wyif\nchart:\n  . [v .] .\n  . [. v] .\n");
    let written = format!(
        "{LINEN_HEAD}written:\n  Row 1 (RS): k1, [sl1 wyif, k1] to last st, k1.\n  Row 2 (WS): p1, [sl1 wyib, p1] to last st, p1.\n"
    );
    let from_chart = parse_str(&chart, "chart.knit").expect("chart linen").pattern;
    let from_written = parse_str(&written, "written.knit").expect("written linen").pattern;
    let stitches = |p: &Pattern| p.rows.iter().map(|r| r.stitches.clone()).collect::<Vec<_>>();
    assert_eq!(stitches(&from_chart), stitches(&from_written));
    // Hand count: row 1 slips the even columns 2..=18, row 2 the odd columns 1..=17.
    let slips = |r: &Row| {
        r.stitches
            .iter()
            .enumerate()
            .filter(|(_, s)| s.is_slip())
            .map(|(c, _)| c)
            .collect::<Vec<_>>()
    };
    assert_eq!(slips(&from_chart.rows[0]), (1..=9).map(|i| 2 * i).collect::<Vec<_>>());
    assert_eq!(
        slips(&from_chart.rows[1]),
        (0..9).map(|i| 2 * i + 1).collect::<Vec<_>>()
    );
    assert!(from_chart
        .rows
        .iter()
        .flat_map(|r| &r.stitches)
        .filter(|s| s.is_slip())
        .all(|s| s.kind == StitchKind::SlipFront));
}

#[test]
fn chart_and_written_disagreement_is_located() {
    let text = "width: 4\nlegend:\n  . = knit\nchart:\n  . . . .\nwritten:\n  Row 1: k2, p1, k1.\n";
    let err = parse_str(text, "t").expect_err("p1 is not in the chart");
    // Worked right to left, the p1 is column 2 (1-based), from the `p1` at 7:14.
    assert!(
        matches!(err.kind, ErrorKind::ChartWrittenMismatch { row: 1, column: 2, .. }),
        "{err}"
    );
    assert_eq!((err.loc.line, err.loc.column), (7, 14));
}

#[test]
fn ws_rows_swap_in_both_directions() {
    let text = "width: 4\nheight: 2\nlegend:\n  . = knit\n  - = purl\n  v = slip wyif\n  V = slip wyib\nchart:\n  . - v V\n  . . . .\n";
    let p = parse_str(text, "t").expect("valid").pattern;
    let ws = &p.rows[1];
    assert_eq!(ws.side, Side::Ws);
    let worked: Vec<Worked> = ws.stitches.iter().map(|s| s.worked(Side::Ws)).collect();
    assert_eq!(
        worked,
        vec![Worked::Purl, Worked::Knit, Worked::SlipWyib, Worked::SlipWyif]
    );
    // And a WS written row lands left to right, swapped back to fabric view.
    let written = parse_str(
        "width: 4\nheight: 2\nwritten:\n  Row 1: knit.\n  Row 2: p1, k1, sl1 wyib, sl1 wyif.\n",
        "t",
    )
    .expect("valid")
    .pattern;
    assert_eq!(written.rows[1].stitches, ws.stitches);
}

#[test]
fn readme_written_example_parses() {
    let text = "yarn MC: #000000\nyarn CC: #ffffff\nwidth: 14\nwritten:\n  Row 1 (RS): k1, [sl1 wyif, k1] to last st, k1.\n  Row 2 (WS): p1, [sl1 wyib, p1] to last st, p1.\n  Rows 3-4, with CC: knit.\n  Rows 5 and 7: [k2, p2] 3 times, k2.\n  Rows 6, 8: purl.\n";
    let p = parse_str(text, "readme.knit").unwrap_or_else(|e| panic!("{e}")).pattern;
    assert_eq!((p.meta.width, p.meta.height), (14, 8));
    // Rows 3-4 are CC; row 4 is a WS knit row, so purl bumps in fabric view.
    assert!(p.rows[3]
        .stitches
        .iter()
        .all(|s| s.yarn == 1 && s.kind == StitchKind::Purl));
    // Row 5 worked from the right: k2 p2 k2 p2 k2 p2 k2 reads the same both ways.
    let row5: String = p.rows[4]
        .stitches
        .iter()
        .map(|s| if s.kind == StitchKind::Knit { 'k' } else { 'p' })
        .collect();
    assert_eq!(row5, "kkppkkppkkppkk");
}
