//! Friction between yarn nodes and scene obstacles (docs/MODEL.md,
//! "Obstacle friction"): one lagged, smoothed Coulomb stencil
//! (`rod::obstacle_friction`) per node that touches an obstacle at the
//! step's start, with the normal force of the obstacle penalty there.
//!
//! Built only in a step with a time step and with
//! `dynamics.obstacle_mu > 0`; a scene without obstacles or friction pays
//! nothing. The step's coordinates `q` are those of its start, so the
//! contact normal, the normal force and the start position all come from
//! `TermInputs::q`.
//!
//! In a stack of layers only the bottom layer's own nodes get friction:
//! - a node on a yarn of a higher layer (`Yarn::layer`) rests on the layer
//!   below, not on the obstacle. Where layers touch, their yarns share
//!   contact nodes, so the centre-line model puts the layers in one surface
//!   and the upper layer's nodes reach the obstacle too (the rendering adds
//!   the thickness); they are kept off it, but without friction. The
//!   bottom layer's grip is then that of its own weight only;
//! - a node that carries a sliding layer contact moves with the contact,
//!   which slides along the yarn beneath, not with that yarn's material, so
//!   friction on the node's displacement would pin the layer above to the
//!   obstacle. The yarn beneath keeps the friction of its own nodes.

use super::obstacle_contact::node_thickness;
use super::{set, TermInputs};
use crate::rod::obstacle_friction::ObstacleFriction;
use crate::solver::assembly::AnyStencilSet;
use crate::topology::ContactKind;
use nalgebra::Vector3;

/// The `obstacle friction` set.
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    let p = t.params;
    let mu = p.dynamics.obstacle_mu;
    let Some((h, _)) = t.step.inertia else {
        return Vec::new();
    };
    if p.obstacles.is_empty() || mu <= 0.0 {
        return Vec::new();
    }
    let eps = p.dynamics.friction_speed * h;
    let thickness = node_thickness(t.disc, p, &t.radii);
    let (f, l) = (t.disc.f, t.disc.l);
    let mut on_layer = vec![false; f.nodes.len()];
    for c in f.contacts.iter().filter(|c| c.kind == ContactKind::Layer) {
        on_layer[c.node] = true;
    }
    for yarn in f.yarns.iter().filter(|y| y.layer > 0) {
        for pt in &yarn.points {
            on_layer[pt.node] = true;
        }
    }
    let (mut st, mut sd) = (vec![], vec![]);
    for (n, node) in f.nodes.iter().enumerate() {
        if node.pinned || on_layer[n] {
            continue;
        }
        let i = l.x(n);
        let x0 = Vector3::new(t.q[i], t.q[i + 1], t.q[i + 2]);
        for shape in &p.obstacles {
            let (s, normal, _) = shape.sdf(&x0);
            let pen = thickness[n] - s;
            if pen > 0.0 {
                let lambda = p.obstacle_stiffness * pen;
                st.push(ObstacleFriction::new(mu * lambda, eps, x0, normal));
                let x = i as u32;
                sd.push([x, x + 1, x + 2]);
            }
        }
    }
    vec![set("obstacle friction", st, sd)]
}
