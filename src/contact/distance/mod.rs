//! Point-edge and edge-edge distances between 3D segments, squared and
//! unsquared, with gradients and Hessians on the 9 / 12 stacked coordinates
//! `[p, e0, e1]` / `[ea0, ea1, eb0, eb1]`.
//!
//! Two steps, as in ipc-toolkit: [`classify`] picks the closest feature
//! pair (a *distance type*), then [`eval`] evaluates that type's smooth
//! closed form. Across type boundaries the squared distance is C1 (the
//! closed forms agree in value and gradient there), so a stencil that keeps
//! the type of its current configuration gets exact derivatives.
//!
//! **No mollifier.** IPC mollifies edge-edge barriers of near-parallel edges
//! to zero because on triangle meshes the point-triangle pairs still carry
//! that contact. Yarns have no triangles: side-by-side parallel yarns are the
//! common case in knits and must keep their contact. We keep the unmollified
//! distance and make it robust instead: near-parallel edges fall back to
//! their closest endpoint-edge pair ([`classify::PARALLEL_SIN2`]), exact for
//! parallel segments, and the line-line parameters use the Lagrange-identity
//! forms `s = (u x v).(v x w) / |u x v|^2` that stay accurate at small angles.

pub mod classify;
pub mod eval;

#[cfg(test)]
mod tests;

pub use classify::{edge_edge_type, point_edge_type, EdgeEdgeType, PointEdgeType, PARALLEL_SIN2};
pub use eval::DistanceDerivs;

use eval::AffinePair;
use nalgebra::{SVector, Vector3};

type V3 = Vector3<f64>;

/// Splits stacked coordinates into `M` points.
pub fn points<const M: usize, const N: usize>(x: &SVector<f64, N>) -> [V3; M] {
    debug_assert_eq!(N, 3 * M);
    std::array::from_fn(|i| x.fixed_rows::<3>(3 * i).into_owned())
}

/// A type's closed form: coefficients, parameter values and inverse Gram matrix.
struct Form<const M: usize> {
    pair: AffinePair<M>,
    tau: [f64; 2],
    gram_inv: [[f64; 2]; 2],
}

impl<const M: usize> Form<M> {
    fn fixed(c0: [f64; M]) -> Self {
        Form {
            pair: AffinePair {
                c0,
                dirs: [[0.0; M]; 2],
                k: 0,
            },
            tau: [0.0; 2],
            gram_inv: [[0.0; 2]; 2],
        }
    }

    /// A point against the interior of an edge: one parameter along `dir`
    /// (whose combination of the points is `-(edge vector)`).
    fn along(c0: [f64; M], dir: [f64; M], t: f64, len2: f64) -> Self {
        Form {
            pair: AffinePair {
                c0,
                dirs: [dir, [0.0; M]],
                k: 1,
            },
            tau: [t, 0.0],
            gram_inv: [[1.0 / len2, 0.0], [0.0, 0.0]],
        }
    }

    fn value(&self, x: &[V3; M]) -> f64 {
        let mut r = V3::zeros();
        for (i, xi) in x.iter().enumerate() {
            let mut ci = self.pair.c0[i];
            for j in 0..self.pair.k {
                ci += self.tau[j] * self.pair.dirs[j][i];
            }
            r += xi * ci;
        }
        r.norm_squared()
    }
}

fn point_edge_form(x: &[V3; 3], ty: PointEdgeType) -> Form<3> {
    let [p, e0, e1] = x;
    match ty {
        PointEdgeType::E0 => Form::fixed([1.0, -1.0, 0.0]),
        PointEdgeType::E1 => Form::fixed([1.0, 0.0, -1.0]),
        PointEdgeType::Interior => {
            let e = e1 - e0;
            let len2 = e.norm_squared();
            Form::along([1.0, -1.0, 0.0], [0.0, 1.0, -1.0], e.dot(&(p - e0)) / len2, len2)
        }
    }
}

fn edge_edge_form(x: &[V3; 4], ty: EdgeEdgeType) -> Form<4> {
    use EdgeEdgeType::*;
    let [ea0, ea1, eb0, eb1] = x;
    let u = ea1 - ea0;
    let v = eb1 - eb0;
    // Vertex `i` of A (0, 1) against the interior of B, and vice versa.
    let a_vertex_b_interior = |i: usize| {
        let mut c0 = [0.0, 0.0, -1.0, 0.0];
        c0[i] = 1.0;
        let len2 = v.norm_squared();
        Form::along(c0, [0.0, 0.0, 1.0, -1.0], v.dot(&(x[i] - eb0)) / len2, len2)
    };
    let b_vertex_a_interior = |j: usize| {
        let mut c0 = [1.0, 0.0, 0.0, 0.0];
        c0[2 + j] = -1.0;
        let len2 = u.norm_squared();
        Form::along(c0, [-1.0, 1.0, 0.0, 0.0], u.dot(&(x[2 + j] - ea0)) / len2, len2)
    };
    match ty {
        A0B0 => Form::fixed([1.0, 0.0, -1.0, 0.0]),
        A0B1 => Form::fixed([1.0, 0.0, 0.0, -1.0]),
        A1B0 => Form::fixed([0.0, 1.0, -1.0, 0.0]),
        A1B1 => Form::fixed([0.0, 1.0, 0.0, -1.0]),
        A0B => a_vertex_b_interior(0),
        A1B => a_vertex_b_interior(1),
        AB0 => b_vertex_a_interior(0),
        AB1 => b_vertex_a_interior(1),
        AB => {
            let w = ea0 - eb0;
            let n = u.cross(&v);
            let det = n.norm_squared();
            let s = n.dot(&v.cross(&w)) / det;
            let t = n.dot(&u.cross(&w)) / det;
            // Gram matrix of the directions (u, -v): [[a, -b], [-b, c]], det |n|^2.
            let (a, b, c) = (u.norm_squared(), u.dot(&v), v.norm_squared());
            Form {
                pair: AffinePair {
                    c0: [1.0, 0.0, -1.0, 0.0],
                    dirs: [[-1.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0]],
                    k: 2,
                },
                tau: [s, t],
                gram_inv: [[c / det, b / det], [b / det, a / det]],
            }
        }
    }
}

/// Squared point-edge distance for a given type.
pub fn point_edge_distance_sq_typed(p: &V3, e0: &V3, e1: &V3, ty: PointEdgeType) -> f64 {
    let x = [*p, *e0, *e1];
    point_edge_form(&x, ty).value(&x)
}

/// Squared point-segment distance.
pub fn point_edge_distance_sq(p: &V3, e0: &V3, e1: &V3) -> f64 {
    point_edge_distance_sq_typed(p, e0, e1, point_edge_type(p, e0, e1))
}

/// Squared edge-edge distance for a given type.
pub fn edge_edge_distance_sq_typed(ea0: &V3, ea1: &V3, eb0: &V3, eb1: &V3, ty: EdgeEdgeType) -> f64 {
    let x = [*ea0, *ea1, *eb0, *eb1];
    edge_edge_form(&x, ty).value(&x)
}

/// Squared segment-segment distance.
pub fn edge_edge_distance_sq(ea0: &V3, ea1: &V3, eb0: &V3, eb1: &V3) -> f64 {
    edge_edge_distance_sq_typed(ea0, ea1, eb0, eb1, edge_edge_type(ea0, ea1, eb0, eb1))
}

/// Squared point-point distance with derivatives on `[p, q]`.
pub fn point_point_derivs(x: &SVector<f64, 6>) -> DistanceDerivs<6> {
    let pts: [V3; 2] = points(x);
    let form = Form::fixed([1.0, -1.0]);
    eval::evaluate(&pts, &form.pair, &form.tau, &form.gram_inv)
}

/// Squared point-edge distance with derivatives on `[p, e0, e1]`, for a type.
pub fn point_edge_derivs_typed(x: &SVector<f64, 9>, ty: PointEdgeType) -> DistanceDerivs<9> {
    let pts: [V3; 3] = points(x);
    let form = point_edge_form(&pts, ty);
    eval::evaluate(&pts, &form.pair, &form.tau, &form.gram_inv)
}

/// Squared point-edge distance with derivatives, type chosen at `x`.
pub fn point_edge_derivs(x: &SVector<f64, 9>) -> DistanceDerivs<9> {
    let [p, e0, e1]: [V3; 3] = points(x);
    point_edge_derivs_typed(x, point_edge_type(&p, &e0, &e1))
}

/// Squared edge-edge distance with derivatives on `[ea0, ea1, eb0, eb1]`, for a type.
pub fn edge_edge_derivs_typed(x: &SVector<f64, 12>, ty: EdgeEdgeType) -> DistanceDerivs<12> {
    let pts: [V3; 4] = points(x);
    let form = edge_edge_form(&pts, ty);
    eval::evaluate(&pts, &form.pair, &form.tau, &form.gram_inv)
}

/// Squared edge-edge distance with derivatives, type chosen at `x`.
pub fn edge_edge_derivs(x: &SVector<f64, 12>) -> DistanceDerivs<12> {
    let [a0, a1, b0, b1]: [V3; 4] = points(x);
    edge_edge_derivs_typed(x, edge_edge_type(&a0, &a1, &b0, &b1))
}
