//! The angles at a crossing: wrapping of a stitch contact's yarns around
//! each other (docs/MODEL.md, "Wrapping") and the crossing shear of float
//! and layer contacts ("Crossing shear"), both against their rest angles.

use super::{set, TermInputs};
use crate::rod::{shear::Shear, wrapping::Wrapping};
use crate::solver::assembly::AnyStencilSet;
use crate::topology::ContactKind;

/// The `wrapping` and `shear` sets, in that order.
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    let (disc, p, rp) = (t.disc, t.params, &t.params.rod);
    let (mut wt, mut wd, mut sht, mut shd) = (vec![], vec![], vec![], vec![]);
    for (ci, c) in disc.f.contacts.iter().enumerate() {
        if p.terms.wrapping && c.kind == ContactKind::Stitch {
            for (role, front) in [(0, true), (1, false)] {
                if let Some(d) = disc.wrap_dofs(ci, front) {
                    wt.push(Wrapping::new(rp.kw(), t.rest.wrap_rest[ci][role]));
                    wd.push(d);
                }
            }
        }
        if p.terms.shear && matches!(c.kind, ContactKind::Float | ContactKind::Layer) {
            if let Some(d) = disc.shear_dofs(ci) {
                sht.push(Shear::new(
                    rp.ksh(),
                    t.rest.shear_rest[ci],
                    rp.shear_jam_angle,
                    rp.shear_jam_gain,
                ));
                shd.push(d);
            }
        }
    }
    vec![set("wrapping", wt, wd), set("shear", sht, shd)]
}
