use super::*;
use crate::io::fixtures::{crossing, meta, push_yarn};
use crate::topology::Vec3;

fn params() -> SimParams {
    let mut p = SimParams::default();
    p.rod.radius = 0.2e-3;
    p
}

/// Two parallel straight yarns `gap` apart (m), radius 0.2 mm each.
fn parallel(gap: f64) -> Fabric {
    let mut f = Fabric {
        meta: meta(&[([0, 0, 0], 0.2e-3)]),
        nodes: vec![],
        yarns: vec![],
        contacts: vec![],
        sim: None,
    };
    for y in [0.0, gap] {
        let xs: Vec<Vec3> = (0..5).map(|k| Vec3::new(k as f64 * 1e-3, y, 0.0)).collect();
        push_yarn(&mut f, 0, &xs);
    }
    f
}

#[test]
fn a_fabric_at_rest_passes_and_its_contact_node_is_no_overlap() {
    let f = crossing();
    let c = check_state(&f, &params(), &Limits::default());
    assert_eq!((c.non_finite, c.overlaps), (0, 0));
    assert!(c.max_strain < 1e-12, "{c:?}");
    assert_eq!(c.rejection(&Limits::default(), true), None);
    let apart = check_state(&parallel(1e-3), &params(), &Limits::default());
    assert_eq!(apart.overlaps, 0);
    assert!(apart.min_gap_ratio.is_infinite(), "{apart:?}");
}

#[test]
fn yarns_inside_each_other_overlap_and_are_rejected_only_with_contact() {
    let f = parallel(0.1e-3);
    let c = check_state(&f, &params(), &Limits::default());
    // Four segments each side, every one within 0.1 mm of up to three.
    assert!(c.overlaps >= 4, "{c:?}");
    assert!((c.min_gap_ratio - 0.25).abs() < 1e-9, "{c:?}");
    // The deepest pair is found between the two yarns, along them.
    let at = c.deepest_overlap_at.expect("an overlap has a place");
    assert!(
        (at[1] - 0.05e-3).abs() < 1e-12 && at[2] == 0.0 && (0.0..=4e-3).contains(&at[0]),
        "{at:?}"
    );
    assert!(c.to_string().contains("deepest overlap at ("), "{c}");
    assert_eq!(
        c.rejection(&Limits::default(), true),
        Some(Rejection::Overlaps(c.overlaps))
    );
    assert_eq!(c.rejection(&Limits::default(), false), None);
    // Touching but not inside: 0.3 mm apart is 0.75 of the radii's sum.
    let c = check_state(&parallel(0.3e-3), &params(), &Limits::default());
    assert_eq!((c.overlaps, c.deepest_overlap_at), (0, None), "{c:?}");
}

#[test]
fn nan_and_stretch_are_counted_and_rejected() {
    let mut f = crossing();
    f.nodes[0].x.x = f64::NAN;
    f.yarns[1].points[0].u = f64::INFINITY;
    let c = check_state(&f, &params(), &Limits::default());
    assert_eq!(c.non_finite, 2);
    assert_eq!(c.rejection(&Limits::default(), false), Some(Rejection::NonFinite(2)));

    // Yarn 0's last segment (2 mm of rest length) pulled to 2.4 mm: 20%.
    let mut f = crossing();
    let last = f.yarns[0].points.last().unwrap().node;
    f.nodes[last].x.x += 0.4e-3;
    let c = check_state(&f, &params(), &Limits::default());
    assert!((c.max_strain - 0.2).abs() < 1e-9, "{c:?}");
    assert_eq!(
        c.rejection(&Limits::default(), false),
        Some(Rejection::Strain(c.max_strain))
    );

    // A real segment without rest length has no finite strain.
    let mut f = crossing();
    let p = &mut f.yarns[1].points;
    p[1].u = p[0].u;
    let c = check_state(&f, &params(), &Limits::default());
    assert!(c.max_strain.is_infinite(), "{c:?}");
}
