//! Structural invariants of every compiled fabric: contact nodes shared by
//! exactly two yarn points, sorted material coordinates, symmetric partners,
//! and the rest-length budget.

mod common;

use common::{pattern, structures};
use knitsim::pattern::Construction;
use knitsim::topology::rest_length::stitch_length;
use knitsim::topology::{compile, CompileOptions, ContactKind, Fabric};

fn check(name: &str, f: &Fabric) {
    let refs = f.node_refcounts();
    let mut contact_node = vec![false; f.nodes.len()];
    for c in &f.contacts {
        assert!(!contact_node[c.node], "{name}: node {} in two contacts", c.node);
        contact_node[c.node] = true;
        assert_eq!(refs[c.node], 2, "{name}: contact node not shared by two points");
        for r in [c.front, c.back] {
            let pt = &f.yarns[r.yarn].points[r.point];
            assert_eq!(pt.node, c.node, "{name}: front/back do not reference the node");
            assert!(!pt.fixed_u, "{name}: a contact point must slide");
        }
        assert_ne!(c.front, c.back, "{name}");
        match c.partner {
            Some(p) => {
                assert_eq!(c.kind, ContactKind::Stitch, "{name}");
                let other = f.contacts.iter().find(|o| o.node == p).expect("partner");
                assert_eq!(other.partner, Some(c.node), "{name}: partner not symmetric");
            }
            None => assert_ne!(c.kind, ContactKind::Stitch, "{name}: stitch contact without partner"),
        }
    }
    for (i, r) in refs.iter().enumerate() {
        if !contact_node[i] {
            assert_eq!(*r, 1, "{name}: node {i} is not a contact but has {r} points");
        }
    }
    for (yi, y) in f.yarns.iter().enumerate() {
        let pts = &y.points;
        assert!(pts.len() >= 2, "{name}: yarn {yi} too short");
        assert!(
            pts[0].fixed_u && pts[pts.len() - 1].fixed_u,
            "{name}: ends must be fixed"
        );
        assert_eq!(pts[0].u, 0.0);
        assert!((pts[pts.len() - 1].u - y.rest_length).abs() <= 1e-12 * y.rest_length);
        for w in pts.windows(2) {
            assert!(w[1].u > w[0].u, "{name}: yarn {yi} u not increasing");
        }
        assert!(pts.iter().all(|p| p.u >= 0.0 && p.u <= y.rest_length));
    }
}

#[test]
fn every_structure_is_well_formed() {
    for (name, t, c) in structures() {
        for cons in [Construction::Flat, Construction::Round] {
            let p = pattern(&t, c.as_deref(), cons, 8, 8);
            let f = compile(&p, &CompileOptions::default()).expect(name);
            check(&format!("{name} {cons:?}"), &f);
        }
    }
}

#[test]
fn stockinette_rest_length_is_loops_times_stitch_length_plus_turns() {
    // 6 x 4 stockinette: 30 loops (24 + 6 cast-on) of Munden length l each,
    // plus 4 edge turns (cast-on->1, 1->2, 2->3, 3->4) and the two ends.
    // With the default gauge and a 1 mm (stated) yarn, 0.6 mm in the model,
    // l = 0.72 sqrt(19 w h) = 12.22 mm (above the jam floor 12 d = 7.2 mm).
    let p = pattern(&["k"], None, Construction::Flat, 6, 4);
    let opts = CompileOptions::default();
    let f = compile(&p, &opts).expect("compile");
    let l = stitch_length(0.1 / 22.0, 0.1 / 30.0, 0.6e-3, 1.0, &opts);
    assert!((l - 0.72 * 16.967e-3).abs() < 1e-5);
    let total: f64 = f.yarns.iter().map(|y| y.rest_length).sum();
    let loops = 30.0 * l;
    // Each turn climbs one row (h = 3.33 mm at gauge) plus short steps out:
    // well under 10 mm per turn, 6 connectors in all.
    assert!(total > loops, "{total} vs {loops}");
    assert!(total < loops + 6.0 * 10e-3, "{total} vs {loops}");
}

#[test]
fn looseness_scales_loops() {
    let mut p = pattern(&["k"], None, Construction::Round, 8, 3);
    let opts = CompileOptions::default();
    let normal: f64 = compile(&p, &opts).unwrap().yarns.iter().map(|y| y.rest_length).sum();
    p.meta.looseness = 1.2;
    let loose: f64 = compile(&p, &opts).unwrap().yarns.iter().map(|y| y.rest_length).sum();
    // 32 loops each 20% longer; the round has no edge turns.
    let l = stitch_length(0.1 / 22.0, 0.1 / 30.0, 1.0e-3, 1.0, &opts);
    assert!(((loose - normal) - 32.0 * 0.2 * l).abs() < 1e-9, "{normal} {loose}");
}
