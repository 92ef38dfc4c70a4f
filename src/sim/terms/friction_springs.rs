//! Friction at the contacts (docs/MODEL.md, "Friction anchors"): a capped
//! spring on the `u` of every sliding contact point, pulling it back to its
//! anchor with at most its Coulomb limit. The anchors and limits are the
//! step's inputs (`coulomb_limits`).

use super::{set, TermInputs};
use crate::rod::friction::FrictionSpring;
use crate::solver::assembly::AnyStencilSet;

/// The `friction` set (none while friction is off).
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    if !t.params.terms.friction {
        return Vec::new();
    }
    let (f, l, rp) = (t.disc.f, t.disc.l, &t.params.rod);
    let (mut ft, mut fd) = (vec![], vec![]);
    for c in &f.contacts {
        for pr in [c.front, c.back] {
            if !f.yarns[pr.yarn].points[pr.point].fixed_u {
                ft.push(FrictionSpring::new(
                    rp.kf,
                    t.step.anchors[l.point(pr)],
                    t.step.friction_limits[l.point(pr)],
                ));
                fd.push([l.u(pr) as u32]);
            }
        }
    }
    vec![set("friction", ft, fd)]
}
