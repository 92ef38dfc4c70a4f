//! Scene obstacles (docs/MODEL.md, "Gravity and obstacles"): a penalty on
//! every unpinned node against every obstacle shape, keeping it off by the
//! radius of its thickest yarn.

use super::{set, TermInputs};
use crate::rod::obstacle::ObstaclePenalty;
use crate::sim::discretization::Discretization;
use crate::sim::params::SimParams;
use crate::solver::assembly::AnyStencilSet;

/// The `obstacles` set (none in a scene without obstacles).
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    if t.params.obstacles.is_empty() {
        return Vec::new();
    }
    let (ot, od) = obstacle_terms(t.disc, t.params, &t.radii);
    vec![set("obstacles", ot, od)]
}

/// Every unpinned node against every obstacle, kept off it by the radius of
/// its thickest yarn.
pub(super) fn obstacle_terms(
    disc: &Discretization,
    p: &SimParams,
    radii: &[f64],
) -> (Vec<ObstaclePenalty>, Vec<[u32; 3]>) {
    let (f, l) = (disc.f, disc.l);
    let node_radius = node_thickness(disc, p, radii);
    let (mut t, mut d) = (vec![], vec![]);
    for (n, node) in f.nodes.iter().enumerate() {
        if node.pinned {
            continue;
        }
        let thickness = node_radius[n];
        for s in &p.obstacles {
            t.push(ObstaclePenalty {
                shape: s.clone(),
                thickness,
                stiffness: p.obstacle_stiffness,
            });
            let x = l.x(n) as u32;
            d.push([x, x + 1, x + 2]);
        }
    }
    (t, d)
}

/// The clearance each node keeps from obstacles: the radius of its
/// thickest yarn (`rod.radius` for a node on no yarn).
pub(crate) fn node_thickness(disc: &Discretization, p: &SimParams, radii: &[f64]) -> Vec<f64> {
    let f = disc.f;
    let mut node_radius = vec![0.0f64; f.nodes.len()];
    for (y, yarn) in f.yarns.iter().enumerate() {
        for pt in &yarn.points {
            node_radius[pt.node] = node_radius[pt.node].max(radii[y]);
        }
    }
    for r in &mut node_radius {
        if *r <= 0.0 {
            *r = p.rod.radius;
        }
    }
    node_radius
}
