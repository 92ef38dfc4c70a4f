//! Where a sliding point stops within one step: bounds on the free `u` of
//! real points, for Newton's projected step
//! ([`Problem::bounds`](crate::solver::newton::Problem::bounds)).
//!
//! Why: the EIL mechanism (docs/MODEL.md, "Node assignment") keeps every real segment at
//! least the safety distance long, but only at the start of a step. Within
//! a step nothing else stops a contact's `u` from running onto its real
//! neighbour, and the stretch term `|dx|^2 / du` of the closing segment
//! stiffens without bound as it does. Measured on a 40x40 linen stitch:
//! stretches of up to nine Newton iterations with the whole step cut to
//! 1/8 .. 1/256 and the gradient norm at 1e3 .. 1e4 N while the energy
//! moved in its third digit, until the step's iteration cap let the re-assignment
//! turn that point EIL. With stops, a real point may slide until its
//! segment is `stop_fraction` of the rest segment (0.05, half the safety
//! distance, when a scene turns them on; off by default, see docs/RELAX.md,
//! "Slide stops") and is held there; the next re-assignment finds it inside
//! the safety distance and hands it to EIL, as the seed intends.
//!
//! Two sliding neighbours share their gap: each may take half of what is
//! left above the stop, so no combination of their moves in one iteration
//! closes the segment past it. A fixed-`u` neighbour (yarn end, resolution
//! node) leaves the whole gap to the sliding point.
//!
//! Bounds are only set with EIL on: without EIL a stopped point would never
//! be handed over, and plain EoL is kept as the seed describes it (it exists
//! to show why EIL matters).

use crate::sim::discretization::Discretization;
use crate::topology::PointRef;

/// One neighbour of a sliding point: its `u` coordinate and whether that
/// `u` slides too (then the gap is shared).
#[derive(Clone, Copy, Debug)]
struct Side {
    u: u32,
    slides: bool,
}

#[derive(Clone, Copy, Debug)]
struct Stop {
    u: u32,
    prev: Option<Side>,
    next: Option<Side>,
    /// Shortest segment this point may leave on either side (m of `u`).
    margin: f64,
}

/// The sliding points of one discretization and their stops.
#[derive(Clone, Debug, Default)]
pub struct SlideStops {
    stops: Vec<Stop>,
}

impl SlideStops {
    /// Every real point with a free `u`, with its real neighbours;
    /// `margin[y]` is yarn `y`'s stop distance.
    pub fn new(disc: &Discretization, margin: &[f64]) -> Self {
        let (f, l) = (disc.f, disc.l);
        let side = |y: usize, pi: usize| Side {
            u: l.u(PointRef { yarn: y, point: pi }) as u32,
            slides: !f.yarns[y].points[pi].fixed_u,
        };
        let mut stops = Vec::new();
        for (y, real) in disc.real.iter().enumerate() {
            for (k, &pi) in real.iter().enumerate() {
                if f.yarns[y].points[pi].fixed_u {
                    continue;
                }
                stops.push(Stop {
                    u: l.u(PointRef { yarn: y, point: pi }) as u32,
                    prev: k.checked_sub(1).map(|j| side(y, real[j])),
                    next: real.get(k + 1).map(|&pj| side(y, pj)),
                    margin: margin[y],
                });
            }
        }
        SlideStops { stops }
    }

    /// Writes this iteration's bounds of every sliding `u` (see the module
    /// docs); returns whether there are any.
    pub fn fill(&self, q: &[f64], lower: &mut [f64], upper: &mut [f64]) -> bool {
        for s in &self.stops {
            let u = q[s.u as usize];
            // `gap`: the segment's current length in `u` (sorted order).
            let room = |side: Side, gap: f64| {
                let left = gap - s.margin;
                let share = if side.slides { 0.5 * left } else { left };
                // A point already at its stop is held there exactly, so
                // Newton sees `q == bound` and can hold it.
                if share > 1e-9 * s.margin {
                    share
                } else {
                    0.0
                }
            };
            if let Some(p) = s.prev {
                lower[s.u as usize] = u - room(p, u - q[p.u as usize]);
            }
            if let Some(n) = s.next {
                upper[s.u as usize] = u + room(n, q[n.u as usize] - u);
            }
        }
        !self.stops.is_empty()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::sim::discretization::assignment::{assign, rest_segment_lengths, tests::meta};
    use crate::sim::discretization::dofs::DofLayout;
    use crate::sim::params::AssignParams;
    use crate::topology::{Fabric, Node, Vec3, Yarn, YarnPoint};

    /// One straight yarn: fixed end, two sliding points, fixed end.
    pub(crate) fn fabric(us: [f64; 4]) -> Fabric {
        let points = us
            .iter()
            .enumerate()
            .map(|(i, &u)| YarnPoint {
                node: i,
                u,
                fixed_u: i == 0 || i == 3,
                eil: false,
            })
            .collect();
        Fabric {
            meta: meta(),
            nodes: us
                .iter()
                .map(|&u| Node {
                    x: Vec3::new(u, 0.0, 0.0),
                    pinned: false,
                })
                .collect(),
            yarns: vec![Yarn {
                layer: 0,
                spec: 0,
                rest_length: 0.9,
                points,
            }],
            contacts: Vec::new(),
            sim: None,
        }
    }

    #[test]
    fn a_fixed_neighbour_leaves_the_whole_gap_and_a_sliding_one_half() {
        let f = fabric([0.0, 0.3, 0.6, 0.9]);
        let l = DofLayout::new(&f);
        let q = l.gather(&f);
        let a = assign(&f, &l, &q, &rest_segment_lengths(&f), AssignParams::default());
        let disc = Discretization::new(&f, &l, &a);
        let stops = SlideStops::new(&disc, &[0.01]);
        let n = q.len();
        let (mut lo, mut hi) = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
        assert!(stops.fill(&q, &mut lo, &mut hi));
        let (u1, u2) = (l.u(PointRef { yarn: 0, point: 1 }), l.u(PointRef { yarn: 0, point: 2 }));
        // Point 1: fixed neighbour behind (gap 0.3), sliding one ahead (0.3).
        assert!((lo[u1] - 0.01).abs() < 1e-12);
        assert!((hi[u1] - (0.3 + 0.145)).abs() < 1e-12);
        assert!((lo[u2] - (0.6 - 0.145)).abs() < 1e-12);
        assert!((hi[u2] - 0.89).abs() < 1e-12);
        // Fixed points and positions are not bounded.
        assert_eq!(lo[l.u(PointRef { yarn: 0, point: 0 })], f64::NEG_INFINITY);
        assert!(lo[..3 * f.nodes.len()].iter().all(|v| *v == f64::NEG_INFINITY));
    }

    #[test]
    fn a_point_at_its_stop_is_bounded_exactly_where_it_is() {
        let f = fabric([0.0, 0.01, 0.6, 0.9]);
        let l = DofLayout::new(&f);
        let q = l.gather(&f);
        let a = assign(
            &f,
            &l,
            &q,
            &rest_segment_lengths(&f),
            AssignParams {
                enable_eil: false,
                ..AssignParams::default()
            },
        );
        let disc = Discretization::new(&f, &l, &a);
        let n = q.len();
        let (mut lo, mut hi) = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
        SlideStops::new(&disc, &[0.01]).fill(&q, &mut lo, &mut hi);
        let u1 = l.u(PointRef { yarn: 0, point: 1 });
        assert_eq!(lo[u1], q[u1]);
        assert!(hi[u1] > q[u1]);
    }
}
