//! Helpers shared by the contact tests, written independently of
//! `knitsim::contact` so they can catch its mistakes: a plain closest
//! distance between segments, a continuous crossing detector between two
//! frames, polyline builders and a runner for pulled single yarns.
#![allow(dead_code)]

#[path = "../common/mod.rs"]
pub mod common;

use knitsim::sim::{ContactModeName, ContactParams, SimParams, Simulation, Terms};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::{Fabric, Node, Vec3, Yarn, YarnPoint};

/// Closest distance between segments `[p0, p1]` and `[q0, q1]`: minimise
/// over the parameter square by checking the interior stationary point and
/// the four edges (each a clamped point-segment projection).
pub fn segment_distance(p0: &Vec3, p1: &Vec3, q0: &Vec3, q1: &Vec3) -> f64 {
    let point_seg = |x: &Vec3, a: &Vec3, b: &Vec3| {
        let ab = b - a;
        let l2 = ab.norm_squared();
        let t = if l2 > 0.0 {
            ((x - a).dot(&ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (x - (a + ab * t)).norm()
    };
    let mut best = point_seg(p0, q0, q1)
        .min(point_seg(p1, q0, q1))
        .min(point_seg(q0, p0, p1))
        .min(point_seg(q1, p0, p1));
    let (u, v, w) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, b, c, d, e) = (u.dot(&u), u.dot(&v), v.dot(&v), u.dot(&w), v.dot(&w));
    let den = a * c - b * b;
    if den > 1e-14 * a * c {
        let s = (b * e - c * d) / den;
        let t = (a * e - b * d) / den;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            best = best.min((w + u * s - v * t).norm());
        }
    }
    best
}

/// Segments of a single open polyline with `n` points.
pub fn chain(n: usize) -> Vec<[usize; 2]> {
    (0..n - 1).map(|i| [i, i + 1]).collect()
}

/// Smallest distance between segments sharing no node.
pub fn min_separation(x: &[Vec3], segs: &[[usize; 2]]) -> f64 {
    let mut best = f64::INFINITY;
    for (i, a) in segs.iter().enumerate() {
        for b in &segs[i + 1..] {
            if a.iter().any(|n| b.contains(n)) {
                continue;
            }
            best = best.min(segment_distance(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]));
        }
    }
    best
}

/// Number of segment pairs (sharing no node) that pass through each other
/// while every point moves linearly from `x0` to `x1`. Two segments meet
/// only when their four points are coplanar: the triple product
/// `(a1 - a0) x (b1 - b0) . (b0 - a0)` (a cubic in time) vanishes. Its sign
/// changes are found on a fine time grid, refined by bisection, and counted
/// when the segments are (nearly) touching there.
pub fn crossings(x0: &[Vec3], x1: &[Vec3], segs: &[[usize; 2]], touch: f64) -> usize {
    crossings_where(x0, x1, segs, touch, |_, _| false)
}

/// [`crossings`] minus the pairs of segment indices `(i, j)`, `i < j`, for
/// which `skip(i, j)` holds (pairs a simulator deliberately leaves without
/// thickness contact).
pub fn crossings_where(
    x0: &[Vec3],
    x1: &[Vec3],
    segs: &[[usize; 2]],
    touch: f64,
    skip: impl Fn(usize, usize) -> bool,
) -> usize {
    crossing_pairs(x0, x1, segs, touch, skip).len()
}

/// The pairs [`crossings_where`] counts: segment indices `(i, j)` and the
/// time in `[0, 1]` at which they touch.
pub fn crossing_pairs(
    x0: &[Vec3],
    x1: &[Vec3],
    segs: &[[usize; 2]],
    touch: f64,
    skip: impl Fn(usize, usize) -> bool,
) -> Vec<(usize, usize, f64)> {
    let at = |k: usize, t: f64| x0[k] + (x1[k] - x0[k]) * t;
    let triple = |a: &[usize; 2], b: &[usize; 2], t: f64| {
        let (a0, a1, b0, b1) = (at(a[0], t), at(a[1], t), at(b[0], t), at(b[1], t));
        (a1 - a0).cross(&(b1 - b0)).dot(&(b0 - a0))
    };
    let reach: Vec<f64> = (0..x0.len()).map(|k| (x1[k] - x0[k]).norm()).collect();
    let boxes: Vec<(Vec3, Vec3)> = segs.iter().map(|s| bounding_box(&x0[s[0]], &x0[s[1]])).collect();
    let mut found = Vec::new();
    for (i, a) in segs.iter().enumerate() {
        for (j, b) in segs.iter().enumerate().skip(i + 1) {
            if a.iter().any(|n| b.contains(n)) || skip(i, j) {
                continue;
            }
            // Cheap rejection: too far apart at the start for the motion.
            // The boxes' gap is a lower bound of the segments' distance.
            let motion = reach[a[0]].max(reach[a[1]]) + reach[b[0]].max(reach[b[1]]);
            if box_gap(&boxes[i], &boxes[j]) > motion + touch {
                continue;
            }
            let d0 = segment_distance(&x0[a[0]], &x0[a[1]], &x0[b[0]], &x0[b[1]]);
            if d0 > motion + touch {
                continue;
            }
            const K: usize = 64;
            let mut t_prev = 0.0;
            let mut f_prev = triple(a, b, 0.0);
            for s in 1..=K {
                let t = s as f64 / K as f64;
                let f = triple(a, b, t);
                if f_prev == 0.0 || f_prev.signum() != f.signum() {
                    let (mut lo, mut hi, mut flo) = (t_prev, t, f_prev);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        let fm = triple(a, b, mid);
                        if fm.signum() == flo.signum() && fm != 0.0 {
                            lo = mid;
                            flo = fm;
                        } else {
                            hi = mid;
                        }
                    }
                    let t_root = 0.5 * (lo + hi);
                    let (a0, a1, b0, b1) = (at(a[0], t_root), at(a[1], t_root), at(b[0], t_root), at(b[1], t_root));
                    if segment_distance(&a0, &a1, &b0, &b1) < touch {
                        found.push((i, j, t_root));
                        break;
                    }
                }
                t_prev = t;
                f_prev = f;
            }
        }
    }
    found
}

/// [`min_separation`] over the pairs `skip` keeps (see [`crossings_where`]).
pub fn min_separation_where(x: &[Vec3], segs: &[[usize; 2]], skip: impl Fn(usize, usize) -> bool) -> f64 {
    let boxes: Vec<(Vec3, Vec3)> = segs.iter().map(|s| bounding_box(&x[s[0]], &x[s[1]])).collect();
    let mut best = f64::INFINITY;
    for (i, a) in segs.iter().enumerate() {
        for (j, b) in segs.iter().enumerate().skip(i + 1) {
            if box_gap(&boxes[i], &boxes[j]) >= best || a.iter().any(|n| b.contains(n)) || skip(i, j) {
                continue;
            }
            best = best.min(segment_distance(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]));
        }
    }
    best
}

fn bounding_box(p: &Vec3, q: &Vec3) -> (Vec3, Vec3) {
    (p.inf(q), p.sup(q))
}

/// Distance between two axis-aligned boxes (0 when they overlap).
fn box_gap(a: &(Vec3, Vec3), b: &(Vec3, Vec3)) -> f64 {
    let gap = (b.0 - a.1).sup(&(a.0 - b.1)).sup(&Vec3::zeros());
    gap.norm()
}

/// A single Lagrangian yarn through `pts` (all `u` fixed at the polyline
/// arc length, so the initial shape is at rest length).
pub fn polyline_fabric(pts: &[Vec3], radius: f64) -> Fabric {
    let mut u = 0.0;
    let mut points = Vec::new();
    for (k, _) in pts.iter().enumerate() {
        if k > 0 {
            u += (pts[k] - pts[k - 1]).norm();
        }
        points.push(YarnPoint {
            node: k,
            u,
            fixed_u: true,
            eil: false,
        });
    }
    let mut f = Fabric {
        meta: common::meta(radius),
        nodes: vec![],
        yarns: vec![],
        contacts: vec![],
        sim: None,
    };
    f.nodes = pts.iter().map(|&x| Node { x, pinned: false }).collect();
    f.yarns.push(Yarn {
        spec: 0,
        rest_length: u,
        points,
    });
    f
}

/// Resamples a polyline to `n` segments of equal arc length.
pub fn resample(pts: &[Vec3], n: usize) -> Vec<Vec3> {
    let mut cum = vec![0.0];
    for w in pts.windows(2) {
        cum.push(cum.last().unwrap() + (w[1] - w[0]).norm());
    }
    let total = *cum.last().unwrap();
    let mut out = Vec::with_capacity(n + 1);
    let mut k = 0;
    for i in 0..=n {
        let s = total * i as f64 / n as f64;
        while k + 2 < cum.len() && cum[k + 1] < s {
            k += 1;
        }
        let t = ((s - cum[k]) / (cum[k + 1] - cum[k])).clamp(0.0, 1.0);
        out.push(pts[k] + (pts[k + 1] - pts[k]) * t);
    }
    out
}

/// Node positions of a simulation (single-yarn fabrics: node k = point k).
pub fn positions(sim: &Simulation) -> Vec<Vec3> {
    positions_of(sim, sim.q())
}

/// Node positions in a coordinate vector `q` of `sim`'s layout (an iterate
/// from `Simulation::take_iterates`, say).
pub fn positions_of(sim: &Simulation, q: &[f64]) -> Vec<Vec3> {
    (0..sim.layout().n_nodes).map(|i| sim.layout().node_x(q, i)).collect()
}

/// Arc length of a polyline.
pub fn arc_length(x: &[Vec3]) -> f64 {
    x.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// Yarn parameters of the polyester tests of *Unlocking Thickness Modeling
/// for Codimensional Contact Simulation*, elastic terms plus the
/// chosen contact mode, no gravity, no friction.
pub fn yarn_params(radius: f64, mode: ContactModeName, cull_window: u32) -> SimParams {
    let mut p = SimParams {
        terms: Terms {
            gravity: false,
            friction: false,
            ..Terms::default()
        },
        ..SimParams::default()
    };
    p.rod.radius = radius;
    p.contact = Some(ContactParams {
        mode,
        cull_window,
        ..ContactParams::default()
    });
    p
}

pub fn simulation(f: Fabric, p: SimParams) -> Simulation {
    Simulation::new(f, p, LinearSolver::direct(), 1.0)
}
