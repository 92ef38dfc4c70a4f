//! Thinning the layout's shape points (opt-in: `CompileOptions::shape_gap`).
//!
//! The layout draws every loop with shape points besides its contacts: a
//! point per leg and row band, the apex, the sinkers, the turns at a flat
//! fabric's edges, and the bends where a leg makes room for a float. They
//! keep the starting yarns apart, and their `u` is fixed. They are
//! optional (docs/MODEL.md, "Stitch contact layout"): a knit can be
//! discretized by its contact nodes alone (four per stitch).
//!
//! Around floats many of them sit closer than a yarn diameter, in rest
//! length, to a contact (a leg's bends lie 0.3 mm from the float crossing
//! it). A rod segment shorter than the yarn is thick resolves no shape of
//! its own; it adds unknowns, a stiff `ks / du` spring, and a fixed point
//! that a sliding contact only gets past through an EIL transition.
//! Dropping the shape points within a diameter of a contact halves a 40x40
//! linen stitch's unknowns, and its relaxation took 100 to 160 Newton
//! iterations over eight seeds instead of 117 to 380, each about half as
//! expensive. The relaxed fabric's width and height moved by 1 to 6%, but
//! it curls out of plane 1.3 to 1.8 times as far (docs/RELAX.md,
//! "Shape gap"), so this is a choice the user makes, not the default. Patterns
//! without floats (stockinette, garter, ribs, seed) have no shape point
//! that close to a contact and come out unchanged.

use super::fabric::Fabric;

/// Drops every droppable shape point of `fabric` whose rest-length distance
/// to the nearest anchor on its yarn, before or after it, is below
/// `gap_diameters` times its yarn's diameter. Droppable: a fixed-`u` point
/// that is not a yarn end, not EIL, and whose node nothing else uses (no
/// contact, no other yarn point, no pin). Anchors: the yarn's other
/// interior points (contacts, pins). Points far from every anchor stay
/// whatever their spacing, so the turns at a flat fabric's edges and the
/// tails keep their shape. Nodes no yarn uses any more are removed and the
/// rest renumbered in their old order, so the result is deterministic.
/// Returns how many points were dropped.
pub fn thin_shape_points(fabric: &mut Fabric, gap_diameters: f64) -> usize {
    if gap_diameters <= 0.0 {
        return 0;
    }
    let mut uses = fabric.node_refcounts().iter().map(|&c| c as usize).collect::<Vec<_>>();
    for c in &fabric.contacts {
        uses[c.node] += 2;
        if let Some(p) = c.partner {
            uses[p] += 2;
        }
    }
    // Points a contact names stay, even in a hand-edited fabric whose
    // contact names a point off its node.
    let mut named: Vec<Vec<bool>> = fabric.yarns.iter().map(|y| vec![false; y.points.len()]).collect();
    for c in &fabric.contacts {
        for p in [c.front, c.back] {
            if let Some(flag) = named.get_mut(p.yarn).and_then(|y| y.get_mut(p.point)) {
                *flag = true;
            }
        }
    }
    let mut point_map: Vec<Vec<Option<usize>>> = Vec::with_capacity(fabric.yarns.len());
    let mut dropped = 0;
    for (yi, yarn) in fabric.yarns.iter_mut().enumerate() {
        let radius = fabric.meta.yarns.get(yarn.spec).map_or(0.0, |s| s.radius);
        let gap = gap_diameters * 2.0 * radius;
        let n = yarn.points.len();
        let droppable: Vec<bool> = (0..n)
            .map(|i| {
                let p = &yarn.points[i];
                let alone = uses[p.node] == 1 && !named[yi][i] && !fabric.nodes[p.node].pinned;
                i > 0 && i + 1 < n && p.fixed_u && !p.eil && alone
            })
            .collect();
        let is_anchor = |i: usize| i > 0 && i + 1 < n && !droppable[i];
        // Rest-length distance to the nearest anchor behind and ahead.
        let mut behind = vec![f64::INFINITY; n];
        let mut last = None;
        for (i, (p, d)) in yarn.points.iter().zip(&mut behind).enumerate() {
            if let Some(a) = last {
                *d = p.u - a;
            }
            if is_anchor(i) {
                last = Some(p.u);
            }
        }
        let mut ahead = vec![f64::INFINITY; n];
        let mut next = None;
        for (i, (p, d)) in yarn.points.iter().zip(&mut ahead).enumerate().rev() {
            if let Some(a) = next {
                *d = a - p.u;
            }
            if is_anchor(i) {
                next = Some(p.u);
            }
        }
        let keep: Vec<bool> = (0..n)
            .map(|i| !(droppable[i] && behind[i].min(ahead[i]) < gap))
            .collect();
        dropped += keep.iter().filter(|k| !**k).count();
        let mut map = vec![None; n];
        let mut kept = Vec::with_capacity(n);
        for (i, p) in yarn.points.drain(..).enumerate() {
            if keep[i] {
                map[i] = Some(kept.len());
                kept.push(p);
            }
        }
        yarn.points = kept;
        point_map.push(map);
    }
    if dropped == 0 {
        return 0;
    }
    for c in &mut fabric.contacts {
        for p in [&mut c.front, &mut c.back] {
            // Named points are never dropped, so the map has them.
            if let Some(kept) = point_map.get(p.yarn).and_then(|m| m.get(p.point)).copied().flatten() {
                p.point = kept;
            }
        }
    }
    renumber_used_nodes(fabric);
    dropped
}

/// Removes nodes that no yarn point and no contact refers to, keeping the
/// others in order.
fn renumber_used_nodes(fabric: &mut Fabric) {
    let mut used = vec![false; fabric.nodes.len()];
    for p in fabric.yarns.iter().flat_map(|y| &y.points) {
        used[p.node] = true;
    }
    for c in &fabric.contacts {
        used[c.node] = true;
        if let Some(p) = c.partner {
            used[p] = true;
        }
    }
    let mut remap = vec![usize::MAX; used.len()];
    let mut nodes = Vec::with_capacity(used.len());
    for (i, node) in fabric.nodes.drain(..).enumerate() {
        if used[i] {
            remap[i] = nodes.len();
            nodes.push(node);
        }
    }
    fabric.nodes = nodes;
    fabric.remap_node_refs(&remap);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pattern::Construction;
    use crate::topology::sample::{chart_pattern, tile};
    use crate::topology::{compile, CompileOptions};

    fn compiled(chart: &[&str], shape_gap: f64) -> Fabric {
        let rows = tile(chart, 8, 8);
        let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
        let p = chart_pattern(&rows, None, Construction::Flat).expect("chart");
        compile(
            &p,
            &CompileOptions {
                shape_gap,
                ..CompileOptions::default()
            },
        )
        .expect("compile")
    }

    const LINEN: [&str; 2] = ["kvkv", "vkvk"];

    /// Indices, order and contact bookkeeping of a thinned fabric.
    fn assert_consistent(f: &Fabric) {
        for y in &f.yarns {
            assert!(y.points.windows(2).all(|s| s[0].u < s[1].u), "u strictly increasing");
            assert!(y.points.iter().all(|p| p.node < f.nodes.len()));
        }
        let refs = f.node_refcounts();
        assert!(refs.iter().all(|&r| r >= 1), "every node is used");
        for c in &f.contacts {
            assert_eq!(f.yarns[c.front.yarn].points[c.front.point].node, c.node);
            assert_eq!(f.yarns[c.back.yarn].points[c.back.point].node, c.node);
        }
    }

    #[test]
    fn thinning_drops_only_shape_points_and_keeps_every_contact_where_it_was() {
        let full = compiled(&LINEN, 0.0);
        // The gap is in model (effective) diameters, 0.6 of the stated ones.
        let thin = compiled(&LINEN, 1.7);
        assert_consistent(&thin);
        assert_eq!(full.contacts.len(), thin.contacts.len());
        assert!(
            thin.nodes.len() < full.nodes.len() * 3 / 4,
            "{} of {}",
            thin.nodes.len(),
            full.nodes.len()
        );
        for (a, b) in full.contacts.iter().zip(&thin.contacts) {
            assert_eq!(a.kind, b.kind);
            assert_eq!(full.nodes[a.node].x, thin.nodes[b.node].x);
            assert_eq!(a.partner.is_some(), b.partner.is_some());
            for (pa, pb) in [(a.front, b.front), (a.back, b.back)] {
                assert_eq!(pa.yarn, pb.yarn);
                let (qa, qb) = (
                    &full.yarns[pa.yarn].points[pa.point],
                    &thin.yarns[pb.yarn].points[pb.point],
                );
                assert_eq!((qa.u, qa.fixed_u), (qb.u, qb.fixed_u));
            }
        }
        for (ya, yb) in full.yarns.iter().zip(&thin.yarns) {
            assert_eq!(ya.rest_length, yb.rest_length);
            assert_eq!(ya.points.first().map(|p| p.u), yb.points.first().map(|p| p.u));
            assert_eq!(ya.points.last().map(|p| p.u), yb.points.last().map(|p| p.u));
            let dropped: Vec<_> = ya
                .points
                .iter()
                .filter(|p| !yb.points.iter().any(|q| q.u == p.u))
                .collect();
            assert!(dropped.iter().all(|p| p.fixed_u), "only fixed-u points go");
        }
    }

    #[test]
    fn every_kept_shape_point_is_a_gap_from_its_anchors_and_thinning_again_drops_nothing() {
        let mut f = compiled(&LINEN, 1.0);
        let uses = f.node_refcounts();
        for y in &f.yarns {
            let gap = 2.0 * f.meta.yarns[y.spec].radius;
            let n = y.points.len();
            let anchor = |i: usize| i > 0 && i + 1 < n && (!y.points[i].fixed_u || uses[y.points[i].node] > 1);
            for i in 1..n - 1 {
                let p = &y.points[i];
                if anchor(i) {
                    continue;
                }
                for j in (1..n - 1).filter(|&j| anchor(j)) {
                    assert!(
                        (y.points[j].u - p.u).abs() >= gap,
                        "kept shape point {i} within the gap of {j}"
                    );
                }
            }
        }
        let before = f.clone();
        assert_eq!(thin_shape_points(&mut f, 1.0), 0);
        assert_eq!(f, before);
    }

    /// The turns at a flat fabric's edges are shape points between shape
    /// points: a plain stockinette, whose loops hold no shape point within
    /// a diameter of a contact, keeps every one of its points.
    #[test]
    fn edge_turns_stay_and_a_stockinette_keeps_every_point() {
        let full = compiled(&["k"], 0.0);
        let thin = compiled(&["k"], 1.0);
        assert_eq!(full, thin);
    }

    #[test]
    fn a_zero_gap_keeps_the_fabric_and_pinned_points_always_stay() {
        let full = compiled(&LINEN, 0.0);
        let mut same = full.clone();
        assert_eq!(thin_shape_points(&mut same, 0.0), 0);
        assert_eq!(same, full);

        // Pin every shape point: a huge gap then drops nothing.
        let mut pinned = full.clone();
        for n in &mut pinned.nodes {
            n.pinned = true;
        }
        assert_eq!(thin_shape_points(&mut pinned, 100.0), 0);
        // Unpinned, every shape point is within 100 diameters of a contact:
        // only contacts and yarn ends are left.
        let mut bare = full.clone();
        assert!(thin_shape_points(&mut bare, 100.0) > 0);
        assert_consistent(&bare);
        let refs = bare.node_refcounts();
        for y in &bare.yarns {
            let inner = &y.points[1..y.points.len() - 1];
            assert!(inner.iter().all(|p| !p.fixed_u || refs[p.node] > 1));
        }
    }

    /// A hand-edited fabric whose contact names a shape point (not the
    /// contact's node): that point stays, and nothing panics.
    #[test]
    fn a_point_a_contact_names_stays_even_off_its_node() {
        let mut f = compiled(&LINEN, 0.0);
        let mut thinned = f.clone();
        thin_shape_points(&mut thinned, 1.0);
        // A shape point that thinning drops: in `f`, not in `thinned`.
        let (yi, pi) = f
            .yarns
            .iter()
            .enumerate()
            .find_map(|(yi, y)| {
                let t = &thinned.yarns[yi];
                let gone = (1..y.points.len() - 1).find(|&i| !t.points.iter().any(|q| q.u == y.points[i].u))?;
                Some((yi, gone))
            })
            .expect("thinning drops a point");
        let u = f.yarns[yi].points[pi].u;
        f.contacts[0].front = crate::topology::PointRef { yarn: yi, point: pi };
        thin_shape_points(&mut f, 1.0);
        let kept = f.yarns[yi]
            .points
            .iter()
            .position(|q| q.u == u)
            .expect("the named point stays");
        assert_eq!(f.contacts[0].front, crate::topology::PointRef { yarn: yi, point: kept });
    }

    #[test]
    fn a_negative_or_nan_gap_is_refused_by_compile() {
        let p = chart_pattern(&LINEN, None, Construction::Flat).expect("chart");
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            let opts = CompileOptions {
                shape_gap: bad,
                ..CompileOptions::default()
            };
            assert!(compile(&p, &opts).is_err(), "{bad}");
        }
    }
}
