//! Where a child is pulled through two heads at once (a tuck loop and the
//! loop it sits on share a needle), the two heads are two pieces of yarn
//! lying against each other, a diameter apart, and the child runs between
//! them. The thickness filter (docs/MODEL.md, "Thickness contact")
//! measures rest distances through the contact nodes, so if the child's
//! yarn between the two heads were shorter than one thickness the heads
//! would count as neighbours and could sink halfway into each other.
//! Checked on the compiled rest lengths of every shipped pattern: between
//! two stitch contacts on one yarn that belong to different heads (not two
//! ends of one wrap), the yarn holds at least one thickness.

mod common;

use knitsim::topology::{compile, CompileOptions, ContactKind, Fabric};

/// Per yarn, the stitch contacts along it in `u` order, each with its
/// contact index, and the rest yarn between consecutive ones that are not
/// partners (two ends of one wrap): `(u gap, contact a, contact b)`.
fn passes_between_heads(f: &Fabric) -> Vec<(f64, usize, usize)> {
    let mut out = Vec::new();
    for (yi, y) in f.yarns.iter().enumerate() {
        let mut along: Vec<(f64, usize)> = f
            .contacts
            .iter()
            .enumerate()
            .filter(|(_, c)| c.kind == ContactKind::Stitch)
            .flat_map(|(k, c)| [c.front, c.back].map(|p| (p, k)))
            .filter(|(p, _)| p.yarn == yi)
            .map(|(p, k)| (y.points[p.point].u, k))
            .collect();
        along.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in along.windows(2) {
            let (a, b) = (&f.contacts[w[0].1], &f.contacts[w[1].1]);
            let partners = a.partner == Some(b.node) || b.partner == Some(a.node);
            if !partners && w[0].1 != w[1].1 {
                out.push((w[1].0 - w[0].0, w[0].1, w[1].1));
            }
        }
    }
    out
}

#[test]
fn a_child_runs_a_thickness_between_two_heads() {
    let mut checked = 0;
    for (stem, pattern) in common::shipped_patterns() {
        let f = compile(&pattern, &CompileOptions::default()).expect(&stem);
        let thickness = 2.0 * f.meta.yarns.iter().map(|y| y.radius).fold(0.0, f64::max);
        let passes = passes_between_heads(&f);
        assert!(!passes.is_empty(), "{stem}: no passes found");
        let (gap, a, b) = passes.iter().copied().min_by(|p, q| p.0.total_cmp(&q.0)).unwrap();
        println!(
            "{stem:20} shortest {:.3} mm, thickness {:.3} mm",
            1e3 * gap,
            1e3 * thickness
        );
        assert!(
            gap >= thickness,
            "{stem}: {:.3} mm of yarn between contacts {a} and {b}, under the thickness {:.3} mm",
            1e3 * gap,
            1e3 * thickness
        );
        checked += 1;
    }
    assert!(checked >= 14, "the shipped patterns are missing");
}
