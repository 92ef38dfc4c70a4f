//! What every knitter knows about plain fabrics, as the outside reference
//! for the relaxed shapes (docs/MODEL.md, "Real-fabric references"):
//!
//! - 1x1 rib draws in: of the same yarn and stitch count it is at least
//!   15% narrower than stockinette laid flat;
//! - stockinette curls at its edges and garter lies flat: stockinette's
//!   out-of-plane extent is at least twice garter's.
//!
//! Each swatch is 12 x 12 at 24 x 32 per 10 cm with the default yarn,
//! relaxed with the default settings at the gauge tests' tolerance. The
//! model does not reproduce either fact yet (docs/RELAX.md, "Open
//! problems": a stitch contact has no thickness), so both tests are
//! ignored with what they measure; `cargo test --release --test
//! knit_fabric_facts -- --ignored --nocapture` runs them.

mod common;

/// A relaxed 12 x 12 swatch of `chart` (one chart line per row, bottom
/// row last, each indented): its extents in the swatch frame (width along
/// the courses, height along the wales, depth across; m) and its measured
/// stitches per 10 cm.
fn relaxed(chart: &str) -> ([f64; 3], f64) {
    let dir = tempfile::tempdir().unwrap();
    let path = common::swatch_file(dir.path(), "24 sts x 32 rows", "", chart);
    let (state, grid) = common::relaxed_swatch(&path);
    let extents = grid.extents(&state).expect("a swatch has a stitch grid");
    let gauge = grid.measure(&state).expect("a swatch has a stitch grid");
    println!(
        "{}: {:.1} x {:.1} x {:.1} mm, {:.1} stitches per 10 cm",
        chart.trim().replace("\n  ", " / "),
        1e3 * extents[0],
        1e3 * extents[1],
        1e3 * extents[2],
        gauge.stitches_per_10cm
    );
    (extents, gauge.stitches_per_10cm)
}

#[test]
#[ignore = "rib measures 48.8 mm wide against 51.5 mm for 12 stitches of stockinette laid flat at its measured 23.3 stitches per 10 cm: 5% narrower, not 15%"]
fn one_by_one_rib_draws_in() {
    let (_, stockinette_gauge) = relaxed("  .\n");
    // Stockinette rolls its sides, so its laid-flat width is its stitch
    // count at its measured gauge, as a knitter's tape laid along it reads.
    let stockinette_flat = 12.0 * 0.1 / stockinette_gauge;
    let (rib, _) = relaxed("  [. -]\n");
    assert!(
        rib[0] <= 0.85 * stockinette_flat,
        "rib {:.1} mm wide, stockinette {:.1} mm laid flat",
        1e3 * rib[0],
        1e3 * stockinette_flat
    );
}

#[test]
#[ignore = "stockinette ends 11.2 mm out of plane and garter 20.0 mm: garter, twisted, is the deeper one"]
fn stockinette_curls_and_garter_lies_flat() {
    let (stockinette, _) = relaxed("  .\n");
    let (garter, _) = relaxed("  .\n  -\n");
    assert!(
        stockinette[2] >= 2.0 * garter[2],
        "stockinette {:.1} mm deep, garter {:.1} mm",
        1e3 * stockinette[2],
        1e3 * garter[2]
    );
}
