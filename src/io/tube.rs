//! Tube meshes around centre lines.
//!
//! Rings of `sides` vertices are placed at every centre-line sample, in the
//! plane normal to the tangent. The ring orientation comes from a
//! rotation-minimising frame propagated along the curve by the double
//! reflection method (Wang, Juttler, Zheng and Liu 2008, "Computation of
//! rotation minimizing frames", ACM TOG 27(1)): two reflections per step
//! carry the previous frame onto the new tangent without twisting about it,
//! which a Frenet frame (undefined on straight parts, flipping at
//! inflections) or a fixed "up" vector (degenerate where the yarn points up,
//! as yarns do through a stitch) would not.
//!
//! Layout, which the counts in the tests and the OBJ read-back rely on, for
//! `n` samples and `k` sides: `n * k` side vertices (ring by ring), then, if
//! capped, for each end one centre vertex followed by a copy of the end ring
//! (`k + 1` each) carrying the flat cap normal. Triangles: `2 (n - 1) k` on
//! the side, `k` per cap. Every vertex has its own normal, so position and
//! normal indices coincide (meshio requires as many `vn` as `v`).

use crate::topology::Vec3;
use std::f64::consts::TAU;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TubeOptions {
    /// Vertices around each ring (at least 3).
    pub sides: usize,
    /// Close both ends with flat discs.
    pub caps: bool,
}

impl Default for TubeOptions {
    fn default() -> Self {
        Self { sides: 12, caps: true }
    }
}

/// Triangle mesh with one normal per vertex; triangles are counter-clockwise
/// seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TubeMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[usize; 3]>,
}

/// Tube of `radius` around `centre`; empty for fewer than two samples.
pub fn tube_around(centre: &[Vec3], radius: f64, options: &TubeOptions) -> TubeMesh {
    let n = centre.len();
    let k = options.sides.max(3);
    let mut mesh = TubeMesh::default();
    if n < 2 {
        return mesh;
    }
    let tangents = tangents(centre);
    let normals = transported_normals(centre, &tangents);
    let ring_dirs = |i: usize| {
        let r = normals[i];
        let b = tangents[i].cross(&r);
        (0..k).map(move |j| {
            let angle = TAU * j as f64 / k as f64;
            r * angle.cos() + b * angle.sin()
        })
    };
    for (i, c) in centre.iter().enumerate() {
        for dir in ring_dirs(i) {
            mesh.positions.push(c + dir * radius);
            mesh.normals.push(dir);
        }
    }
    for i in 0..n - 1 {
        for j in 0..k {
            let a = i * k + j;
            let b = i * k + (j + 1) % k;
            let (c, d) = (b + k, a + k);
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    if options.caps {
        for (end, outward) in [(0, -tangents[0]), (n - 1, tangents[n - 1])] {
            let centre_index = mesh.positions.len();
            mesh.positions.push(centre[end]);
            mesh.normals.push(outward);
            for dir in ring_dirs(end) {
                mesh.positions.push(centre[end] + dir * radius);
                mesh.normals.push(outward);
            }
            // Ring order turns positively about the tangent, so the start
            // cap (facing -t) is wound the other way round.
            for j in 0..k {
                let (p, q) = (centre_index + 1 + j, centre_index + 1 + (j + 1) % k);
                mesh.triangles.push(if end == 0 {
                    [centre_index, q, p]
                } else {
                    [centre_index, p, q]
                });
            }
        }
    }
    mesh
}

/// Unit tangents: central differences inside, one-sided at the ends. A zero
/// difference (the curve doubles back exactly) reuses the previous tangent.
fn tangents(c: &[Vec3]) -> Vec<Vec3> {
    let n = c.len();
    let mut out: Vec<Vec3> = Vec::with_capacity(n);
    for i in 0..n {
        let d = c[(i + 1).min(n - 1)] - c[i.saturating_sub(1)];
        let fallback = out.last().copied().unwrap_or_else(Vec3::x);
        out.push(d.try_normalize(1e-300).unwrap_or(fallback));
    }
    out
}

/// Ring reference directions, rotation-minimising along the curve (double
/// reflection, Wang et al. 2008, Algorithm 1).
fn transported_normals(c: &[Vec3], t: &[Vec3]) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(c.len());
    out.push(any_perpendicular(&t[0]));
    for i in 0..c.len() - 1 {
        let r = out[i];
        let v1 = c[i + 1] - c[i];
        let c1 = v1.dot(&v1);
        let (r_l, t_l) = if c1 > 0.0 {
            (r - v1 * (2.0 / c1 * v1.dot(&r)), t[i] - v1 * (2.0 / c1 * v1.dot(&t[i])))
        } else {
            (r, t[i])
        };
        let v2 = t[i + 1] - t_l;
        let c2 = v2.dot(&v2);
        let next = if c2 > 0.0 {
            r_l - v2 * (2.0 / c2 * v2.dot(&r_l))
        } else {
            r_l
        };
        // Re-orthonormalise against round-off drift over long yarns.
        let next = (next - t[i + 1] * next.dot(&t[i + 1]))
            .try_normalize(1e-12)
            .unwrap_or_else(|| any_perpendicular(&t[i + 1]));
        out.push(next);
    }
    out
}

/// A unit vector perpendicular to unit `t`, built from the axis least
/// aligned with it (well conditioned for every `t`).
fn any_perpendicular(t: &Vec3) -> Vec3 {
    let axis = if t.x.abs() <= t.y.abs() && t.x.abs() <= t.z.abs() {
        Vec3::x()
    } else if t.y.abs() <= t.z.abs() {
        Vec3::y()
    } else {
        Vec3::z()
    };
    t.cross(&axis).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn helix(n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let a = i as f64 * 0.3;
                Vec3::new(a.cos(), a.sin(), 0.2 * a)
            })
            .collect()
    }

    #[test]
    fn counts_match_the_documented_layout() {
        let (n, k) = (7, 5);
        let mesh = tube_around(&helix(n), 0.1, &TubeOptions { sides: k, caps: true });
        assert_eq!(mesh.positions.len(), n * k + 2 * (k + 1));
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        assert_eq!(mesh.triangles.len(), 2 * (n - 1) * k + 2 * k);
        let open = tube_around(&helix(n), 0.1, &TubeOptions { sides: k, caps: false });
        assert_eq!(open.positions.len(), n * k);
        assert_eq!(open.triangles.len(), 2 * (n - 1) * k);
    }

    #[test]
    fn side_vertices_are_at_radius_in_the_normal_plane() {
        let centre = helix(20);
        let (k, radius) = (8, 0.05);
        let mesh = tube_around(&centre, radius, &TubeOptions { sides: k, caps: false });
        let t = tangents(&centre);
        for (i, c) in centre.iter().enumerate() {
            for j in 0..k {
                let offset = mesh.positions[i * k + j] - c;
                assert!((offset.norm() - radius).abs() < 1e-12);
                assert!(offset.dot(&t[i]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn triangles_face_outward() {
        let mesh = tube_around(&helix(10), 0.1, &TubeOptions::default());
        for tri in &mesh.triangles {
            let [a, b, c] = tri.map(|i| mesh.positions[i]);
            let face = (b - a).cross(&(c - a));
            let vertex_normals: Vec3 = tri.iter().map(|&i| mesh.normals[i]).sum();
            assert!(face.dot(&vertex_normals) > 0.0, "triangle {tri:?}");
        }
    }

    #[test]
    fn frame_does_not_twist_along_a_straight_tube() {
        // Rotation-minimising on a line means identical rings up to translation.
        let centre: Vec<Vec3> = (0..6).map(|i| Vec3::new(0.0, 0.0, i as f64)).collect();
        let k = 6;
        let mesh = tube_around(&centre, 1.0, &TubeOptions { sides: k, caps: false });
        for i in 1..centre.len() {
            for j in 0..k {
                let d = mesh.positions[i * k + j] - mesh.positions[j] - (centre[i] - centre[0]);
                assert!(d.norm() < 1e-12);
            }
        }
    }

    #[test]
    fn fewer_than_two_samples_give_an_empty_mesh() {
        assert_eq!(
            tube_around(&[Vec3::zeros()], 1.0, &TubeOptions::default()),
            TubeMesh::default()
        );
    }
}
