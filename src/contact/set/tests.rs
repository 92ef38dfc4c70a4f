use super::*;

/// A yarn polyline through `points`, one segment per consecutive pair.
fn yarn(points: &[V3], yarn_id: u32, first_node: usize, segs: &mut ContactSegments) {
    for k in 0..points.len() - 1 {
        segs.nodes.push([first_node + k, first_node + k + 1]);
        segs.yarn.push(yarn_id);
        segs.index_in_yarn.push(k as u32);
        segs.rest_length.push((points[k + 1] - points[k]).norm());
    }
}

fn energy(set: &ContactSet, x: &[V3], kappa: f64) -> (usize, f64) {
    let st = set.stencils(x, kappa);
    (st.len(), st.iter().map(|s| s.value(&s.local(x))).sum())
}

/// Straight yarn, segment length 0.1, much finer than h = 0.25.
fn straight() -> (Vec<V3>, ContactSegments) {
    let x: Vec<V3> = (0..40).map(|k| V3::new(0.1 * k as f64, 0.0, 0.0)).collect();
    let mut s = ContactSegments::default();
    yarn(&x, 0, 0, &mut s);
    (x, s)
}

const H: ThicknessParams = ThicknessParams {
    thickness: 0.25,
    core: 0.0,
    penalty_stiffness: 10.0,
};

#[test]
fn rest_yarn_locks_with_plain_barrier_only() {
    let (x, segs) = straight();
    let barrier = ContactSet::build(segs.clone(), ContactMode::Barrier, H);
    let (n, e) = energy(&barrier, &x, 1.0);
    // Pairs (i, i+2) at 0.1 and (i, i+3) at 0.2 are inside h: 37 + 36.
    assert_eq!(n, 73);
    assert!(e > 1e-3, "plain barrier should push at rest: {e}");
    let filtered = ContactSet::build(segs.clone(), ContactMode::Filtered, H);
    assert!((filtered.dbar_min() - 0.1).abs() < 1e-12);
    let (_, e) = energy(&filtered, &x, 1.0);
    assert!(e < 1e-25, "filtered barrier must be silent at rest: {e}");
    let culled = ContactSet::build(segs, ContactMode::Culled { window: 5 }, H);
    assert_eq!(energy(&culled, &x, 1.0).0, 0);
}

#[test]
fn filtered_keeps_full_thickness_for_distant_parts_of_the_yarn() {
    // A hairpin: the yarn comes back 0.2 above itself (closer than h).
    let mut x: Vec<V3> = (0..20).map(|k| V3::new(0.1 * k as f64, 0.0, 0.0)).collect();
    x.extend((0..20).map(|k| V3::new(1.9 - 0.1 * k as f64, 0.0, 0.2)));
    let mut s = ContactSegments::default();
    yarn(&x, 0, 0, &mut s);
    let set = ContactSet::build(s.clone(), ContactMode::Filtered, H);
    let st = set.stencils(&x, 1.0);
    let full: Vec<_> = st
        .iter()
        .filter(|s| matches!(s.energy, ContactEnergy::Barrier(b) if b.shape.activation == 0.25))
        .collect();
    assert!(full.len() > 20, "{} full-thickness stencils", full.len());
    // Culling with a window of 11 keeps them too (they are far apart in index)
    // but a window of 40 drops the whole yarn's self-contact.
    let culled = ContactSet::build(s, ContactMode::Culled { window: 40 }, H);
    assert_eq!(culled.stencils(&x, 1.0).len(), 0);
}

#[test]
fn max_step_stops_before_the_core() {
    // Yarn B crosses above yarn A and is pushed down through it.
    let a: Vec<V3> = (0..11).map(|k| V3::new(0.1 * k as f64 - 0.5, 0.0, 0.0)).collect();
    let b: Vec<V3> = (0..11).map(|k| V3::new(0.0, 0.1 * k as f64 - 0.5, 0.5)).collect();
    let mut s = ContactSegments::default();
    yarn(&a, 0, 0, &mut s);
    yarn(&b, 1, 11, &mut s);
    let x: Vec<V3> = a.iter().chain(&b).copied().collect();
    let dx: Vec<V3> = (0..22)
        .map(|n| if n < 11 { V3::zeros() } else { V3::new(0.0, 0.0, -1.0) })
        .collect();
    let params = ThicknessParams { core: 0.1, ..H };
    let set = ContactSet::build(s, ContactMode::Filtered, params);
    let t = set.max_step(&x, &dx);
    // Impact with the 0.1 core at t = 0.4; additive CCD stops short of it.
    assert!((0.3..=0.4).contains(&t), "{t}");
    let penalty = ContactSet {
        mode: ContactMode::Penalty,
        ..set
    };
    assert_eq!(penalty.max_step(&x, &dx), 1.0);
}
