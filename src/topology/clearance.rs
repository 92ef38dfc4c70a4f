//! Clearance: no two yarn segments may come closer than the sum of their
//! radii, except where the model says they touch.
//!
//! In the centre-line model two yarns meet only at their shared contact
//! nodes; everywhere else their centre lines must stay `r_a + r_b` apart or
//! the rendered tubes would intersect (and the relaxation would start from a
//! state its contact barrier cannot represent). Exempt pairs:
//! - segments sharing a node (consecutive on a yarn, or meeting at a contact);
//! - segments both touching the same contact, or the same stitch-contact pair
//!   (a node and its `partner`): near a contact the yarns converge by design;
//! - segments of one yarn within `same_yarn_window` diameters of arc length
//!   of each other: a yarn bends, its own neighbouring segments are close.
//!
//! Broad phase: a uniform grid with cells the size of the largest required
//! distance; each segment is binned by its bounding box and tested against
//! the segments of the cells its inflated box touches. Cost is linear in the
//! number of segments for a fabric at gauge density.

use super::fabric::{Fabric, Vec3};
use std::collections::HashMap;

#[derive(Clone, Debug, PartialEq)]
pub struct ClearanceOptions {
    /// Allowed shortfall, as a fraction of the required distance.
    pub tolerance: f64,
    /// Same-yarn exemption window, in yarn diameters of arc length.
    pub same_yarn_window: f64,
    /// How many violations to list (all are counted).
    pub max_listed: usize,
}

impl Default for ClearanceOptions {
    fn default() -> Self {
        Self {
            tolerance: 0.02,
            same_yarn_window: std::f64::consts::PI,
            max_listed: 100,
        }
    }
}

/// A segment: point `point` to `point + 1` of yarn `yarn`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SegmentRef {
    pub yarn: usize,
    pub point: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    pub a: SegmentRef,
    pub b: SegmentRef,
    pub distance: f64,
    /// `r_a + r_b`.
    pub required: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ClearanceReport {
    /// Smallest distance between non-exempt segments closer than the search
    /// radius (twice the largest required distance); infinite if none.
    pub min_distance: f64,
    /// Smallest `distance / required` over the same pairs.
    pub min_ratio: f64,
    pub pairs_checked: usize,
    pub violation_count: usize,
    /// The first `max_listed` violations, worst first.
    pub violations: Vec<Violation>,
}

impl ClearanceReport {
    pub fn ok(&self) -> bool {
        self.violation_count == 0
    }
}

struct Seg {
    a: Vec3,
    b: Vec3,
    na: usize,
    nb: usize,
    yarn: usize,
    point: usize,
    radius: f64,
    /// Arc length of the start and end along the yarn.
    s0: f64,
    s1: f64,
    /// Contact groups touched by the ends.
    ga: Option<usize>,
    gb: Option<usize>,
}

/// Closest distance between segments `p0 p1` and `q0 q1`.
pub fn segment_distance(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> f64 {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let a = d1.dot(&d1);
    let e = d2.dot(&d2);
    let f = d2.dot(&r);
    let eps = 1e-30;
    let (s, t);
    if a <= eps && e <= eps {
        return r.norm();
    }
    if a <= eps {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= eps {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > eps * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    ((p0 + d1 * s) - (q0 + d2 * t)).norm()
}

fn contact_groups(f: &Fabric) -> Vec<Option<usize>> {
    let mut group = vec![None; f.nodes.len()];
    for c in &f.contacts {
        let g = c.partner.map_or(c.node, |p| p.min(c.node));
        if let Some(slot) = group.get_mut(c.node) {
            *slot = Some(g);
        }
    }
    group
}

fn segments(f: &Fabric) -> Vec<Seg> {
    let group = contact_groups(f);
    let mut out = Vec::new();
    for (yi, y) in f.yarns.iter().enumerate() {
        let radius = f.meta.yarns.get(y.spec).map_or(0.0, |s| s.radius);
        let pos: Vec<Vec3> = (0..y.points.len())
            .map(|p| f.point_position(super::PointRef { yarn: yi, point: p }))
            .collect();
        let mut s = 0.0;
        for p in 0..y.points.len().saturating_sub(1) {
            let len = (pos[p + 1] - pos[p]).norm();
            let (na, nb) = (y.points[p].node, y.points[p + 1].node);
            out.push(Seg {
                a: pos[p],
                b: pos[p + 1],
                na,
                nb,
                yarn: yi,
                point: p,
                radius,
                s0: s,
                s1: s + len,
                ga: group.get(na).copied().flatten(),
                gb: group.get(nb).copied().flatten(),
            });
            s += len;
        }
    }
    out
}

fn exempt(p: &Seg, q: &Seg, window: f64) -> bool {
    if p.na == q.na || p.na == q.nb || p.nb == q.na || p.nb == q.nb {
        return true;
    }
    let groups_p = [p.ga, p.gb];
    if [q.ga, q.gb].iter().flatten().any(|g| groups_p.contains(&Some(*g))) {
        return true;
    }
    if p.yarn == q.yarn {
        let gap = if q.s0 >= p.s1 { q.s0 - p.s1 } else { p.s0 - q.s1 };
        return gap < window * 2.0 * p.radius.max(q.radius);
    }
    false
}

/// Checks every non-exempt pair of segments against `r_a + r_b - tol`.
pub fn clearance(f: &Fabric, opts: &ClearanceOptions) -> ClearanceReport {
    let segs = segments(f);
    let max_r = segs.iter().map(|s| s.radius).fold(0.0, f64::max);
    let mut report = ClearanceReport {
        min_distance: f64::INFINITY,
        min_ratio: f64::INFINITY,
        pairs_checked: 0,
        violation_count: 0,
        violations: Vec::new(),
    };
    if segs.is_empty() || max_r <= 0.0 {
        return report;
    }
    let search = 4.0 * max_r;
    let cell = search;
    let key = |x: f64| (x / cell).floor() as i64;
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, s) in segs.iter().enumerate() {
        let lo = s.a.inf(&s.b);
        let hi = s.a.sup(&s.b);
        for x in key(lo.x)..=key(hi.x) {
            for y in key(lo.y)..=key(hi.y) {
                for z in key(lo.z)..=key(hi.z) {
                    grid.entry((x, y, z)).or_default().push(i);
                }
            }
        }
    }
    let mut seen = vec![usize::MAX; segs.len()];
    let mut all = Vec::new();
    for (i, p) in segs.iter().enumerate() {
        let lo = p.a.inf(&p.b).add_scalar(-search);
        let hi = p.a.sup(&p.b).add_scalar(search);
        for x in key(lo.x)..=key(hi.x) {
            for y in key(lo.y)..=key(hi.y) {
                for z in key(lo.z)..=key(hi.z) {
                    let Some(bucket) = grid.get(&(x, y, z)) else { continue };
                    for &j in bucket {
                        if j <= i || seen[j] == i {
                            continue;
                        }
                        seen[j] = i;
                        let q = &segs[j];
                        if exempt(p, q, opts.same_yarn_window) {
                            continue;
                        }
                        let dist = segment_distance(p.a, p.b, q.a, q.b);
                        if dist > search {
                            continue;
                        }
                        report.pairs_checked += 1;
                        let required = p.radius + q.radius;
                        report.min_distance = report.min_distance.min(dist);
                        report.min_ratio = report.min_ratio.min(dist / required);
                        if dist < required * (1.0 - opts.tolerance) {
                            report.violation_count += 1;
                            all.push(Violation {
                                a: SegmentRef {
                                    yarn: p.yarn,
                                    point: p.point,
                                },
                                b: SegmentRef {
                                    yarn: q.yarn,
                                    point: q.point,
                                },
                                distance: dist,
                                required,
                            });
                        }
                    }
                }
            }
        }
    }
    all.sort_by(|a, b| (a.distance / a.required).total_cmp(&(b.distance / b.required)));
    all.truncate(opts.max_listed);
    report.violations = all;
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_cases() {
        let v = Vec3::new;
        // Skew perpendicular lines one unit apart in z.
        let d = segment_distance(v(-1., 0., 0.), v(1., 0., 0.), v(0., -1., 1.), v(0., 1., 1.));
        assert!((d - 1.0).abs() < 1e-12);
        // Parallel, offset by (3, 4): distance 5 (overlapping in x).
        let d = segment_distance(v(0., 0., 0.), v(2., 0., 0.), v(1., 3., 4.), v(5., 3., 4.));
        assert!((d - 5.0).abs() < 1e-12);
        // Collinear, gap of 1 between ends.
        let d = segment_distance(v(0., 0., 0.), v(1., 0., 0.), v(2., 0., 0.), v(3., 0., 0.));
        assert!((d - 1.0).abs() < 1e-12);
        // Endpoint to interior: (1,1,0) to the x-axis segment.
        let d = segment_distance(v(0., 0., 0.), v(2., 0., 0.), v(1., 1., 0.), v(1., 3., 0.));
        assert!((d - 1.0).abs() < 1e-12);
    }
}
