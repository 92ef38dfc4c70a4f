//! A tiny z-buffered ray caster for capsules, seen orthographically from +z.
//!
//! Each centre-line segment of radius `r` is drawn as a capsule (all points
//! within `r` of the segment), the exact shape of a tube with round joints,
//! so consecutive segments join without gaps at any angle. For every pixel
//! the view ray is the vertical line through the pixel centre; the visible
//! surface is the *highest* intersection (largest z, nearest the viewer).
//!
//! The capsule is the union of a finite cylinder and two end spheres, so its
//! top along the ray is the highest of (a) the lateral cylinder hit, when its
//! axial coordinate lies within the segment, and (b) the tops of the two
//! spheres. (Where the lateral top falls outside the segment the ray can
//! only enter through an end disc, which lies inside that end's sphere.)
//!
//! Lateral hit, derived here: with unit axis `d` from `a`, and the ray point
//! `q = a + e + h z^` (`e` the in-plane offset from `a`, `h` the height above
//! `a`), the distance to the axis is `r` where
//! `|e + h z^|^2 - ((e + h z^) . d)^2 = r^2`, a quadratic in `h`:
//! `(1 - d_z^2) h^2 - 2 (e.d) d_z h + |e|^2 - (e.d)^2 - r^2 = 0`;
//! the larger root is the top. Its surface normal is the radial direction.

use crate::topology::Vec3;

/// Colour and depth buffers; row 0 is the top of the image.
pub(crate) struct Canvas {
    pub width: usize,
    pub height: usize,
    /// Linear RGB in `[0, 1]` per pixel.
    pub color: Vec<[f64; 3]>,
    depth: Vec<f64>,
    /// World coordinates of the left and top image edges, and pixels per world unit.
    left: f64,
    top: f64,
    scale: f64,
}

/// Lambert plus ambient, `ambient + (1 - ambient) max(0, n . light)`, times
/// a silhouette darkening `1 - edge (1 - n_z)` that outlines every yarn
/// where it dips away from the viewer, so same-coloured crossings stay
/// readable whatever the light direction. Then a depth cue: the surface is
/// mixed with the background in proportion `fade (near_z - z) / (near_z -
/// far_z)`, so what lies behind the front layer (WS floats seen through
/// the open starting lattice, heads behind the legs) recedes, as it does
/// in a real fabric where it is hidden or in shadow.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shading {
    pub ambient: f64,
    /// Unit vector towards the light.
    pub light: Vec3,
    pub edge: f64,
    /// Largest share of background at `far_z`, in `[0, 1]` (0 = no cue).
    pub fade: f64,
    pub near_z: f64,
    pub far_z: f64,
    /// Linear RGB.
    pub background: [f64; 3],
}

impl Shading {
    fn factor(&self, normal: &Vec3) -> f64 {
        let lambert = self.ambient + (1.0 - self.ambient) * normal.dot(&self.light).max(0.0);
        lambert * (1.0 - self.edge * (1.0 - normal.z.max(0.0)))
    }

    /// Shaded linear colour of a surface point at height `z`.
    fn colour(&self, base: [f64; 3], normal: &Vec3, z: f64) -> [f64; 3] {
        let light = self.factor(normal);
        let span = self.near_z - self.far_z;
        let depth = if span > 0.0 {
            ((self.near_z - z) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let t = self.fade * depth;
        let mut out = [0.0; 3];
        for ((o, c), bg) in out.iter_mut().zip(base).zip(self.background) {
            *o = (1.0 - t) * c * light + t * bg;
        }
        out
    }
}

impl Canvas {
    pub fn new(width: usize, height: usize, left: f64, top: f64, scale: f64, background: [f64; 3]) -> Self {
        Self {
            width,
            height,
            color: vec![background; width * height],
            depth: vec![f64::NEG_INFINITY; width * height],
            left,
            top,
            scale,
        }
    }

    /// World position of a pixel centre.
    fn pixel_centre(&self, col: usize, row: usize) -> (f64, f64) {
        (
            self.left + (col as f64 + 0.5) / self.scale,
            self.top - (row as f64 + 0.5) / self.scale,
        )
    }

    /// Draws the capsule around segment `a`-`b`, where it is nearer the viewer
    /// than what is already there.
    pub fn draw_capsule(&mut self, a: Vec3, b: Vec3, radius: f64, base: [f64; 3], shading: &Shading) {
        let to_px_col = |x: f64| (x - self.left) * self.scale;
        let to_px_row = |y: f64| (self.top - y) * self.scale;
        let col_range = pixel_range(
            to_px_col(a.x.min(b.x) - radius),
            to_px_col(a.x.max(b.x) + radius),
            self.width,
        );
        let row_range = pixel_range(
            to_px_row(a.y.max(b.y) + radius),
            to_px_row(a.y.min(b.y) - radius),
            self.height,
        );
        let capsule = Capsule::new(a, b, radius);
        // Nothing of the capsule is above this: pixels already nearer skip
        // the ray test.
        let capsule_top = a.z.max(b.z) + radius;
        for row in row_range {
            for col in col_range.clone() {
                let i = row * self.width + col;
                if self.depth[i] >= capsule_top {
                    continue;
                }
                let (x, y) = self.pixel_centre(col, row);
                let Some((z, normal)) = capsule.top(x, y) else {
                    continue;
                };
                if z > self.depth[i] {
                    self.depth[i] = z;
                    self.color[i] = shading.colour(base, &normal, z);
                }
            }
        }
    }
}

/// Pixel indices whose centres may lie in `[lo, hi]` (pixel units), clipped.
fn pixel_range(lo: f64, hi: f64, size: usize) -> std::ops::Range<usize> {
    let start = lo.floor().max(0.0) as usize;
    let end = (hi.ceil().max(0.0) as usize).min(size);
    start.min(end)..end
}

struct Capsule {
    a: Vec3,
    b: Vec3,
    radius: f64,
    /// Unit axis and length; `None` for a degenerate (sphere) capsule.
    axis: Option<(Vec3, f64)>,
}

impl Capsule {
    fn new(a: Vec3, b: Vec3, radius: f64) -> Self {
        let ab = b - a;
        let len = ab.norm();
        let axis = (len > 0.0).then(|| (ab / len, len));
        Self { a, b, radius, axis }
    }

    /// Highest surface point on the vertical line through `(x, y)`: its
    /// height and unit outward normal.
    fn top(&self, x: f64, y: f64) -> Option<(f64, Vec3)> {
        // Seen from +z the capsule covers exactly the points within `radius`
        // of the projected segment: one cheap test rejects most pixels of
        // the bounding box of a slanted span.
        if self.projected_distance_squared(x, y) > self.radius * self.radius {
            return None;
        }
        let mut best = sphere_top(self.a, self.radius, x, y);
        let mut consider = |hit: Option<(f64, Vec3)>| {
            if let Some(h) = hit {
                if best.is_none_or(|b| h.0 > b.0) {
                    best = Some(h);
                }
            }
        };
        consider(sphere_top(self.b, self.radius, x, y));
        consider(self.lateral_top(x, y));
        best
    }

    fn projected_distance_squared(&self, x: f64, y: f64) -> f64 {
        let (ex, ey) = (x - self.a.x, y - self.a.y);
        let (dx, dy) = (self.b.x - self.a.x, self.b.y - self.a.y);
        let len2 = dx * dx + dy * dy;
        let s = if len2 > 0.0 {
            ((ex * dx + ey * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (px, py) = (ex - s * dx, ey - s * dy);
        px * px + py * py
    }

    fn lateral_top(&self, x: f64, y: f64) -> Option<(f64, Vec3)> {
        let (d, len) = self.axis?;
        let e = Vec3::new(x - self.a.x, y - self.a.y, 0.0);
        let qa = 1.0 - d.z * d.z;
        // A vertical axis is seen end-on: its top is an end sphere.
        if qa < 1e-12 {
            return None;
        }
        let ed = e.dot(&d);
        let half_b = -ed * d.z;
        let c = e.dot(&e) - ed * ed - self.radius * self.radius;
        let disc = half_b * half_b - qa * c;
        if disc < 0.0 {
            return None;
        }
        let h = (-half_b + disc.sqrt()) / qa;
        let rel = e + Vec3::z() * h;
        let s = rel.dot(&d);
        if !(0.0..=len).contains(&s) {
            return None;
        }
        let normal = (rel - d * s) / self.radius;
        Some((self.a.z + h, normal))
    }
}

fn sphere_top(c: Vec3, radius: f64, x: f64, y: f64) -> Option<(f64, Vec3)> {
    let (dx, dy) = (x - c.x, y - c.y);
    let h2 = radius * radius - dx * dx - dy * dy;
    (h2 >= 0.0).then(|| {
        let h = h2.sqrt();
        (c.z + h, Vec3::new(dx, dy, h) / radius)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn capsule_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
        let ab = b - a;
        let s = ((p - a).dot(&ab) / ab.dot(&ab)).clamp(0.0, 1.0);
        (p - (a + ab * s)).norm()
    }

    #[test]
    fn top_hit_lies_on_the_surface_and_nothing_above_it() {
        // A tilted segment; check against brute-force distance along the ray.
        let (a, b, r) = (Vec3::new(-1.0, -0.5, 0.2), Vec3::new(1.0, 0.7, -0.6), 0.4);
        let cap = Capsule::new(a, b, r);
        let mut hits = 0;
        for i in 0..40 {
            for j in 0..40 {
                let (x, y) = (-1.6 + i as f64 * 0.08, -1.2 + j as f64 * 0.06);
                let Some((z, n)) = cap.top(x, y) else {
                    // No hit: the whole vertical line stays outside.
                    let min = (0..400)
                        .map(|k| capsule_distance(Vec3::new(x, y, -2.0 + k as f64 * 0.01), a, b))
                        .fold(f64::INFINITY, f64::min);
                    assert!(min >= r - 1e-2, "missed a hit at ({x}, {y})");
                    continue;
                };
                hits += 1;
                let p = Vec3::new(x, y, z);
                assert!((capsule_distance(p, a, b) - r).abs() < 1e-9);
                assert!((n.norm() - 1.0).abs() < 1e-9);
                assert!(
                    capsule_distance(p + Vec3::z() * 1e-6, a, b) > r,
                    "a higher point is inside"
                );
            }
        }
        assert!(hits > 100);
    }

    #[test]
    fn nearer_capsule_wins_the_depth_test() {
        let shade = Shading {
            ambient: 1.0,
            light: Vec3::z(),
            edge: 0.0,
            fade: 0.0,
            near_z: 0.0,
            far_z: 0.0,
            background: [1.0; 3],
        };
        let mut canvas = Canvas::new(10, 10, 0.0, 10.0, 1.0, [1.0; 3]);
        // Red below (z = 0), green above (z = 1), crossing at the centre.
        let (red, green) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        canvas.draw_capsule(Vec3::new(5.0, 0.0, 1.0), Vec3::new(5.0, 10.0, 1.0), 1.0, green, &shade);
        canvas.draw_capsule(Vec3::new(0.0, 5.0, 0.0), Vec3::new(10.0, 5.0, 0.0), 1.0, red, &shade);
        assert_eq!(canvas.color[4 * 10 + 4], green, "crossing shows the upper yarn");
        assert_eq!(canvas.color[4 * 10 + 1], red);
        assert_eq!(canvas.color[0], [1.0; 3], "background");
    }
}
