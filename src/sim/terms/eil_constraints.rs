//! The soft EIL constraint of each contact with an EIL point
//! (docs/MODEL.md, "EIL constraint spring"): the interpolated point is held
//! to its partner's node, or to the partner's own interpolation when both
//! points are EIL. A contact with both points real shares one node and
//! needs no constraint.

use super::{set, TermInputs};
use crate::rod::eil::{EilToEil, EilToPoint};
use crate::sim::discretization::{arr, push3};
use crate::solver::assembly::AnyStencilSet;
use crate::topology::PointRef;

/// The `eil-contact` and `eil-eil-contact` sets, in that order.
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    let (disc, rp) = (t.disc, &t.params.rod);
    let (mut e1t, mut e1d, mut e2t, mut e2d) = (vec![], vec![], vec![], vec![]);
    for c in &disc.f.contacts {
        let (ea, eb) = (disc.is_eil(c.front), disc.is_eil(c.back));
        let kc = |pr: PointRef| rp.contact_stiffness(t.rest.rest_seg[pr.yarn]);
        match (ea, eb) {
            (false, false) => {}
            (true, true) => {
                let mut d = Vec::with_capacity(18);
                if disc.eil_dofs(c.front, &mut d).is_some() && disc.eil_dofs(c.back, &mut d).is_some() {
                    e2t.push(EilToEil::new(kc(c.front).min(kc(c.back))));
                    e2d.push(arr::<18>(d));
                }
            }
            (true, false) | (false, true) => {
                let e = if ea { c.front } else { c.back };
                let mut d = Vec::with_capacity(12);
                if disc.eil_dofs(e, &mut d).is_some() {
                    push3(&mut d, disc.l.x(c.node));
                    e1t.push(EilToPoint::new(kc(e)));
                    e1d.push(arr::<12>(d));
                }
            }
        }
    }
    vec![set("eil-contact", e1t, e1d), set("eil-eil-contact", e2t, e2d)]
}
