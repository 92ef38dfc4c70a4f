//! The embedded default drape scene, and the obstacles drawn as triangle
//! meshes for the outputs.
//!
//! Default scene: the relaxed swatch is held where it is, above a sphere of
//! radius `0.35` swatch widths (the larger of its `x` and `y` extents)
//! centred under its middle, whose top lies two yarn radii below the
//! swatch's lowest node; the swatch drops under gravity (9.81 m/s^2) with
//! Coulomb friction `mu = 0.3` against the sphere and air drag, and stops
//! at rest or after 2 s of simulated time (the other settings are
//! [`DynamicsParams::default`]).
//!
//! Air drag is the mass-proportional damping [`AIR_DAMPING`]. A linear drag
//! `alpha M v` stands in for the quadratic drag of a falling sheet: a
//! cotton swatch of about 300 g/m^2 with drag coefficient 1.2 falls at
//! `v = sqrt(2 m g / (rho_air C_d A)) ~ 2 m/s`, and a linear drag with the
//! same terminal speed has `alpha = g / v ~ 5 /s`. Without it nothing but
//! yarn friction and the time stepper's own dissipation stops the swatch
//! swinging on the sphere; a 20 x 16 linen stitch still swung at 6 cm/s
//! after 1 s.

use crate::app::summary::extents;
use crate::rod::obstacle::Shape;
use crate::sim::{DynamicsParams, SimParams};
use crate::topology::Fabric;

/// Sphere radius of the default scene, in swatch widths.
pub const SPHERE_RADIUS_WIDTHS: f64 = 0.35;
/// Coulomb coefficient of the default scene between yarn and sphere.
pub const DEFAULT_MU: f64 = 0.3;
/// Mass-proportional damping of the default scene (1/s): air drag with the
/// terminal speed of a falling swatch (module docs).
pub const AIR_DAMPING: f64 = 5.0;
/// Simulated time (s) after which the default scene stops if the swatch is
/// not yet at rest.
pub const DEFAULT_DURATION: f64 = 2.0;

/// Lowest corner and extents of the fabric's nodes.
fn bounds(f: &Fabric) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    for n in &f.nodes {
        for (k, l) in lo.iter_mut().enumerate() {
            *l = l.min(n.x[k]);
        }
    }
    (lo, extents(f))
}

/// The default scene's sphere under `relaxed`.
pub fn default_sphere(relaxed: &Fabric, yarn_radius: f64) -> Shape {
    let (lo, ext) = bounds(relaxed);
    let width = ext[0].max(ext[1]);
    let radius = SPHERE_RADIUS_WIDTHS * width;
    Shape::Sphere {
        center: [
            lo[0] + 0.5 * ext[0],
            lo[1] + 0.5 * ext[1],
            lo[2] - 2.0 * yarn_radius - radius,
        ],
        radius,
    }
}

/// `params` with the default scene under `relaxed`: the sphere, friction
/// against it, gravity on, air drag.
pub fn with_default_scene(mut params: SimParams, relaxed: &Fabric) -> SimParams {
    let sphere = default_sphere(relaxed, params.rod.radius);
    params.obstacles = vec![sphere];
    params.dynamics = DynamicsParams {
        obstacle_mu: DEFAULT_MU,
        damping: AIR_DAMPING,
        duration: DEFAULT_DURATION,
        ..DynamicsParams::default()
    };
    params
}

/// A triangle mesh: vertices and triangles, with the obstacle of each
/// triangle.
#[derive(Clone, Debug, Default)]
pub struct Triangles {
    pub points: Vec<[f64; 3]>,
    pub triangles: Vec<[usize; 3]>,
    pub ids: Vec<usize>,
}

impl Triangles {
    fn push_quad(&mut self, id: usize, q: [[f64; 3]; 4]) {
        let b = self.points.len();
        self.points.extend(q);
        self.triangles.push([b, b + 1, b + 2]);
        self.triangles.push([b, b + 2, b + 3]);
        self.ids.extend([id, id]);
    }
}

/// Every obstacle as triangles: spheres as latitude-longitude meshes,
/// boxes as their six faces, meshes as they are; the unbounded ones around
/// the point nearest `centre`: planes as a square of side `4 size`,
/// cylinders as a tube of that length.
pub fn obstacle_triangles(shapes: &[Shape], centre: [f64; 3], size: f64) -> Triangles {
    let mut t = Triangles::default();
    for (id, s) in shapes.iter().enumerate() {
        match s {
            Shape::Sphere { center, radius } => {
                let (nu, nv) = (32usize, 16usize);
                let at = |i: usize, j: usize| {
                    let th = std::f64::consts::PI * j as f64 / nv as f64;
                    let ph = 2.0 * std::f64::consts::PI * i as f64 / nu as f64;
                    [
                        center[0] + radius * th.sin() * ph.cos(),
                        center[1] + radius * th.sin() * ph.sin(),
                        center[2] + radius * th.cos(),
                    ]
                };
                for i in 0..nu {
                    for j in 0..nv {
                        t.push_quad(id, [at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
                    }
                }
            }
            Shape::Box {
                center,
                half_extents: h,
            } => {
                let c =
                    |sx: f64, sy: f64, sz: f64| [center[0] + sx * h[0], center[1] + sy * h[1], center[2] + sz * h[2]];
                for s in [-1.0, 1.0] {
                    t.push_quad(id, [c(s, -1.0, -1.0), c(s, 1.0, -1.0), c(s, 1.0, 1.0), c(s, -1.0, 1.0)]);
                    t.push_quad(id, [c(-1.0, s, -1.0), c(1.0, s, -1.0), c(1.0, s, 1.0), c(-1.0, s, 1.0)]);
                    t.push_quad(id, [c(-1.0, -1.0, s), c(1.0, -1.0, s), c(1.0, 1.0, s), c(-1.0, 1.0, s)]);
                }
            }
            Shape::Plane { point, normal } => {
                let n = nalgebra::Vector3::from(*normal).normalize();
                let p = nalgebra::Vector3::from(*point);
                let c = nalgebra::Vector3::from(centre);
                let foot = c - n * n.dot(&(c - p));
                let a = if n.x.abs() < 0.9 {
                    nalgebra::Vector3::x()
                } else {
                    nalgebra::Vector3::y()
                };
                let e1 = (a - n * n.dot(&a)).normalize() * (2.0 * size);
                let e2 = n.cross(&e1);
                let v = |s1: f64, s2: f64| {
                    let q = foot + e1 * s1 + e2 * s2;
                    [q.x, q.y, q.z]
                };
                t.push_quad(id, [v(-1.0, -1.0), v(1.0, -1.0), v(1.0, 1.0), v(-1.0, 1.0)]);
            }
            Shape::Cylinder { point, axis, radius } => {
                let a = nalgebra::Vector3::from(*axis).normalize();
                let p = nalgebra::Vector3::from(*point);
                let c = nalgebra::Vector3::from(centre);
                let mid = p + a * a.dot(&(c - p));
                let any = if a.x.abs() < 0.9 {
                    nalgebra::Vector3::x()
                } else {
                    nalgebra::Vector3::y()
                };
                let e1 = (any - a * a.dot(&any)).normalize();
                let e2 = a.cross(&e1);
                let n = 32usize;
                let at = |i: usize, s: f64| {
                    let ph = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                    let q = mid + (e1 * ph.cos() + e2 * ph.sin()) * *radius + a * (2.0 * size * s);
                    [q.x, q.y, q.z]
                };
                for i in 0..n {
                    t.push_quad(id, [at(i, -1.0), at(i + 1, -1.0), at(i + 1, 1.0), at(i, 1.0)]);
                }
            }
            Shape::Mesh { mesh, .. } => {
                let b = t.points.len();
                t.points.extend(mesh.vertices.iter().map(|v| [v.x, v.y, v.z]));
                t.triangles.extend(mesh.triangles.iter().map(|tri| tri.map(|i| b + i)));
                t.ids.extend(std::iter::repeat_n(id, mesh.triangles.len()));
            }
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sphere_sits_under_the_middle_of_the_swatch() {
        let f = crate::io::fixtures::crossing();
        let (lo, ext) = bounds(&f);
        let Shape::Sphere { center, radius } = default_sphere(&f, 1e-3) else {
            panic!("not a sphere")
        };
        assert!((radius - 0.35 * ext[0].max(ext[1])).abs() < 1e-15);
        assert!((center[2] + radius - (lo[2] - 2e-3)).abs() < 1e-15);
        let t = obstacle_triangles(&[default_sphere(&f, 1e-3)], [0.0; 3], 1.0);
        // Every vertex lies on the sphere.
        for p in &t.points {
            let r = ((p[0] - center[0]).powi(2) + (p[1] - center[1]).powi(2) + (p[2] - center[2]).powi(2)).sqrt();
            assert!((r - radius).abs() < 1e-12);
        }
    }
}
