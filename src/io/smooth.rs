//! Smooth centre lines for drawing: centripetal Catmull-Rom through the yarn
//! points.
//!
//! The simulation's centre line is a polyline (docs/MODEL.md, "Kinematics":
//! linear interpolation between nodes), but a tube around a coarse polyline shows
//! kinks at every node. The drawn curve therefore interpolates the same
//! points with a C1 spline. We use the *centripetal* parametrisation
//! (knot spacing `|P_{i+1} - P_i|^alpha`, `alpha = 1/2`; Yuksel, Schaefer and
//! Keyser 2011, "Parameterization and applications of Catmull-Rom curves"),
//! because with uneven point spacing, which EoL sliding produces, uniform
//! Catmull-Rom overshoots and forms cusps and small loops; the centripetal
//! variant provably does not. The curve is evaluated with the Barry-Goldman
//! pyramid of linear interpolations, which needs no basis matrix.
//!
//! The centripetal knots are undefined for coincident consecutive points (an
//! EIL node may sit exactly on its neighbour), so those are merged first.

use crate::topology::Vec3;

/// How finely drawn centre lines are resampled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothOptions {
    /// Curve samples per polyline segment (1 keeps the polyline as is).
    pub samples_per_segment: usize,
    /// Consecutive points closer than this fraction of the yarn radius are
    /// merged before smoothing (invisible at drawing scale).
    pub merge_fraction_of_radius: f64,
}

impl Default for SmoothOptions {
    fn default() -> Self {
        Self {
            samples_per_segment: 4,
            merge_fraction_of_radius: 1e-3,
        }
    }
}

/// Drops every point closer than `min_distance` to the last kept one, but
/// always keeps the final point (it is the yarn end) in place of its
/// predecessor.
pub fn merge_close_points(points: &[Vec3], min_distance: f64) -> Vec<Vec3> {
    let mut kept: Vec<Vec3> = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        match kept.last() {
            Some(last) if (p - last).norm() <= min_distance => {
                let is_end = i + 1 == points.len();
                if is_end && kept.len() > 1 {
                    *kept.last_mut().expect("non-empty") = *p;
                }
            }
            _ => kept.push(*p),
        }
    }
    kept
}

/// The drawn centre line of a yarn of radius `radius`: merged points, then
/// `(m - 1) * samples_per_segment + 1` curve samples for `m` merged points.
/// It passes through every merged point (every `samples_per_segment`-th
/// sample). Fewer than two distinct points give the merged points unchanged.
pub fn smooth_centre_line(points: &[Vec3], radius: f64, options: &SmoothOptions) -> Vec<Vec3> {
    let merged = merge_close_points(points, options.merge_fraction_of_radius * radius.abs());
    catmull_rom(&merged, options.samples_per_segment.max(1))
}

/// Centripetal Catmull-Rom samples through `points`, which must have no
/// coincident consecutive entries. The ends use mirrored phantom points
/// (`2 P_0 - P_1`), which makes the curve leave the end along the first chord.
pub fn catmull_rom(points: &[Vec3], samples_per_segment: usize) -> Vec<Vec3> {
    let m = points.len();
    if m < 2 || samples_per_segment <= 1 {
        return points.to_vec();
    }
    let mut out = Vec::with_capacity((m - 1) * samples_per_segment + 1);
    for seg in 0..m - 1 {
        let p1 = points[seg];
        let p2 = points[seg + 1];
        let p0 = if seg == 0 { 2.0 * p1 - p2 } else { points[seg - 1] };
        let p3 = if seg + 2 < m { points[seg + 2] } else { 2.0 * p2 - p1 };
        let segment = CentripetalSegment::new([p0, p1, p2, p3]);
        for k in 0..samples_per_segment {
            out.push(segment.at(k as f64 / samples_per_segment as f64));
        }
    }
    out.push(points[m - 1]);
    out
}

/// One Catmull-Rom span from `p[1]` to `p[2]` with centripetal knots.
struct CentripetalSegment {
    p: [Vec3; 4],
    t: [f64; 4],
}

impl CentripetalSegment {
    fn new(p: [Vec3; 4]) -> Self {
        let mut t = [0.0; 4];
        for i in 1..4 {
            // sqrt of the chord length: alpha = 1/2. The max() guards a
            // phantom or neighbour point that coincides despite merging.
            t[i] = t[i - 1] + (p[i] - p[i - 1]).norm().sqrt().max(f64::MIN_POSITIVE);
        }
        Self { p, t }
    }

    /// Point at fraction `s` in `[0, 1]` of the span (in knot space).
    fn at(&self, s: f64) -> Vec3 {
        let [p0, p1, p2, p3] = self.p;
        let [t0, t1, t2, t3] = self.t;
        let t = t1 + s * (t2 - t1);
        let lerp = |a: Vec3, b: Vec3, ta: f64, tb: f64| a * ((tb - t) / (tb - ta)) + b * ((t - ta) / (tb - ta));
        let a1 = lerp(p0, p1, t0, t1);
        let a2 = lerp(p1, p2, t1, t2);
        let a3 = lerp(p2, p3, t2, t3);
        let b1 = lerp(a1, a2, t0, t2);
        let b2 = lerp(a2, a3, t1, t3);
        lerp(b1, b2, t1, t2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3::new(x, y, z)
    }

    #[test]
    fn passes_through_every_point_and_has_expected_count() {
        let pts = vec![v(0.0, 0.0, 0.0), v(1.0, 2.0, 0.0), v(3.0, 2.5, 1.0), v(4.0, 0.0, 0.0)];
        let s = 5;
        let out = catmull_rom(&pts, s);
        assert_eq!(out.len(), 3 * s + 1);
        for (j, p) in pts.iter().enumerate() {
            assert!((out[j * s] - p).norm() < 1e-12, "point {j}");
        }
    }

    #[test]
    fn collinear_points_stay_on_the_line_and_in_order() {
        // Uneven spacing: the centripetal curve must not overshoot.
        let dir = v(1.0, 2.0, -0.5).normalize();
        let params = [0.0, 0.1, 1.5, 1.6, 4.0];
        let pts: Vec<Vec3> = params.iter().map(|&t| dir * t).collect();
        let out = catmull_rom(&pts, 8);
        let mut last = -1.0;
        for p in &out {
            let along = p.dot(&dir);
            assert!((p - dir * along).norm() < 1e-12);
            assert!(along >= last - 1e-12, "monotone along the line");
            last = along;
        }
    }

    #[test]
    fn points_on_a_circle_give_samples_near_the_circle() {
        let n = 24;
        let pts: Vec<Vec3> = (0..=n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::PI;
                v(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let out = catmull_rom(&pts, 6);
        // Skip the first and last spans: mirrored phantom ends bend them less.
        for p in &out[6..out.len() - 6] {
            assert!((p.norm() - 1.0).abs() < 1e-4, "radius {}", p.norm());
        }
    }

    #[test]
    fn coincident_points_are_merged_keeping_the_end() {
        let pts = vec![
            v(0.0, 0.0, 0.0),
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(1.0 + 1e-9, 0.0, 0.0),
        ];
        let merged = merge_close_points(&pts, 1e-6);
        assert_eq!(merged, vec![v(0.0, 0.0, 0.0), v(1.0 + 1e-9, 0.0, 0.0)]);
        let out = smooth_centre_line(&pts, 1.0, &SmoothOptions::default());
        assert_eq!(out.len(), SmoothOptions::default().samples_per_segment + 1);
        assert!(out.iter().all(|p| p.iter().all(|c| c.is_finite())));
    }

    #[test]
    fn fewer_than_two_points_are_returned_unchanged() {
        assert!(catmull_rom(&[], 4).is_empty());
        assert_eq!(catmull_rom(&[v(1.0, 2.0, 3.0)], 4), vec![v(1.0, 2.0, 3.0)]);
    }
}
