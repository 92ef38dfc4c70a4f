//! A closed triangle mesh as a signed distance field: the obstacle a user
//! brings as an OBJ file (a hand, a mannequin, a form).
//!
//! The distance is to the closest point of the mesh, found over every
//! triangle (Ericson, *Real-Time Collision Detection*, 5.1.5), and its sign
//! is that of the angle-weighted pseudo-normal of the closest feature
//! (face, edge or vertex; Baerentzen and Aanaes 2005), which is correct
//! for any closed, consistently oriented mesh. Normals point out of the
//! solid (counter-clockwise faces seen from outside, as OBJ exporters write
//! them). Gradient and Hessian are those of the distance to the closest
//! feature: flat over a face, `(I - n n^T - e e^T) / d` near an edge of
//! direction `e`, `(I - n n^T) / d` near a vertex.
//!
//! The search is brute force, `O(triangles)` per query: a mesh obstacle is
//! meant to be small (hundreds of triangles).

use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;

/// A triangle mesh with the pseudo-normals of its features.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    pub vertices: Vec<Vector3<f64>>,
    pub triangles: Vec<[usize; 3]>,
    face_normals: Vec<Vector3<f64>>,
    vertex_normals: Vec<Vector3<f64>>,
    /// Per (smaller, larger) vertex pair: the sum of its faces' normals.
    edge_normals: HashMap<(usize, usize), Vector3<f64>>,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    #[error("line {line}: {message}")]
    Line { line: usize, message: String },
    #[error("the mesh has no triangles")]
    Empty,
    #[error("triangle {0} has no area")]
    Degenerate(usize),
}

/// Where on a triangle the closest point lies.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Feature {
    Face,
    Edge(usize, usize),
    Vertex(usize),
}

impl TriMesh {
    /// The mesh of `vertices` and `triangles` (indices into `vertices`).
    pub fn new(vertices: Vec<Vector3<f64>>, triangles: Vec<[usize; 3]>) -> Result<Self, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        let mut face_normals = Vec::with_capacity(triangles.len());
        let mut vertex_normals = vec![Vector3::zeros(); vertices.len()];
        let mut edge_normals: HashMap<(usize, usize), Vector3<f64>> = HashMap::new();
        for (k, t) in triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| vertices[i]);
            let n = (b - a).cross(&(c - a));
            if n.norm() <= 1e-300 {
                return Err(MeshError::Degenerate(k));
            }
            let n = n.normalize();
            face_normals.push(n);
            for i in 0..3 {
                let (p, q, r) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                let angle = (vertices[q] - vertices[p]).angle(&(vertices[r] - vertices[p]));
                vertex_normals[p] += n * angle;
                *edge_normals.entry((p.min(q), p.max(q))).or_insert_with(Vector3::zeros) += n;
            }
        }
        Ok(TriMesh {
            vertices,
            triangles,
            face_normals,
            vertex_normals,
            edge_normals,
        })
    }

    /// Reads the `v` and `f` lines of an OBJ text (faces with more than
    /// three corners are fanned; `f 1/2/3` and negative indices are read;
    /// other lines are ignored), scaled by `scale` then moved by `offset`.
    pub fn from_obj(text: &str, scale: f64, offset: Vector3<f64>) -> Result<Self, MeshError> {
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let bad = |message: String| MeshError::Line { line: i + 1, message };
            let mut words = line.split_whitespace();
            match words.next() {
                Some("v") => {
                    let v: Vec<f64> = words
                        .take(3)
                        .map(|w| w.parse::<f64>().map_err(|_| bad(format!("not a number: {w:?}"))))
                        .collect::<Result<_, _>>()?;
                    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
                        return Err(bad("a vertex needs three finite coordinates".into()));
                    }
                    vertices.push(Vector3::new(v[0], v[1], v[2]) * scale + offset);
                }
                Some("f") => {
                    let corners: Vec<usize> = words
                        .map(|w| {
                            let first = w.split('/').next().unwrap_or_default();
                            let k: i64 = first.parse().map_err(|_| bad(format!("not a vertex index: {w:?}")))?;
                            let n = vertices.len() as i64;
                            let k = if k < 0 { n + k } else { k - 1 };
                            if k < 0 || k >= n {
                                return Err(bad(format!("vertex {first} is not defined above")));
                            }
                            Ok(k as usize)
                        })
                        .collect::<Result<_, _>>()?;
                    if corners.len() < 3 {
                        return Err(bad("a face needs three corners".into()));
                    }
                    for k in 1..corners.len() - 1 {
                        triangles.push([corners[0], corners[k], corners[k + 1]]);
                    }
                }
                _ => {}
            }
        }
        TriMesh::new(vertices, triangles)
    }

    /// Signed distance at `x`, its gradient and Hessian (module docs).
    pub fn sdf(&self, x: &Vector3<f64>) -> (f64, Vector3<f64>, Matrix3<f64>) {
        let mut best = (f64::INFINITY, Vector3::zeros(), 0usize, Feature::Face);
        for (k, t) in self.triangles.iter().enumerate() {
            let (c, feature) = closest_on_triangle(x, t, &self.vertices);
            let d2 = (x - c).norm_squared();
            if d2 < best.0 {
                best = (d2, c, k, feature);
            }
        }
        let (d2, c, k, feature) = best;
        let d = d2.sqrt();
        let pseudo = match feature {
            Feature::Face => self.face_normals[k],
            Feature::Edge(a, b) => self.edge_normals[&(a.min(b), a.max(b))],
            Feature::Vertex(v) => self.vertex_normals[v],
        };
        let sign = if (x - c).dot(&pseudo) < 0.0 { -1.0 } else { 1.0 };
        if d < 1e-12 || feature == Feature::Face {
            let n = self.face_normals[k];
            let s = n.dot(&(x - c));
            return (if d < 1e-12 { 0.0 } else { s }, n, Matrix3::zeros());
        }
        let u = (x - c) / d;
        let mut h = Matrix3::identity() - u * u.transpose();
        if let Feature::Edge(a, b) = feature {
            let e = (self.vertices[b] - self.vertices[a]).normalize();
            h -= e * e.transpose();
        }
        (sign * d, u * sign, h * (sign / d))
    }
}

/// The closest point to `p` on triangle `t` and the feature it lies on.
fn closest_on_triangle(p: &Vector3<f64>, t: &[usize; 3], v: &[Vector3<f64>]) -> (Vector3<f64>, Feature) {
    let [ia, ib, ic] = *t;
    let (a, b, c) = (v[ia], v[ib], v[ic]);
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Vertex(ia));
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Vertex(ib));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), Feature::Edge(ia, ib));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Vertex(ic));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), Feature::Edge(ia, ic));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return (
            b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))),
            Feature::Edge(ib, ic),
        );
    }
    let denom = 1.0 / (va + vb + vc);
    (a + ab * (vb * denom) + ac * (vc * denom), Feature::Face)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube `[0, 1]^3`, faces counter-clockwise from outside.
    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

    #[test]
    fn a_cube_mesh_measures_distances_like_a_box() {
        let m = TriMesh::from_obj(CUBE, 1.0, Vector3::zeros()).unwrap();
        assert_eq!(m.triangles.len(), 12);
        for (x, d) in [
            (Vector3::new(0.5, 0.5, 1.5), 0.5),         // above a face
            (Vector3::new(0.5, 0.5, 0.9), -0.1),        // inside, near the top
            (Vector3::new(1.3, 0.5, 1.4), 0.5),         // off an edge
            (Vector3::new(2.0, 2.0, 2.0), 3f64.sqrt()), // off a corner
            (Vector3::new(0.5, 0.4, 0.5), -0.4),        // centre region
        ] {
            let (s, g, _) = m.sdf(&x);
            assert!((s - d).abs() < 1e-12, "{x:?}: {s} vs {d}");
            assert!((g.norm() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn gradient_and_hessian_match_finite_differences_off_edges_and_corners() {
        let m = TriMesh::from_obj(CUBE, 1.0, Vector3::zeros()).unwrap();
        let h = 1e-6;
        for x in [
            Vector3::new(1.3, 0.5, 1.4),
            Vector3::new(1.2, 1.3, 1.1),
            Vector3::new(0.3, 0.6, 1.2),
        ] {
            let (_, g, hs) = m.sdf(&x);
            for i in 0..3 {
                let mut e = Vector3::zeros();
                e[i] = h;
                let (sp, gp, _) = m.sdf(&(x + e));
                let (sm, gm, _) = m.sdf(&(x - e));
                assert!(((sp - sm) / (2.0 * h) - g[i]).abs() < 1e-6);
                let col = (gp - gm) / (2.0 * h);
                assert!(
                    (col - hs.column(i)).norm() < 1e-5,
                    "{x:?} {i}: {col:?} vs {:?}",
                    hs.column(i)
                );
            }
        }
    }

    #[test]
    fn bad_obj_lines_are_errors_with_their_line() {
        assert_eq!(
            TriMesh::from_obj("v 0 0 0\nv 1 0 0\nf 1 2 3\n", 1.0, Vector3::zeros()),
            Err(MeshError::Line {
                line: 3,
                message: "vertex 3 is not defined above".into()
            })
        );
        assert!(matches!(
            TriMesh::from_obj("v 0 0 x\n", 1.0, Vector3::zeros()),
            Err(MeshError::Line { line: 1, .. })
        ));
        assert_eq!(
            TriMesh::from_obj("v 0 0 0\n", 1.0, Vector3::zeros()),
            Err(MeshError::Empty)
        );
    }
}
