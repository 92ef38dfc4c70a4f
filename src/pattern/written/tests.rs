use super::syntax::{row_line, Count, Item};
use super::*;
use crate::pattern::source::Line;
use crate::pattern::{parse_str, ErrorKind};

fn line(text: &str) -> Line<'_> {
    Line { number: 7, text }
}

#[test]
fn row_label_forms() {
    let row = row_line(line("  Rows 2, 4 and 6-8 (WS), with CC: purl.")).expect("valid row");
    let ranges: Vec<(usize, usize)> = row.rows.iter().map(|&(a, b, _)| (a, b)).collect();
    assert_eq!(ranges, vec![(2, 2), (4, 4), (6, 8)]);
    assert_eq!(row.side.map(|s| s.0), Some("WS"));
    assert_eq!(row.yarn.map(|y| (y.0, y.1.col)), Some(("CC", 32)));
}

#[test]
fn items_with_counts_and_brackets() {
    let row = row_line(line(
        "Row 1: k1, [sl1 wyif, p2] 3 times, tk, [k1, [p1] twice] to last 2 sts, k2",
    ))
    .expect("valid");
    let counts: Vec<Count> = row
        .items
        .iter()
        .map(|i| match i {
            Item::Op { count, .. } | Item::Group { count, .. } => *count,
        })
        .collect();
    assert_eq!(
        counts,
        vec![
            Count::Times(1),
            Count::Times(3),
            Count::Times(1),
            Count::UntilLeft(2),
            Count::Times(2)
        ]
    );
}

#[test]
fn syntax_errors_point_at_the_bad_item() {
    let cases = [
        ("Row 1: k1, kfb, k1", 12),
        ("Row 1: k1, [p1, k1 3 times", 20),
        ("Row 1: k2 to end", 8),
        ("Row 1: sl1, k1", 8),
        ("Row 1 k1", 7),
        ("Row 1: [[[[[k1] once] once] once] once] once", 12),
    ];
    for (text, col) in cases {
        let fail = row_line(line(text)).expect_err(text);
        assert_eq!(
            line(text).pos(fail.at, 1).col,
            col,
            "{text}: expected {}",
            fail.expected
        );
    }
}

#[test]
fn fabric_kind_inverts_worked() {
    use crate::pattern::model::{Side, Stitch, StitchKind};
    for kind in [
        StitchKind::Knit,
        StitchKind::Purl,
        StitchKind::SlipFront,
        StitchKind::SlipBack,
        StitchKind::Tuck,
    ] {
        for side in [Side::Rs, Side::Ws] {
            let worked = Stitch { kind, yarn: 0 }.worked(side);
            assert_eq!(fabric_kind(worked, side), kind, "{kind:?} on {side:?}");
        }
    }
    // By hand: a WS purl shows as a knit V on the RS; a WS sl wyib floats on the RS.
    assert_eq!(fabric_kind(Worked::Purl, Side::Ws), StitchKind::Knit);
    assert_eq!(fabric_kind(Worked::SlipWyib, Side::Ws), StitchKind::SlipFront);
}

#[test]
fn to_last_fills_the_width() {
    let text = "width: 7\nwritten:\n  Row 1: k1, [p1, k1] to last 2 sts, p2.\n";
    let parsed = parse_str(text, "t").expect("fits");
    let row = &parsed.pattern.rows[0];
    // Worked right to left: columns 6..0 = k p k p k p p.
    use crate::pattern::model::StitchKind::{Knit as K, Purl as P};
    let kinds: Vec<_> = row.stitches.iter().map(|s| s.kind).collect();
    assert_eq!(kinds, vec![P, P, K, P, K, P, K]);
}

#[test]
fn garter_repeats_the_instruction_not_the_fabric() {
    let parsed = parse_str("width: 3\nheight: 2\nwritten:\n  Row 1: knit.\n", "t").expect("garter");
    use crate::pattern::model::StitchKind::{Knit, Purl};
    assert!(parsed.pattern.rows[0].stitches.iter().all(|s| s.kind == Knit));
    assert!(parsed.pattern.rows[1].stitches.iter().all(|s| s.kind == Purl));
}

#[test]
fn count_and_repeat_errors() {
    let err = parse_str("width: 6\nwritten:\n  Row 1: k1, [p1, k1] to end.\n", "t").expect_err("5 left for 2");
    assert!(matches!(err.kind, ErrorKind::RepeatDoesNotFit { what: "stitch", .. }));
    assert_eq!((err.loc.line, err.loc.column), (3, 14));
    let err = parse_str("written:\n  Row 1: k4.\n  Row 2: p5.\n", "t").expect_err("5 != 4");
    assert_eq!(
        err.kind,
        ErrorKind::StitchCount {
            row: 2,
            expected: 4,
            found: 5
        }
    );
    assert_eq!((err.loc.line, err.loc.column), (3, 3));
    let err = parse_str("written:\n  Row 1: k99999999999999999999.\n", "t").expect_err("overflow");
    assert!(matches!(err.kind, ErrorKind::Syntax(_)));
    let err = parse_str("written:\n  Row 1: [[k1] 99999999999 times] 99999999999 times.\n", "t").expect_err("huge");
    assert!(matches!(err.kind, ErrorKind::TooLarge(_)));
}

#[test]
fn sides_and_missing_rows() {
    let err = parse_str("written:\n  Row 1 (RS): k2.\n  Row 2 (RS): p2.\n", "t").expect_err("row 2 is WS");
    assert_eq!(
        err.kind,
        ErrorKind::WrongSide {
            row: 2,
            claimed: "RS",
            actual: "WS"
        }
    );
    assert_eq!((err.loc.line, err.loc.column), (3, 10));
    let err = parse_str("written:\n  Row 1: k2.\n  Row 3: k2.\n", "t").expect_err("no row 2");
    assert_eq!(err.kind, ErrorKind::MissingRow(2));
    let ok = parse_str("construction: round\nwritten:\n  Rows 1-2 (RS): k2.\n", "t").expect("round is all RS");
    assert_eq!(ok.pattern.meta.height, 2);
}
