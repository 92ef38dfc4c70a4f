//! External objects as signed distance fields with a stiff one-sided penalty.
//!
//! A yarn node at signed distance `s(x)` from the surface penetrates when
//! `s < r` (the yarn radius). The potential `k/2 (r - s)^2` for `s < r` is C1
//! at contact, so Newton sees a continuous gradient, and its Hessian
//! `k (grad s grad s^T - (r - s) hess s)` is exact, with the curvature term
//! that makes sliding over a sphere converge quadratically. Obstacles act on
//! node positions only (3 local coordinates), so EoL sliding is untouched.

use super::trimesh::TriMesh;
use crate::energy::Stencil;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use serde::Serialize;
use std::sync::Arc;

/// A rigid, fixed obstacle. Scenes read it with its values checked
/// (`scene::shape_json`): a sphere's radius and a box's half extents are
/// above 0, a plane's normal is not zero.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Shape {
    Sphere {
        center: [f64; 3],
        radius: f64,
    },
    /// Half-space below `point` along `normal` is solid.
    Plane {
        point: [f64; 3],
        normal: [f64; 3],
    },
    /// Axis-aligned box (a table top, a step).
    Box {
        center: [f64; 3],
        half_extents: [f64; 3],
    },
    /// Infinite circular cylinder around the line through `point` along
    /// `axis` (a rail, a table edge, an arm).
    Cylinder {
        point: [f64; 3],
        axis: [f64; 3],
        radius: f64,
    },
    /// A closed triangle mesh read from an OBJ file (`rod::trimesh`),
    /// scaled by `scale` and moved by `translate`; `path` as the scene
    /// gives it.
    Mesh {
        path: String,
        scale: f64,
        translate: [f64; 3],
        #[serde(skip)]
        mesh: Arc<TriMesh>,
    },
}

impl Shape {
    /// Signed distance, its gradient and Hessian at `x`.
    pub fn sdf(&self, x: &Vector3<f64>) -> (f64, Vector3<f64>, Matrix3<f64>) {
        match self {
            Shape::Sphere { center, radius } => {
                let d = x - Vector3::from(*center);
                let r = d.norm();
                if r < 1e-300 {
                    // The centre: any direction is outward; the curvature term is unbounded there.
                    return (-radius, Vector3::z(), Matrix3::zeros());
                }
                let n = d / r;
                (r - radius, n, (Matrix3::identity() - n * n.transpose()) / r)
            }
            Shape::Plane { point, normal } => {
                let n = Vector3::from(*normal).normalize();
                (n.dot(&(x - Vector3::from(*point))), n, Matrix3::zeros())
            }
            Shape::Box { center, half_extents } => {
                box_sdf(&(x - Vector3::from(*center)), &Vector3::from(*half_extents))
            }
            Shape::Cylinder { point, axis, radius } => {
                let a = Vector3::from(*axis).normalize();
                let d = x - Vector3::from(*point);
                let radial = d - a * a.dot(&d);
                let r = radial.norm();
                if r < 1e-300 {
                    let any = if a.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
                    return (-radius, (any - a * a.dot(&any)).normalize(), Matrix3::zeros());
                }
                let n = radial / r;
                (
                    r - radius,
                    n,
                    (Matrix3::identity() - a * a.transpose() - n * n.transpose()) / r,
                )
            }
            Shape::Mesh { mesh, .. } => mesh.sdf(x),
        }
    }
}

/// Box SDF in the box frame. Outside: distance to the closest point, whose
/// Hessian lives only on the axes where `x` is beyond a face. Inside: the
/// nearest face, a flat field.
fn box_sdf(p: &Vector3<f64>, h: &Vector3<f64>) -> (f64, Vector3<f64>, Matrix3<f64>) {
    let q = p.abs() - h;
    if q.max() > 0.0 {
        let mut v = Vector3::zeros();
        let mut mask = Matrix3::zeros();
        for i in 0..3 {
            if q[i] > 0.0 {
                v[i] = q[i] * p[i].signum();
                mask[(i, i)] = 1.0;
            }
        }
        let d = v.norm();
        let n = v / d;
        (d, n, (mask - n * n.transpose()) / d)
    } else {
        let i = q.imax();
        let mut n = Vector3::zeros();
        n[i] = if p[i] >= 0.0 { 1.0 } else { -1.0 };
        (q[i], n, Matrix3::zeros())
    }
}

/// Penalty of one node against one obstacle.
#[derive(Clone, Debug)]
pub struct ObstaclePenalty {
    pub shape: Shape,
    /// Contact thickness: the yarn radius.
    pub thickness: f64,
    pub stiffness: f64,
}

impl Stencil<3> for ObstaclePenalty {
    fn value(&self, x: &SVector<f64, 3>) -> f64 {
        let (s, _, _) = self.shape.sdf(x);
        let pen = self.thickness - s;
        if pen > 0.0 {
            0.5 * self.stiffness * pen * pen
        } else {
            0.0
        }
    }

    fn gradient(&self, x: &SVector<f64, 3>) -> SVector<f64, 3> {
        let (s, n, _) = self.shape.sdf(x);
        let pen = self.thickness - s;
        if pen > 0.0 {
            -n * (self.stiffness * pen)
        } else {
            SVector::zeros()
        }
    }

    fn hessian(&self, x: &SVector<f64, 3>) -> SMatrix<f64, 3, 3> {
        let (s, n, hs) = self.shape.sdf(x);
        let pen = self.thickness - s;
        if pen > 0.0 {
            (n * n.transpose() - hs * pen) * self.stiffness
        } else {
            SMatrix::zeros()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;

    fn shapes() -> Vec<Shape> {
        vec![
            Shape::Sphere {
                center: [0.0, 0.0, -0.1],
                radius: 0.1,
            },
            Shape::Plane {
                point: [0.0, 0.0, 0.0],
                normal: [0.0, 0.3, 1.0],
            },
            Shape::Box {
                center: [0.0, 0.0, -0.05],
                half_extents: [0.2, 0.1, 0.05],
            },
            Shape::Cylinder {
                point: [0.0, 0.0, -0.05],
                axis: [1.0, 0.2, 0.0],
                radius: 0.05,
            },
            Shape::Mesh {
                path: "cube".into(),
                scale: 0.1,
                translate: [-0.04, -0.05, -0.1],
                mesh: Arc::new(
                    TriMesh::from_obj(
                        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                         f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
                        0.1,
                        Vector3::new(-0.04, -0.05, -0.1),
                    )
                    .unwrap(),
                ),
            },
        ]
    }

    #[test]
    fn penalty_derivatives_match_finite_differences() {
        let pts = [
            Vector3::new(0.01, 0.02, -0.0004),    // shallow penetration, top face
            Vector3::new(0.2003, 0.05, 0.0002),   // box edge region, outside
            Vector3::new(0.2002, 0.1001, 0.0003), // box corner region
            Vector3::new(0.03, -0.01, -0.02),     // deep
            Vector3::new(0.0603, 0.02, 0.0004),   // mesh edge region
        ];
        for s in shapes() {
            let e = ObstaclePenalty {
                shape: s.clone(),
                thickness: 1e-3,
                stiffness: 1e4,
            };
            for p in &pts {
                if e.value(p) > 0.0 {
                    check_derivatives(&e, p, 1e-8, 1e-5);
                }
            }
        }
    }

    #[test]
    fn sdf_matches_geometry() {
        let s = Shape::Sphere {
            center: [1.0, 0.0, 0.0],
            radius: 0.5,
        };
        assert!((s.sdf(&Vector3::new(1.0, 2.0, 0.0)).0 - 1.5).abs() < 1e-15);
        let b = Shape::Box {
            center: [0.0; 3],
            half_extents: [1.0, 1.0, 1.0],
        };
        // Distance from (2,2,0) to the box edge is sqrt(2).
        assert!((b.sdf(&Vector3::new(2.0, 2.0, 0.0)).0 - 2f64.sqrt()).abs() < 1e-15);
        assert!((b.sdf(&Vector3::new(0.0, 0.0, 0.5)).0 + 0.5).abs() < 1e-15);
        let e = ObstaclePenalty {
            shape: b.clone(),
            thickness: 0.0,
            stiffness: 1.0,
        };
        assert_eq!(e.value(&Vector3::new(0.0, 0.0, 1.5)), 0.0);
    }
}
