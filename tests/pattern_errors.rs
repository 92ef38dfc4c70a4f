//! Every file in tests/malformed/ must fail with the right kind of error at
//! the exact line and column (counted by hand from the file).

use std::mem::discriminant;
use std::path::Path;

use knitsim::pattern::{load, parse_bytes, parse_str, parse_str_with, ErrorKind, Limits, StitchKind};

fn check(file: &str, expected: ErrorKind, line: usize, column: usize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/malformed").join(file);
    let err = match load(&path) {
        Ok(_) => panic!("{file} parsed without error"),
        Err(err) => err,
    };
    assert_eq!(discriminant(&err.kind), discriminant(&expected), "{file}: {err}");
    assert_eq!((err.loc.line, err.loc.column), (line, column), "{file}: {err}");
    // The rendering names the place and puts the caret under the column.
    let text = err.to_string();
    assert!(text.contains(&format!("{}:{line}:{column}", path.display())), "{text}");
    let lines: Vec<&str> = text.lines().collect();
    let (source_line, caret_line) = (lines[lines.len() - 2], lines[lines.len() - 1]);
    let gutter = source_line.find(" | ").expect("gutter") + 3;
    let caret = caret_line.find('^').expect("caret");
    assert_eq!(caret - gutter, column - 1, "{text}");
}

#[test]
fn unknown_symbol() {
    check("unknown-symbol.knit", ErrorKind::UnknownSymbol('x'), 8, 7);
}

#[test]
fn ragged_row() {
    check("ragged-row.knit", ErrorKind::RaggedRow { expected: 4, found: 3 }, 7, 8);
}

#[test]
fn stitch_repeat_does_not_fit() {
    let kind = ErrorKind::RepeatDoesNotFit {
        what: "stitch",
        detail: String::new(),
    };
    check("repeat-does-not-fit.knit", kind, 2, 8);
}

#[test]
fn row_repeat_does_not_fit() {
    let kind = ErrorKind::RepeatDoesNotFit {
        what: "row",
        detail: String::new(),
    };
    check("row-repeat-does-not-fit.knit", kind, 3, 9);
}

#[test]
fn misaligned_repeat() {
    check(
        "misaligned-repeat.knit",
        ErrorKind::MisalignedRepeat {
            expected: (1, 3),
            found: (2, 4),
        },
        7,
        7,
    );
}

#[test]
fn written_row_count_differs_from_width() {
    check(
        "stitch-count-written.knit",
        ErrorKind::StitchCount {
            row: 2,
            expected: 10,
            found: 9,
        },
        5,
        3,
    );
}

#[test]
fn written_rows_differ_from_each_other() {
    check(
        "stitch-count-rows.knit",
        ErrorKind::StitchCount {
            row: 3,
            expected: 6,
            found: 8,
        },
        5,
        3,
    );
}

#[test]
fn slip_stacked_too_high() {
    check(
        "slip-stacked.knit",
        ErrorKind::SlipStacked { count: 4, limit: 3 },
        12,
        5,
    );
}

#[test]
fn tuck_stacked_too_high() {
    check("tuck-stacked.knit", ErrorKind::TuckStacked { count: 2, limit: 1 }, 8, 7);
}

#[test]
fn missing_legend_entry() {
    check("missing-legend-entry.knit", ErrorKind::EmptyLegendEntry('v'), 4, 3);
}

#[test]
fn duplicate_legend_symbol() {
    check("duplicate-symbol.knit", ErrorKind::DuplicateSymbol('.'), 4, 3);
}

#[test]
fn missing_legend() {
    check("missing-legend.knit", ErrorKind::MissingLegend, 3, 1);
}

#[test]
fn unknown_yarn() {
    check("unknown-yarn.knit", ErrorKind::UnknownYarn("CC".into()), 6, 13);
}

#[test]
fn bad_gauges() {
    check("bad-gauge-nan.knit", ErrorKind::BadGauge(String::new()), 2, 8);
    check("bad-gauge-zero.knit", ErrorKind::BadGauge(String::new()), 1, 17);
    check("bad-gauge-negative.knit", ErrorKind::BadGauge(String::new()), 2, 8);
}

#[test]
fn unknown_metadata_key() {
    check("unknown-key.knit", ErrorKind::UnknownKey("gague".into()), 2, 1);
}

#[test]
fn missing_chart() {
    check("missing-chart.knit", ErrorKind::MissingChart, 1, 1);
}

#[test]
fn bad_colour_literal() {
    check("bad-colour.knit", ErrorKind::BadColour(String::new()), 2, 10);
}

#[test]
fn wrong_side_label() {
    check(
        "wrong-side.knit",
        ErrorKind::WrongSide {
            row: 2,
            claimed: "RS",
            actual: "WS",
        },
        5,
        10,
    );
}

#[test]
fn yarn_thicker_than_the_stitch() {
    check("thick-yarn.knit", ErrorKind::BadYarn(String::new()), 3, 28);
}

#[test]
fn a_byte_that_is_not_utf8_is_located() {
    // A Latin-1 `×` (0xD7) in the gauge line.
    check("latin1-gauge.knit", ErrorKind::Encoding(String::new()), 2, 15);
}

#[test]
fn a_nan_yarn_radius_is_an_error_at_the_number() {
    check("yarn-radius-nan.knit", ErrorKind::BadYarn(String::new()), 2, 26);
}

#[test]
fn a_byte_order_mark_is_accepted_and_columns_stay_right() {
    let shipped = std::fs::read("patterns/stockinette.knit").expect("shipped pattern");
    let with_bom = [b"\xef\xbb\xbf".as_slice(), &shipped].concat();
    let plain = parse_bytes(&shipped, "p.knit").expect("shipped pattern parses");
    let marked = parse_bytes(&with_bom, "p.knit").expect("a BOM is accepted");
    assert_eq!(plain.pattern, marked.pattern);
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("bom.knit");
    std::fs::write(&path, &with_bom).expect("write");
    assert_eq!(load(&path).expect("a BOM file loads").pattern.meta, plain.pattern.meta);
    // Columns on the first line count from after the mark.
    let err = parse_str("\u{feff}gauge: 24 x nan\nchart:\n  .\n", "p.knit").expect_err("nan rows");
    assert_eq!((err.loc.line, err.loc.column), (1, 13), "{err}");
}

#[test]
fn an_error_in_a_very_long_row_shows_a_window_around_the_true_column() {
    let mut row = "k".repeat(5000);
    row.replace_range(3999..4000, "x");
    let text = format!("legend:\n  k = knit\nchart:\n  {row}\n");
    let limits = Limits {
        max_width: 10_000,
        ..Limits::default()
    };
    let err = parse_str_with(&text, "p.knit", &limits).expect_err("a long row with an unknown symbol");
    let rendered = err.to_string();
    assert_eq!((err.loc.line, err.loc.column), (4, 4002), "{rendered}");
    assert!(rendered.contains("p.knit:4:4002"), "{rendered}");
    assert!(rendered.lines().all(|l| l.chars().count() <= 100), "{rendered}");
    let lines: Vec<&str> = rendered.lines().collect();
    let (source_line, caret_line) = (lines[lines.len() - 2], lines[lines.len() - 1]);
    assert!(
        source_line.starts_with("4 | ...k") && source_line.ends_with("k..."),
        "{rendered}"
    );
    assert_eq!(caret_line.find('^'), source_line.find('x'), "{rendered}");
}

#[test]
fn every_malformed_file_is_checked() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/malformed");
    let count = std::fs::read_dir(dir).expect("dir").filter_map(Result::ok).count();
    // One per `check` call above; keeps new files from going untested.
    assert_eq!(count, 23);
}

#[test]
fn rendering_matches_rustc_layout() {
    let err = parse_str("legend:\n  . = knit\nchart:\n  ..x.\n", "p.knit").expect_err("x");
    let expected = "error: unknown symbol 'x' (not in the legend)\n --> p.knit:4:5\n  |\n4 |   ..x.\n  |     ^";
    assert_eq!(err.to_string(), expected);
}

#[test]
fn slipping_on_row_one_holds_a_cast_on_loop() {
    // Not an error: a cast-on row is implied below row 1.
    let text = "legend:\n  . = knit\n  v = slip wyif\n  T = tuck\nchart:\n  . . .\n  v . T\n";
    let parsed = parse_str(text, "t").expect("row 1 may slip and tuck");
    assert_eq!(parsed.pattern.rows[0].stitches[0].kind, StitchKind::SlipFront);
    assert_eq!(parsed.pattern.rows[0].stitches[2].kind, StitchKind::Tuck);
}

#[test]
fn long_floats_warn_with_a_location() {
    // MC floats behind 6 CC stitches (> 5): a warning, not an error.
    let text =
        "yarn MC: #000000\nyarn CC: #ffffff\nlegend:\n  . = knit\n  x = knit, yarn CC\nchart:\n  . x x x x x x .\n";
    let parsed = parse_str(text, "t").expect("floats only warn");
    assert_eq!(parsed.warnings.len(), 1, "{:?}", parsed.warnings);
    let w = &parsed.warnings[0];
    assert_eq!((w.loc.line, w.loc.column), (7, 5));
    assert!(
        w.to_string().starts_with("warning: yarn 'MC' floats past 6 stitches"),
        "{w}"
    );
}
