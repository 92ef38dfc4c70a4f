//! The weight of every rod segment between real points (docs/MODEL.md,
//! "Gravity and obstacles"); `Terms::gravity`, off by default.

use super::rod_segments::segment_dofs;
use super::{set, TermInputs};
use crate::rod::gravity::SegmentGravity;
use crate::solver::assembly::AnyStencilSet;

/// The `gravity` set (none while gravity is off).
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    if !t.params.terms.gravity {
        return Vec::new();
    }
    let rp = &t.params.rod;
    let (mut gt, mut gd) = (vec![], vec![]);
    for (y, real) in t.disc.real.iter().enumerate() {
        for d in segment_dofs(t.disc, y, real) {
            gt.push(SegmentGravity::new(rp.rho, rp.gravity));
            gd.push(d);
        }
    }
    vec![set("gravity", gt, gd)]
}
