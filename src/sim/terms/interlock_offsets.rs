//! Thickness at the interlocks: where each yarn's centre line runs at a
//! stitch or tuck contact (docs/MODEL.md, "Interlock thickness").
//!
//! The two yarns of a persistent contact share one node `X`. Real yarns
//! there are a diameter apart: the front yarn's axis lies `r_front` in
//! front of the touching point, the back yarn's `r_back` behind it, along
//! the contact normal `n` (from the back yarn to the front yarn,
//! `EolState::contact_normals`). The rod energies (stretch and bending) of
//! each yarn are evaluated at `X + offset` for its own point:
//!
//! ```text
//! front yarn: X + s r_front n        back yarn: X - s r_back n
//! ```
//!
//! with `s = SimParams::interlock_thickness` (1 = touching yarns, 0 = the
//! centre-line model, both yarns through `X`).
//!
//! The normal is held for a step and turned with the yarn tangents between
//! steps, as the friction anchors are moved: within a step the offset is a
//! constant translation of the shared node, so the rod stencils keep their
//! derivatives (`energy::shifted`). An equilibrium is a state whose
//! normals the turn leaves unchanged; the relaxation's static residual is
//! measured after the turn, so it tests exactly that.
//!
//! Only stitch and tuck contacts are offset: they are loops through loops,
//! where the yarn wraps its partner. A float crossing is laid out at the
//! float's own depth, and a layer or seam contact joins separate fabrics.

use super::TermInputs;
use crate::topology::{ContactKind, Vec3};

/// The centre-line offset of every global point (zero where there is
/// none); empty when the thickness is off or no normals are tracked.
pub fn interlock_offsets(t: &TermInputs) -> Vec<Vec3> {
    let s = t.params.interlock_thickness;
    let normals = t.step.contact_normals;
    let f = t.disc.f;
    if s == 0.0 || normals.len() != f.contacts.len() {
        return Vec::new();
    }
    let l = t.disc.l;
    let mut offsets = vec![Vec3::zeros(); l.n_points()];
    for (c, n) in f.contacts.iter().zip(normals) {
        if !matches!(c.kind, ContactKind::Stitch | ContactKind::Tuck) {
            continue;
        }
        offsets[l.point(c.front)] = s * t.radii[c.front.yarn] * n;
        offsets[l.point(c.back)] = -s * t.radii[c.back.yarn] * n;
    }
    offsets
}
