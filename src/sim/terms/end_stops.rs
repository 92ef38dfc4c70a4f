//! Secured yarn ends: a knitter weaves the tails in.
//!
//! The compiled yarn ends in a short free tail past its outermost contact
//! (a few mm). Nothing in the rod model keeps that tail from being pulled
//! through the last loop: the fabric's tension slides the contact toward
//! the fixed-`u` end until it falls off. Measured before this term existed:
//! the 8x8 variant of `fig3-jacquard` lost a contact off its yarn's start
//! during relaxation. A designer's pattern never unravels from its tails,
//! so relaxation must not either.
//!
//! The stop is the parallel-contact penalty (`rod::parallel_contact`) between the
//! end's fixed `u` and the outermost contact point's `u`, at a distance of
//! one diameter of that yarn (`SimParams::yarn_radii`), or half the
//! compiled tail if that is shorter (so the compiled state is never inside
//! a stop). Only the fabric's own contacts count: a contact with another
//! layer, or a seam, is not how the yarn's tail is secured, and a layer
//! sliding off another must be free to leave its yarns. It is a term like
//! any other:
//! `Terms::secured_ends` switches it off for scenes that want a tail to
//! pull out.

use super::{set, TermInputs};
use crate::rod::parallel_contact::ParallelContact;
use crate::sim::discretization::Discretization;
use crate::sim::params::SimParams;
use crate::solver::assembly::AnyStencilSet;
use crate::topology::{ContactKind, PointRef};

/// The `yarn-ends` set (none while `Terms::secured_ends` is off).
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    if !t.params.terms.secured_ends {
        return Vec::new();
    }
    let (et, ed) = end_stops(t.disc, t.params, &t.radii);
    vec![set("yarn-ends", et, ed)]
}

/// The stops of every yarn end that has a contact: `(stencil, [u_lo, u_hi])`.
/// `radii` holds each yarn's radius (`SimParams::yarn_radii`).
pub fn end_stops(disc: &Discretization, p: &SimParams, radii: &[f64]) -> (Vec<ParallelContact>, Vec<[u32; 2]>) {
    let (f, l) = (disc.f, disc.l);
    let (mut t, mut d) = (vec![], vec![]);
    for (y, ord) in disc.a.orders().iter().enumerate() {
        let pts = &f.yarns[y].points;
        let contact = |pi: &&usize| {
            disc.contact_at(PointRef { yarn: y, point: **pi })
                .is_some_and(|c| !matches!(c.kind, ContactKind::Layer | ContactKind::Seam))
        };
        let (Some(&start), Some(&end)) = (ord.first(), ord.last()) else {
            continue;
        };
        let ends = [
            (start, ord.iter().find(contact), true),
            (end, ord.iter().rev().find(contact), false),
        ];
        for (e, c, at_start) in ends {
            let Some(&c) = c else { continue };
            if !pts[e].fixed_u || c == e {
                continue;
            }
            // The compiled (rest) tail: `Fabric` keeps the compiled `u`.
            let tail = (pts[c].u - pts[e].u).abs();
            let (ue, uc) = (
                l.u(PointRef { yarn: y, point: e }) as u32,
                l.u(PointRef { yarn: y, point: c }) as u32,
            );
            t.push(ParallelContact::new(p.rod.kp, (2.0 * radii[y]).min(0.5 * tail)));
            d.push(if at_start { [ue, uc] } else { [uc, ue] });
        }
    }
    (t, d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::Stencil;
    use crate::sim::discretization::assignment::{assign, rest_segment_lengths, tests::crossing_fabric};
    use crate::sim::discretization::dofs::DofLayout;
    use crate::sim::params::AssignParams;
    use crate::topology::Fabric;
    use nalgebra::SVector;

    /// Two crossing yarns of length 0.1 m; the contact sits 4 mm from the
    /// start of yarn 0 (a short tail) and mid-way along yarn 1.
    fn crossing() -> Fabric {
        crossing_fabric(
            &[
                [0.004, 0.0, 0.0],
                [0.0, 0.0, 0.0],
                [0.1, 0.0, 0.0],
                [0.004, -0.05, 0.0],
                [0.004, 0.05, 0.0],
            ],
            [
                &[(1, 0.0, true), (0, 0.004, false), (2, 0.1, true)],
                &[(3, 0.0, true), (0, 0.05, false), (4, 0.1, true)],
            ],
            0.1,
            1,
            1,
        )
    }

    #[test]
    fn every_yarn_end_gets_a_stop_a_diameter_or_half_the_tail_long() {
        let f = crossing();
        let l = DofLayout::new(&f);
        let q = l.gather(&f);
        let a = assign(&f, &l, &q, &rest_segment_lengths(&f), AssignParams::default());
        let disc = Discretization::new(&f, &l, &a);
        let p = SimParams::default();
        let (t, d) = end_stops(&disc, &p, &p.yarn_radii(&f));
        assert_eq!(t.len(), 4, "two ends on each of two yarns");
        let u = |y, pi| l.u(PointRef { yarn: y, point: pi }) as u32;
        assert_eq!(d[0], [u(0, 0), u(0, 1)]);
        assert_eq!(d[1], [u(0, 1), u(0, 2)]);
        // Yarn 0's start tail is 4 mm: a diameter (1.5 mm) fits.
        assert_eq!(t[0].diameter, p.rod.diameter());
        // At rest no stop pushes; a contact slid to 0.5 mm from the end is
        // pushed back toward the fabric (positive energy, force away from the end).
        for (s, dd) in t.iter().zip(&d) {
            let x = SVector::<f64, 2>::new(q[dd[0] as usize], q[dd[1] as usize]);
            assert_eq!(s.value(&x), 0.0);
        }
        let slid = SVector::<f64, 2>::new(0.0, 0.0005);
        assert!(t[0].value(&slid) > 0.0);
        assert!(
            t[0].gradient(&slid)[1] < 0.0,
            "energy falls as the contact moves away from the end"
        );
        // Half the tail when the tail is shorter than two diameters.
        let mut short = crossing();
        short.yarns[0].points[1].u = 0.001;
        let l = DofLayout::new(&short);
        let q = l.gather(&short);
        let a = assign(&short, &l, &q, &rest_segment_lengths(&short), AssignParams::default());
        let (t, _) = end_stops(&Discretization::new(&short, &l, &a), &p, &p.yarn_radii(&short));
        assert!((t[0].diameter - 0.0005).abs() < 1e-15);
    }
}
