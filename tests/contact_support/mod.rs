//! Helpers shared by the contact tests: the segment geometry of the state
//! checks (`knitsim::app::checks::segments`, written independently of
//! `knitsim::contact` so it can catch its mistakes: a plain closest distance
//! between segments, a continuous crossing detector between two frames),
//! polyline builders and a runner for pulled single yarns.
#![allow(dead_code)]

#[path = "../common/mod.rs"]
pub mod common;

#[allow(unused_imports)]
pub use knitsim::app::checks::segments::{crossing_pairs, min_separation_where, segment_distance};
use knitsim::sim::{ContactModeName, ContactParams, SimParams, Simulation, Terms};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::{Fabric, Node, Vec3, Yarn, YarnPoint};

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
        layer: 0,
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
