//! Fabrics lying on each other: placing patches and joining them with
//! persistent EoL contacts where their yarns touch (*Robust
//! Eulerian-on-Lagrangian Rods*, sec. 5: stacked layers).
//!
//! Why persistent contacts between layers: two tablecloths on a table, a
//! pocket on jeans or a tag on a shirt stay in contact while they slide on
//! each other. An EoL contact follows that sliding through its Eulerian
//! coordinates, without a collision response at every crossing the layers
//! pass. As in the paper, the contacts are found once, at the start
//! ([`join_layers`]): every crossing of a yarn of one layer over a yarn of
//! another, closer than `reach` times the sum of their radii, becomes a
//! [`ContactKind::Layer`] node shared by both yarns, at the midpoint of the
//! two closest points. Both new yarn points have a free `u`, so the yarns
//! slide through it. The simulation removes such a contact when its `u`
//! leaves a yarn (`sim::events::removal`) or, if the scene turns the sign
//! test on, when its normal force pulls the layers together
//! (`sim::events::separation`): a buckling tag lifts off.
//!
//! The yarn of the higher layer (`Yarn::layer`, the later patch) is the
//! contact's front point: the side convention of `sim::events::separation`,
//! whose normals start from `+z`. Stack layers along `z` (gravity along
//! `-z`). Place touching layers at the same height: a contact's two yarns
//! share its node, so layers placed apart are pulled into one surface at
//! their contacts, and start bent (and, with the sign test on, separating).
//!
//! [`sew`] joins two layers along a seam instead: [`ContactKind::Seam`]
//! nodes with fixed `u` on both yarns, which neither slide nor separate.
//!
//! Like [`super::stack::stack_layers`], which merges the patches into one
//! fabric first, this works on a fabric whose points are all real (none
//! EIL): a compiled fabric or a relaxed state.

use super::error::TopologyError;
use super::fabric::{Contact, ContactKind, Fabric, Node, PointRef, Vec3, YarnPoint};
use crate::contact::broad_phase::edge_edge_candidates;
use nalgebra::{Rotation3, Vector3};

/// Where a patch goes in a scene: turned about its own centre (the middle
/// of its bounding box) by `rotate_deg` (degrees about x, then y, then z),
/// then moved by `translate` (m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Placement {
    pub translate: Vec3,
    pub rotate_deg: Vec3,
}

/// Moves every node of `f` by `p`.
pub fn place(f: &mut Fabric, p: &Placement) {
    let (lo, hi) = f.nodes.iter().fold(
        (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
        |(lo, hi), n| (lo.inf(&n.x), hi.sup(&n.x)),
    );
    let centre = if f.nodes.is_empty() {
        Vec3::zeros()
    } else {
        (lo + hi) / 2.0
    };
    let r = p.rotate_deg.map(f64::to_radians);
    let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), r.z)
        * Rotation3::from_axis_angle(&Vector3::y_axis(), r.y)
        * Rotation3::from_axis_angle(&Vector3::x_axis(), r.x);
    for n in &mut f.nodes {
        n.x = centre + rot * (n.x - centre) + p.translate;
    }
}

/// A point to insert on a yarn: on the segment starting at point
/// `after`, at fraction `s` of it.
#[derive(Clone, Copy, Debug)]
struct Insert {
    yarn: usize,
    after: usize,
    s: f64,
}

/// Parameters `(s, t)` in `[0, 1]` of the closest points of segments
/// `a0 a1` and `b0 b1`.
fn closest_parameters(a0: &Vec3, a1: &Vec3, b0: &Vec3, b1: &Vec3) -> (f64, f64) {
    let (da, db, r) = (a1 - a0, b1 - b0, a0 - b0);
    let (aa, bb, ab) = (da.dot(&da), db.dot(&db), da.dot(&db));
    let (ar, br) = (da.dot(&r), db.dot(&r));
    let denom = aa * bb - ab * ab;
    let mut s = if denom > 1e-12 * aa * bb {
        ((ab * br - bb * ar) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = if bb > 0.0 { (ab * s + br) / bb } else { 0.0 };
    if !(0.0..=1.0).contains(&t) {
        t = t.clamp(0.0, 1.0);
        s = if aa > 0.0 {
            ((ab * t - ar) / aa).clamp(0.0, 1.0)
        } else {
            0.0
        };
    }
    (s, t)
}

/// The segments of every yarn as node pairs, with their yarn and first point.
fn segments(f: &Fabric) -> (Vec<[usize; 2]>, Vec<(usize, usize)>) {
    let mut nodes = Vec::new();
    let mut at = Vec::new();
    for (yi, y) in f.yarns.iter().enumerate() {
        for (pi, w) in y.points.windows(2).enumerate() {
            nodes.push([w[0].node, w[1].node]);
            at.push((yi, pi));
        }
    }
    (nodes, at)
}

/// Joins the layers of `f` (each yarn's [`Yarn::layer`](super::Yarn)) with
/// a [`ContactKind::Layer`] contact wherever a yarn of one layer passes a
/// yarn of another closer than `reach` times the sum of their radii, away
/// from both segments' ends. Along each yarn, contacts keep at least one
/// yarn radius (in `u`) from each other and from the yarn's other
/// contacts, so no segment starts degenerate: the closest crossing wins.
/// Returns how many were added.
pub fn join_layers(f: &mut Fabric, reach: f64) -> Result<usize, TopologyError> {
    join(f, reach, &|_, _, _, _| true, ContactKind::Layer)
}

/// Sews layer `top` onto layer `bottom`: like [`join_layers`], but only
/// where a yarn of `top` at a material point that `along(yarn, u)` selects
/// (the seam line, e.g. the points near a patch's edge) passes a yarn of
/// `bottom`, and with [`ContactKind::Seam`] contacts, whose points have
/// fixed `u` on both yarns. Sew before joining the layers, so the seams
/// get the crossings they ask for. Returns how many were added.
pub fn sew(
    f: &mut Fabric,
    (top, bottom): (usize, usize),
    reach: f64,
    along: &dyn Fn(usize, f64) -> bool,
) -> Result<usize, TopologyError> {
    let layer: Vec<usize> = f.yarns.iter().map(|y| y.layer).collect();
    let on_seam = |ya: usize, ua: f64, yb: usize, ub: f64| {
        let (la, lb) = (layer[ya], layer[yb]);
        (la == top && lb == bottom && along(ya, ua)) || (lb == top && la == bottom && along(yb, ub))
    };
    join(f, reach, &on_seam, ContactKind::Seam)
}

/// The crossings between yarns of two layers that `accept(yarn_a, u_a,
/// yarn_b, u_b)` takes, as contacts of `kind` (see [`join_layers`]); a
/// seam's points get fixed `u`.
fn join(
    f: &mut Fabric,
    reach: f64,
    accept: &dyn Fn(usize, f64, usize, f64) -> bool,
    kind: ContactKind,
) -> Result<usize, TopologyError> {
    if f.yarns.iter().flat_map(|y| &y.points).any(|p| p.eil) {
        return Err(TopologyError::Internal(
            "layers are joined on a state without EIL points".into(),
        ));
    }
    let layer_of_yarn: Vec<usize> = f.yarns.iter().map(|y| y.layer).collect();
    if !(reach.is_finite() && reach > 0.0) {
        return Err(TopologyError::BadOption {
            name: "reach",
            value: reach,
            why: "the layer-contact reach must be positive and finite",
        });
    }
    let radius = |y: usize| f.meta.yarns.get(f.yarns[y].spec).map_or(0.0, |s| s.radius);
    let max_r = (0..f.yarns.len()).map(radius).fold(0.0, f64::max);
    let x: Vec<Vec3> = f.nodes.iter().map(|n| n.x).collect();
    let (segs, at) = segments(f);
    let u_of = |ins: &Insert| {
        let p = &f.yarns[ins.yarn].points;
        p[ins.after].u + ins.s * (p[ins.after + 1].u - p[ins.after].u)
    };
    // (distance, insert on the first yarn, insert on the second yarn)
    let mut found: Vec<(f64, Insert, Insert)> = Vec::new();
    for [i, j] in edge_edge_candidates(&x, &segs, 2.0 * reach * max_r) {
        let ((ya, pa), (yb, pb)) = (at[i as usize], at[j as usize]);
        if layer_of_yarn[ya] == layer_of_yarn[yb] {
            continue;
        }
        let ([a0, a1], [b0, b1]) = (segs[i as usize], segs[j as usize]);
        let (s, t) = closest_parameters(&x[a0], &x[a1], &x[b0], &x[b1]);
        let interior = |v: f64| v > 1e-3 && v < 1.0 - 1e-3;
        let d = (x[a0].lerp(&x[a1], s) - x[b0].lerp(&x[b1], t)).norm();
        let (a, b) = (
            Insert { yarn: ya, after: pa, s },
            Insert {
                yarn: yb,
                after: pb,
                s: t,
            },
        );
        if interior(s) && interior(t) && d < reach * (radius(ya) + radius(yb)) && accept(ya, u_of(&a), yb, u_of(&b)) {
            found.push((d, a, b));
        }
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Contact u's taken on each yarn: the existing contacts, then each accepted one.
    let mut taken: Vec<Vec<f64>> = vec![Vec::new(); f.yarns.len()];
    for c in &f.contacts {
        for p in [c.front, c.back] {
            taken[p.yarn].push(f.yarns[p.yarn].points[p.point].u);
        }
    }
    let mut accepted = Vec::new();
    for (_, a, b) in found {
        let (ua, ub) = (u_of(&a), u_of(&b));
        let gap = radius(a.yarn).max(radius(b.yarn));
        let free = |y: usize, u: f64| taken[y].iter().all(|&v| (v - u).abs() >= gap);
        if free(a.yarn, ua) && free(b.yarn, ub) {
            taken[a.yarn].push(ua);
            taken[b.yarn].push(ub);
            accepted.push((a, b));
        }
    }
    let added = accepted.len();
    let upper_first: Vec<bool> = accepted
        .iter()
        .map(|(a, b)| layer_of_yarn[a.yarn] > layer_of_yarn[b.yarn])
        .collect();
    insert_contacts(f, &accepted, &upper_first, kind, kind == ContactKind::Seam);
    Ok(added)
}

/// Adds one contact per pair, on a new node at the midpoint of the two
/// points; the pair's first point is the front one where `a_front` says so.
fn insert_contacts(f: &mut Fabric, pairs: &[(Insert, Insert)], a_front: &[bool], kind: ContactKind, fixed_u: bool) {
    // New points per yarn: (after, s, node), then merged into the yarns.
    let mut new_points: Vec<Vec<(usize, f64, usize, bool)>> = vec![Vec::new(); f.yarns.len()];
    let mut contact_ends = Vec::with_capacity(pairs.len());
    for ((a, b), &a_front) in pairs.iter().zip(a_front) {
        let pos = |i: &Insert| {
            let p = &f.yarns[i.yarn].points;
            f.nodes[p[i.after].node].x.lerp(&f.nodes[p[i.after + 1].node].x, i.s)
        };
        let (xa, xb) = (pos(a), pos(b));
        f.nodes.push(Node {
            x: (xa + xb) / 2.0,
            pinned: false,
        });
        let node = f.nodes.len() - 1;
        for i in [a, b] {
            new_points[i.yarn].push((i.after, i.s, node, fixed_u));
        }
        contact_ends.push((node, a.yarn, b.yarn, a_front));
    }
    // Rebuild each yarn's point list in u order; remember where points went.
    let mut moved: Vec<Vec<usize>> = Vec::with_capacity(f.yarns.len());
    for (yi, y) in f.yarns.iter_mut().enumerate() {
        let mut adds = std::mem::take(&mut new_points[yi]);
        adds.sort_by(|p, q| (p.0, p.1).partial_cmp(&(q.0, q.1)).unwrap_or(std::cmp::Ordering::Equal));
        let old = std::mem::take(&mut y.points);
        let mut map = Vec::with_capacity(old.len());
        let mut k = 0;
        for (i, p) in old.iter().enumerate() {
            map.push(y.points.len());
            y.points.push(p.clone());
            while k < adds.len() && adds[k].0 == i {
                let (_, s, node, fixed) = adds[k];
                let u = p.u + s * (old[i + 1].u - p.u);
                y.points.push(YarnPoint {
                    node,
                    u,
                    fixed_u: fixed,
                    eil: false,
                });
                k += 1;
            }
        }
        moved.push(map);
    }
    for c in &mut f.contacts {
        for p in [&mut c.front, &mut c.back] {
            p.point = moved[p.yarn][p.point];
        }
    }
    for (node, ya, yb, a_front) in contact_ends {
        let find = |y: usize| PointRef {
            yarn: y,
            point: f.yarns[y]
                .points
                .iter()
                .position(|p| p.node == node)
                .expect("inserted point"),
        };
        let (pa, pb) = (find(ya), find(yb));
        let (front, back) = if a_front { (pa, pb) } else { (pb, pa) };
        f.contacts.push(Contact {
            node,
            front,
            back,
            kind,
            partner: None,
        });
    }
}
