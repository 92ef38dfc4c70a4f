//! A slipped (or held) loop is one loop's yarn drawn over two rows or
//! more. A knitter's slipped stitch is an ordinary loop, only longer in
//! the legs, and its child is pulled through it like any other: its head
//! must hold about an ordinary head's yarn between the child's two legs,
//! and at least a diameter. Checked on the compiled rest lengths of every
//! shipped pattern with slipped or held loops.

mod common;

use knitsim::topology::{compile, CompileOptions, ContactKind, Fabric};

/// The rest yarn of every head between its child's two legs: on a yarn,
/// two stitch-contact points of the same side with one free point (the
/// apex) between them, above them in the flat layout. A leg runs from a
/// foot contact to a head contact on opposite sides, and a sinker between
/// two feet dips below them, so neither matches.
fn head_spans(f: &Fabric) -> Vec<f64> {
    let mut side = vec![None; f.nodes.len()];
    for c in f.contacts.iter().filter(|c| c.kind == ContactKind::Stitch) {
        side[c.node] = Some(c.front);
    }
    let mut spans = Vec::new();
    for (yi, y) in f.yarns.iter().enumerate() {
        let role = |i: usize| side[y.points[i].node].map(|front| front.yarn == yi && front.point == i);
        for i in 0..y.points.len().saturating_sub(2) {
            if let (Some(a), None, Some(b)) = (role(i), role(i + 1), role(i + 2)) {
                let height = |k: usize| f.nodes[y.points[k].node].x.y;
                if a == b && height(i + 1) > height(i).max(height(i + 2)) {
                    spans.push(y.points[i + 2].u - y.points[i].u);
                }
            }
        }
    }
    spans
}

#[test]
fn every_slipped_head_holds_an_ordinary_heads_yarn() {
    for stem in [
        "fig3-diagonal-slip",
        "fig3-long-slip",
        "fig3-woven-slip",
        "linen-stitch",
        "honeycomb",
        "mosaic",
        "tuck",
    ] {
        let f = compile(&common::shipped(stem), &CompileOptions::default()).expect(stem);
        let mut spans = head_spans(&f);
        assert!(spans.len() > 50, "{stem}: {} heads found", spans.len());
        spans.sort_by(f64::total_cmp);
        let median = spans[spans.len() / 2];
        let shortest = spans[0];
        let d = 2.0 * f.meta.yarns[0].radius;
        assert!(
            shortest > 0.8 * median && shortest > d,
            "{stem}: shortest head {:.2} mm, median {:.2} mm, model diameter {:.2} mm",
            1e3 * shortest,
            1e3 * median,
            1e3 * d
        );
    }
}
