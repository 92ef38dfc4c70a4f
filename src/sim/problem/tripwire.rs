//! Ends a relaxation step once a real segment has closed: the "hand it to
//! EIL at once" rule.
//!
//! Why: EIL keeps every real segment at least the safety distance long, but
//! only at a step's start (docs/MODEL.md, "Node assignment": the assignment runs per time
//! step). Within a relaxation step nothing else stops a contact's `u` from
//! running onto its real neighbour, and once it has, the closed segment's
//! stretch `ks |dx|^2 / du` makes the Newton matrix as stiff as `ks l^2 /
//! du^3`. Measured on the 80x80 linen stitch's first step: one segment
//! closed to `du` = 7e-14 m at `l` = 2e-10 m and put 1.3e22 on the
//! matrix diagonal (median 2e5); the 13 iterations after the collapse
//! lowered the energy from 2573.37 to 2573.28 J while the gradient norm
//! grew from 4.4e4 to 1e9 .. 3e9 N, and their factorizations took 3.1 to
//! 5.4 s against 0.9 to 1.1 s before (docs/RELAX.md, "Closed segments"). A step
//! that ends at the first iterate with a closed segment
//! goes straight to the next re-assignment, which makes that point EIL.
//!
//! Only relaxation steps trip: a dynamic step must converge to be a step
//! of the time integrator, so it keeps its adaptive-`h` retries. Unlike
//! the sliding stops (`sim::problem::slide_stops`) nothing is held: the iterate that
//! closed the segment is kept as it is, and the next step starts from it.

use crate::sim::discretization::Discretization;
use crate::topology::PointRef;

/// One real segment with a sliding end: its two `u` unknowns (in `u` order)
/// and the length below which it counts as closed.
#[derive(Clone, Copy, Debug)]
struct Watched {
    lo: u32,
    hi: u32,
    closed_below: f64,
}

/// The real segments of one discretization that can close.
#[derive(Clone, Debug, Default)]
pub struct Tripwire {
    segments: Vec<Watched>,
}

impl Tripwire {
    /// Every real segment of `disc` with at least one sliding end;
    /// `closed_below[y]` is yarn `y`'s threshold (m of `u`).
    pub fn new(disc: &Discretization, closed_below: &[f64]) -> Self {
        let (f, l) = (disc.f, disc.l);
        let mut segments = Vec::new();
        for (y, real) in disc.real.iter().enumerate() {
            for w in real.windows(2) {
                let (a, b) = (&f.yarns[y].points[w[0]], &f.yarns[y].points[w[1]]);
                if a.fixed_u && b.fixed_u {
                    continue;
                }
                segments.push(Watched {
                    lo: l.u(PointRef { yarn: y, point: w[0] }) as u32,
                    hi: l.u(PointRef { yarn: y, point: w[1] }) as u32,
                    closed_below: closed_below[y],
                });
            }
        }
        Tripwire { segments }
    }

    /// Whether some watched segment is shorter than its threshold at `q`.
    pub fn tripped(&self, q: &[f64]) -> bool {
        self.segments
            .iter()
            .any(|s| q[s.hi as usize] - q[s.lo as usize] < s.closed_below)
    }

    /// Number of watched segments (0: the tripwire is off).
    pub fn len(&self) -> usize {
        self.segments.len()
    }

    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::discretization::assignment::{assign, rest_segment_lengths};
    use crate::sim::discretization::dofs::DofLayout;
    use crate::sim::params::AssignParams;
    use crate::sim::problem::slide_stops::tests::fabric;

    /// The tripwire of a straight yarn with points at `us` (ends fixed,
    /// the two inner points sliding), its `u` unknowns and its state.
    fn watch(us: [f64; 4], closed_below: f64) -> (Tripwire, [usize; 4], Vec<f64>) {
        let f = fabric(us);
        let l = DofLayout::new(&f);
        let q = l.gather(&f);
        let a = assign(&f, &l, &q, &rest_segment_lengths(&f), AssignParams::default());
        let disc = Discretization::new(&f, &l, &a);
        let u = [0, 1, 2, 3].map(|point| l.u(PointRef { yarn: 0, point }));
        (Tripwire::new(&disc, &[closed_below]), u, q)
    }

    #[test]
    fn a_segment_trips_only_below_its_threshold() {
        let (wire, u, mut q) = watch([0.0, 0.3, 0.6, 0.9], 0.01);
        // Three real segments, each with a sliding end.
        assert_eq!(wire.len(), 3);
        assert!(!wire.tripped(&q));
        // Point 2 slides to 0.0105 short of the fixed end: still open.
        q[u[2]] = 0.9 - 0.0105;
        assert!(!wire.tripped(&q));
        q[u[2]] = 0.9 - 0.0095;
        assert!(wire.tripped(&q));
        // Two sliding points closing on each other trip it too.
        q[u[2]] = 0.6;
        q[u[1]] = 0.6 - 0.005;
        assert!(wire.tripped(&q));
    }

    #[test]
    fn eil_points_and_fixed_pairs_are_not_watched() {
        // Point 1 is EIL at the start (inside the safety distance of point
        // 0), so the real segments are 0-2 and 2-3; both have a sliding end.
        let (wire, _, _) = watch([0.0, 0.001, 0.6, 0.9], 0.01);
        assert_eq!(wire.len(), 2);
        // A yarn of two fixed ends only has nothing to watch.
        let mut f = fabric([0.0, 0.3, 0.6, 0.9]);
        for p in &mut f.yarns[0].points {
            p.fixed_u = true;
        }
        let l = DofLayout::new(&f);
        let q = l.gather(&f);
        let a = assign(&f, &l, &q, &rest_segment_lengths(&f), AssignParams::default());
        assert!(Tripwire::new(&Discretization::new(&f, &l, &a), &[0.01]).is_empty());
    }
}
