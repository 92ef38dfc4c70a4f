//! Segment geometry for the state checks, written independently of
//! `crate::contact` so that it can catch that module's mistakes: a plain
//! closest distance between two segments, the smallest separation over a
//! set of segments, and a continuous detector of segments passing through
//! each other while every point moves linearly between two frames.
//!
//! The contact tests use these too (`tests/contact_support`), so the
//! library's checks and the tests' frame-to-frame check are one code.

use crate::topology::Vec3;

/// Closest distance between segments `[p0, p1]` and `[q0, q1]`: minimise
/// over the parameter square by checking the interior stationary point and
/// the four edges (each a clamped point-segment projection).
pub fn segment_distance(p0: &Vec3, p1: &Vec3, q0: &Vec3, q1: &Vec3) -> f64 {
    let point_seg = |x: &Vec3, a: &Vec3, b: &Vec3| {
        let ab = b - a;
        let l2 = ab.norm_squared();
        let t = if l2 > 0.0 {
            ((x - a).dot(&ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (x - (a + ab * t)).norm()
    };
    let mut best = point_seg(p0, q0, q1)
        .min(point_seg(p1, q0, q1))
        .min(point_seg(q0, p0, p1))
        .min(point_seg(q1, p0, p1));
    let (u, v, w) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, b, c, d, e) = (u.dot(&u), u.dot(&v), v.dot(&v), u.dot(&w), v.dot(&w));
    let den = a * c - b * b;
    if den > 1e-14 * a * c {
        let s = (b * e - c * d) / den;
        let t = (a * e - b * d) / den;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            best = best.min((w + u * s - v * t).norm());
        }
    }
    best
}

/// Axis-aligned bounding box of a segment.
pub fn bounding_box(p: &Vec3, q: &Vec3) -> (Vec3, Vec3) {
    (p.inf(q), p.sup(q))
}

/// Distance between two axis-aligned boxes (0 when they overlap); a lower
/// bound of the distance between anything inside them.
pub fn box_gap(a: &(Vec3, Vec3), b: &(Vec3, Vec3)) -> f64 {
    let gap = (b.0 - a.1).sup(&(a.0 - b.1)).sup(&Vec3::zeros());
    gap.norm()
}

/// Smallest distance between segments (node pairs into `x`) sharing no
/// node, over the pairs `(i, j)`, `i < j`, for which `skip(i, j)` is false.
pub fn min_separation_where(x: &[Vec3], segs: &[[usize; 2]], skip: impl Fn(usize, usize) -> bool) -> f64 {
    let boxes: Vec<(Vec3, Vec3)> = segs.iter().map(|s| bounding_box(&x[s[0]], &x[s[1]])).collect();
    let mut best = f64::INFINITY;
    for (i, a) in segs.iter().enumerate() {
        for (j, b) in segs.iter().enumerate().skip(i + 1) {
            if box_gap(&boxes[i], &boxes[j]) >= best || a.iter().any(|n| b.contains(n)) || skip(i, j) {
                continue;
            }
            best = best.min(segment_distance(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]));
        }
    }
    best
}

/// The pairs of segments (sharing no node, `skip(i, j)` false) that pass
/// through each other while every point moves linearly from `x0` to `x1`,
/// with the time in `[0, 1]` at which they touch. Two segments meet only
/// when their four points are coplanar: the triple product
/// `(a1 - a0) x (b1 - b0) . (b0 - a0)` (a cubic in time) vanishes. Its sign
/// changes are found on a fine time grid, refined by bisection, and counted
/// when the segments are closer than `touch` there.
pub fn crossing_pairs(
    x0: &[Vec3],
    x1: &[Vec3],
    segs: &[[usize; 2]],
    touch: f64,
    skip: impl Fn(usize, usize) -> bool,
) -> Vec<(usize, usize, f64)> {
    let at = |k: usize, t: f64| x0[k] + (x1[k] - x0[k]) * t;
    let triple = |a: &[usize; 2], b: &[usize; 2], t: f64| {
        let (a0, a1, b0, b1) = (at(a[0], t), at(a[1], t), at(b[0], t), at(b[1], t));
        (a1 - a0).cross(&(b1 - b0)).dot(&(b0 - a0))
    };
    let reach: Vec<f64> = (0..x0.len()).map(|k| (x1[k] - x0[k]).norm()).collect();
    let boxes: Vec<(Vec3, Vec3)> = segs.iter().map(|s| bounding_box(&x0[s[0]], &x0[s[1]])).collect();
    let mut found = Vec::new();
    for (i, a) in segs.iter().enumerate() {
        for (j, b) in segs.iter().enumerate().skip(i + 1) {
            if a.iter().any(|n| b.contains(n)) || skip(i, j) {
                continue;
            }
            // Cheap rejection: too far apart at the start for the motion.
            let motion = reach[a[0]].max(reach[a[1]]) + reach[b[0]].max(reach[b[1]]);
            if box_gap(&boxes[i], &boxes[j]) > motion + touch {
                continue;
            }
            let d0 = segment_distance(&x0[a[0]], &x0[a[1]], &x0[b[0]], &x0[b[1]]);
            if d0 > motion + touch {
                continue;
            }
            if let Some(t) = first_touch(&triple, a, b, &at, touch) {
                found.push((i, j, t));
            }
        }
    }
    found
}

/// The first root of the triple product of `a` and `b` in `[0, 1]` at
/// which the segments are closer than `touch`.
fn first_touch(
    triple: &impl Fn(&[usize; 2], &[usize; 2], f64) -> f64,
    a: &[usize; 2],
    b: &[usize; 2],
    at: &impl Fn(usize, f64) -> Vec3,
    touch: f64,
) -> Option<f64> {
    const K: usize = 64;
    let mut t_prev = 0.0;
    let mut f_prev = triple(a, b, 0.0);
    for s in 1..=K {
        let t = s as f64 / K as f64;
        let f = triple(a, b, t);
        if f_prev == 0.0 || f_prev.signum() != f.signum() {
            let (mut lo, mut hi, mut flo) = (t_prev, t, f_prev);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                let fm = triple(a, b, mid);
                if fm.signum() == flo.signum() && fm != 0.0 {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            let t_root = 0.5 * (lo + hi);
            let (a0, a1, b0, b1) = (at(a[0], t_root), at(a[1], t_root), at(b[0], t_root), at(b[1], t_root));
            if segment_distance(&a0, &a1, &b0, &b1) < touch {
                return Some(t_root);
            }
        }
        t_prev = t;
        f_prev = f;
    }
    None
}

/// Every pair `(i, j)`, `i < j`, of segments closer than `reach` whose
/// bounding boxes come within `reach`: sweep and prune along the axis of
/// largest extent, so long strips and columns stay near linear.
pub fn close_pairs(x: &[Vec3], segs: &[[usize; 2]], reach: impl Fn(usize, usize) -> f64) -> Vec<(usize, usize, f64)> {
    let boxes: Vec<(Vec3, Vec3)> = segs.iter().map(|s| bounding_box(&x[s[0]], &x[s[1]])).collect();
    let Some((lo, hi)) = boxes.iter().copied().reduce(|a, b| (a.0.inf(&b.0), a.1.sup(&b.1))) else {
        return Vec::new();
    };
    let axis = (hi - lo).imax();
    let max_reach = (0..segs.len()).map(|i| reach(i, i)).fold(0.0, f64::max);
    let mut order: Vec<usize> = (0..segs.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0[axis].total_cmp(&boxes[b].0[axis]));
    let mut out = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if boxes[j].0[axis] > boxes[i].1[axis] + max_reach {
                break;
            }
            let r = reach(i, j);
            if box_gap(&boxes[i], &boxes[j]) >= r {
                continue;
            }
            let (a, b) = (segs[i], segs[j]);
            let d = segment_distance(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]);
            if d < r {
                out.push((i.min(j), i.max(j), d));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3::new(x, y, z)
    }

    #[test]
    fn skew_segments_are_as_far_apart_as_their_common_normal() {
        let d = segment_distance(
            &v(-1.0, 0.0, 0.0),
            &v(1.0, 0.0, 0.0),
            &v(0.0, -1.0, 0.5),
            &v(0.0, 1.0, 0.5),
        );
        assert!((d - 0.5).abs() < 1e-12);
        // Past an end the distance is to that end.
        let d = segment_distance(
            &v(0.0, 0.0, 0.0),
            &v(1.0, 0.0, 0.0),
            &v(2.0, 0.0, 0.0),
            &v(3.0, 0.0, 0.0),
        );
        assert!((d - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_segment_moved_through_another_is_one_crossing_and_a_parallel_move_none() {
        let x0 = vec![v(-1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, -1.0, 1.0), v(0.0, 1.0, 1.0)];
        let mut x1 = x0.clone();
        x1[2].z = -1.0;
        x1[3].z = -1.0;
        let segs = [[0, 1], [2, 3]];
        let found = crossing_pairs(&x0, &x1, &segs, 1e-6, |_, _| false);
        assert_eq!(found.len(), 1);
        assert!((found[0].2 - 0.5).abs() < 1e-6);
        x1[2].z = 0.5;
        x1[3].z = 0.5;
        assert!(crossing_pairs(&x0, &x1, &segs, 1e-6, |_, _| false).is_empty());
    }

    #[test]
    fn close_pairs_agrees_with_every_pair_checked() {
        // Twenty parallel segments stacked along y, 0.19 apart between
        // neighbours (perpendicular to their direction) and 0.38 or more
        // otherwise: a reach of 0.25 finds exactly the neighbours.
        let x: Vec<Vec3> = (0..40).map(|k| v((k % 2) as f64 * 0.3, k as f64 * 0.1, 0.0)).collect();
        let segs: Vec<[usize; 2]> = (0..20).map(|k| [2 * k, 2 * k + 1]).collect();
        let found = close_pairs(&x, &segs, |_, _| 0.25);
        let mut brute = Vec::new();
        for i in 0..segs.len() {
            for j in i + 1..segs.len() {
                let (a, b) = (segs[i], segs[j]);
                let d = segment_distance(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]);
                if d < 0.25 {
                    brute.push((i, j));
                }
            }
        }
        let mut got: Vec<(usize, usize)> = found.iter().map(|p| (p.0, p.1)).collect();
        got.sort_unstable();
        assert_eq!(brute.len(), segs.len() - 1, "{brute:?}");
        assert_eq!(got, brute);
    }
}
