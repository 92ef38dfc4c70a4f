//! The starting geometry keeps non-contact segments a yarn diameter apart on
//! every shipped pattern file and every structure, flat and round, contact
//! nodes are shared by their two yarns, and the check itself can fail.

mod common;

use common::{pattern, shipped_patterns, structures};
use knitsim::pattern::Construction;
use knitsim::pattern::Meta;
use knitsim::topology::fabric::{Contact, ContactKind, Node, PointRef, Vec3, Yarn, YarnPoint};
use knitsim::topology::{clearance, compile, ClearanceOptions, CompileOptions, Fabric};

#[test]
fn every_shipped_pattern_clears_and_shares_its_contact_nodes() {
    for (name, p) in shipped_patterns() {
        let f = compile(&p, &CompileOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        // A contact is one node on both yarns: both points name it, so the
        // two centre lines coincide there exactly.
        assert!(!f.contacts.is_empty(), "{name}: no contacts");
        for c in &f.contacts {
            let front = f.yarns[c.front.yarn].points[c.front.point].node;
            let back = f.yarns[c.back.yarn].points[c.back.point].node;
            assert_eq!((front, back), (c.node, c.node), "{name}: contact {c:?}");
            assert_ne!(c.front, c.back, "{name}: a contact needs two yarn points");
        }
        let r = clearance(&f, &ClearanceOptions::default());
        let d = 2.0 * p.meta.yarns.iter().map(|y| y.radius).fold(0.0, f64::max);
        println!(
            "{name:20}: min {:.3} d over {} pairs",
            r.min_distance / d,
            r.pairs_checked
        );
        assert!(
            r.ok(),
            "{name}: {} violations, worst {:?}",
            r.violation_count,
            r.violations.first()
        );
        assert!(r.pairs_checked > 0, "{name}: nothing was checked");
    }
}

#[test]
fn every_structure_clears() {
    for (name, t, c) in structures() {
        for cons in [Construction::Flat, Construction::Round] {
            let p = pattern(&t, c.as_deref(), cons, 8, 8);
            // At the stated radius (no compression) the layout is at its
            // tightest, and every structure has pairs within reach.
            let opts = CompileOptions {
                yarn_compression: 1.0,
                ..CompileOptions::default()
            };
            let f = compile(&p, &opts).expect(name);
            let r = clearance(&f, &ClearanceOptions::default());
            let d = 2.0 * p.meta.yarns[0].radius;
            println!(
                "{name:12} {cons:?}: min {:.3} d over {} pairs",
                r.min_distance / d,
                r.pairs_checked
            );
            assert!(
                r.ok(),
                "{name} {cons:?}: {} violations, worst {:?}",
                r.violation_count,
                r.violations.first()
            );
            assert!(r.pairs_checked > 0, "{name}: nothing was checked");
        }
    }
}

#[test]
fn moving_a_node_onto_another_yarn_fails() {
    let p = pattern(&["k"], None, Construction::Flat, 6, 6);
    let mut f = compile(&p, &CompileOptions::default()).unwrap();
    assert!(clearance(&f, &ClearanceOptions::default()).ok());
    // Take a free point in the middle of the yarn and put it on a point of
    // the same yarn two rows further on (far beyond the arc-length window).
    let y = &f.yarns[0];
    let refs = f.node_refcounts();
    let mid = y.points.len() / 3;
    let a = (mid..y.points.len()).find(|&i| refs[y.points[i].node] == 1).unwrap();
    let target = y.points[a + y.points.len() / 3].node;
    let node = y.points[a].node;
    f.nodes[node].x = f.nodes[target].x + Vec3::new(0.0, 0.0, 1e-4);
    let r = clearance(&f, &ClearanceOptions::default());
    assert!(!r.ok());
    assert!(r.min_distance < 0.2e-3, "{}", r.min_distance);
    assert!(r.violations.iter().all(|v| v.distance < v.required));
}

fn meta() -> Meta {
    let p = pattern(&["k"], None, Construction::Flat, 1, 1);
    p.meta
}

fn straight(nodes: &mut Vec<Node>, pts: &[Vec3], shared: Option<(usize, usize)>) -> Yarn {
    let mut points = Vec::new();
    for (i, x) in pts.iter().enumerate() {
        let node = match shared {
            Some((at, n)) if at == i => n,
            _ => {
                nodes.push(Node { x: *x, pinned: false });
                nodes.len() - 1
            }
        };
        points.push(YarnPoint {
            node,
            u: i as f64 * 1e-3,
            fixed_u: true,
            eil: false,
        });
    }
    Yarn {
        layer: 0,
        spec: 0,
        rest_length: (pts.len() - 1) as f64 * 1e-3,
        points,
    }
}

#[test]
fn crossing_yarns_need_a_shared_contact_node() {
    // Two yarns crossing at the origin in the plane z = 0 (radius 0.5 mm,
    // points 2 mm apart, so the next segments are already 2 mm > 1 mm from
    // the other yarn). With the crossing as a shared contact node they are
    // exempt; as two separate nodes at the same place they intersect.
    let h = 2e-3;
    let xs: Vec<Vec3> = (-3..=3).map(|i| Vec3::new(i as f64 * h, 0.0, 0.0)).collect();
    let ys: Vec<Vec3> = (-3..=3).map(|i| Vec3::new(0.0, i as f64 * h, 0.0)).collect();
    let mut nodes = Vec::new();
    let a = straight(&mut nodes, &xs, None);
    let centre = a.points[3].node;
    let b_shared = straight(&mut nodes, &ys, Some((3, centre)));
    let contact = Contact {
        node: centre,
        front: PointRef { yarn: 0, point: 3 },
        back: PointRef { yarn: 1, point: 3 },
        kind: ContactKind::Float,
        partner: None,
    };
    let f = Fabric {
        meta: meta(),
        nodes: nodes.clone(),
        yarns: vec![a.clone(), b_shared],
        contacts: vec![contact],
        sim: None,
    };
    assert!(clearance(&f, &ClearanceOptions::default()).ok());

    let mut nodes2 = nodes.clone();
    let b_apart = straight(&mut nodes2, &ys, None);
    let f = Fabric {
        meta: meta(),
        nodes: nodes2,
        yarns: vec![a, b_apart],
        contacts: vec![],
        sim: None,
    };
    let r = clearance(&f, &ClearanceOptions::default());
    assert!(!r.ok());
    assert!(r.min_distance < 1e-12);
}

#[test]
fn parallel_yarns_just_apart_pass_and_just_closer_fail() {
    // Two straight parallel yarns of radius 0.5 mm: 1.0 mm apart is exactly
    // touching (allowed), 0.95 mm is 5% too close (beyond the 2% tolerance).
    let h = 1e-3;
    for (gap, ok) in [(1.0e-3, true), (0.95e-3, false)] {
        let xs: Vec<Vec3> = (0..8).map(|i| Vec3::new(i as f64 * h, 0.0, 0.0)).collect();
        let ys: Vec<Vec3> = xs.iter().map(|x| x + Vec3::new(0.0, gap, 0.0)).collect();
        let mut nodes = Vec::new();
        let a = straight(&mut nodes, &xs, None);
        let b = straight(&mut nodes, &ys, None);
        let f = Fabric {
            meta: meta(),
            nodes,
            yarns: vec![a, b],
            contacts: vec![],
            sim: None,
        };
        let r = clearance(&f, &ClearanceOptions::default());
        assert_eq!(r.ok(), ok, "gap {gap}: min {}", r.min_distance);
        assert!((r.min_distance - gap).abs() < 1e-12);
    }
}
