//! Thinning the layout's shape points (opt-in: `CompileOptions::shape_gap`).
//!
//! The layout draws every loop with shape points besides its contacts: a
//! point per leg and row band, the apex, the sinkers, and the bends where a
//! leg makes room for a float. They keep the starting yarns apart, and
//! their `u` is fixed. MODEL.md calls them optional: Cirio 2017 and seed
//! 000 discretize a knit by its contact nodes alone (four per stitch).
//!
//! At tight gauges many of them sit closer than a yarn diameter, in rest
//! length, to a contact or to each other (a float's leg bends lie 0.3 mm
//! from the float). A rod segment shorter than the yarn is thick resolves
//! no shape of its own; it adds unknowns, a stiff `ks / du` spring, and a
//! fixed point that every sliding contact must get past through an EIL
//! transition. Dropping them makes a float pattern's Newton iterations
//! about half as expensive and its relaxation about 2.5 times faster, but
//! it changes the relaxed shape (docs/RELAX.md section 11 has the figures),
//! so it is a choice the user makes, not the default.

use super::fabric::Fabric;

/// Drops every droppable shape point of `fabric` whose rest-length distance
/// to the previous kept point, or to the next point that is kept in any
/// case, is below `gap_diameters` times its yarn's diameter. Droppable: a
/// fixed-`u` point that is not a yarn end, not EIL, and whose node nothing
/// else uses (no contact, no other yarn point, no pin). Nodes no yarn uses
/// any more are removed and the rest renumbered in their old order, so the
/// result is deterministic. Returns how many points were dropped.
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
    let mut point_map: Vec<Vec<Option<usize>>> = Vec::with_capacity(fabric.yarns.len());
    let mut dropped = 0;
    for yarn in &mut fabric.yarns {
        let radius = fabric.meta.yarns.get(yarn.spec).map_or(0.0, |s| s.radius);
        let gap = gap_diameters * 2.0 * radius;
        let n = yarn.points.len();
        let droppable: Vec<bool> = (0..n)
            .map(|i| {
                let p = &yarn.points[i];
                i > 0 && i + 1 < n && p.fixed_u && !p.eil && uses[p.node] == 1 && !fabric.nodes[p.node].pinned
            })
            .collect();
        let mut keep = vec![true; n];
        let mut last_kept = yarn.points.first().map_or(0.0, |p| p.u);
        // The next point kept in any case, found by one backward sweep.
        let mut next_fixed = vec![0.0; n];
        let mut next = yarn.points.last().map_or(0.0, |p| p.u);
        for i in (0..n).rev() {
            next_fixed[i] = next;
            if !droppable[i] {
                next = yarn.points[i].u;
            }
        }
        for i in 0..n {
            let u = yarn.points[i].u;
            if droppable[i] && (u - last_kept < gap || next_fixed[i] - u < gap) {
                keep[i] = false;
                dropped += 1;
            } else {
                last_kept = u;
            }
        }
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
            // Contact points are never droppable (their node has uses > 1).
            p.point = point_map[p.yarn][p.point].expect("a contact point is kept");
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
    for p in fabric.yarns.iter_mut().flat_map(|y| &mut y.points) {
        p.node = remap[p.node];
    }
    for c in &mut fabric.contacts {
        c.node = remap[c.node];
        c.partner = c.partner.map(|p| remap[p]);
    }
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
        let thin = compiled(&LINEN, 1.0);
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
    fn every_kept_shape_point_is_a_gap_away_and_thinning_again_drops_nothing() {
        let mut f = compiled(&LINEN, 1.0);
        let uses = f.node_refcounts();
        for y in &f.yarns {
            let gap = 2.0 * f.meta.yarns[y.spec].radius;
            let n = y.points.len();
            for i in 1..n - 1 {
                let p = &y.points[i];
                if p.fixed_u && uses[p.node] == 1 {
                    assert!(p.u - y.points[i - 1].u >= gap, "kept shape point too close behind");
                    let next = y.points[i + 1..].iter().find(|q| !q.fixed_u || uses[q.node] > 1);
                    let next_u = next.map_or(y.points[n - 1].u, |q| q.u);
                    assert!(next_u - p.u >= gap, "kept shape point too close ahead");
                }
            }
        }
        let before = f.clone();
        assert_eq!(thin_shape_points(&mut f, 1.0), 0);
        assert_eq!(f, before);
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
        // Unpinned, the same gap leaves only contacts and yarn ends.
        let mut bare = full.clone();
        assert!(thin_shape_points(&mut bare, 100.0) > 0);
        assert_consistent(&bare);
        let refs = bare.node_refcounts();
        for y in &bare.yarns {
            let inner = &y.points[1..y.points.len() - 1];
            assert!(inner.iter().all(|p| !p.fixed_u || refs[p.node] > 1));
        }
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
