//! Gravity, per node or per EoL segment.
//!
//! [`NodeGravity`] is the lumped form `V = -m g . x` (linear, zero Hessian),
//! for nodes whose mass is fixed (pinned masses, Lagrangian nodes of a
//! lumped model).
//!
//! [`SegmentGravity`] is the consistent form for an EoL segment: the
//! potential of the material it holds, with `x` linear in `u` along it,
//!
//! ```text
//! V = -rho integral_{u_a}^{u_b} g . x(u) du = -rho (u_b - u_a) g . (x_a + x_b) / 2
//! ```
//!
//! It depends on the Eulerian coordinates: sliding material toward the lower
//! node lowers the energy, which is how a draped yarn pulls material down
//! through its contacts. Summed over the segments of a yarn, the boundary
//! terms of shared nodes cancel and the total is the yarn's exact potential
//! under piecewise-linear interpolation. Its Hessian only couples `u` with
//! `x` (`d2V/du_a dx_a = rho g / 2`, etc.), so it is indefinite; the PSD
//! projection deals with that.

use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector, Vector3};

/// Lumped gravity on `[x]` (N = 3): `V = -mass g . x`.
#[derive(Clone, Copy, Debug)]
pub struct NodeGravity {
    /// Node mass (kg).
    pub mass: f64,
    /// Gravitational acceleration (m/s^2), e.g. `(0, 0, -9.81)`.
    pub g: Vector3<f64>,
}

impl NodeGravity {
    pub fn new(mass: f64, g: Vector3<f64>) -> Self {
        NodeGravity { mass, g }
    }
}

impl Stencil<3> for NodeGravity {
    fn value(&self, q: &SVector<f64, 3>) -> f64 {
        -self.mass * self.g.dot(q)
    }
    fn gradient(&self, _q: &SVector<f64, 3>) -> SVector<f64, 3> {
        -self.g * self.mass
    }
    fn hessian(&self, _q: &SVector<f64, 3>) -> SMatrix<f64, 3, 3> {
        SMatrix::zeros()
    }
}

/// Consistent segment gravity on `[x_a(3), u_a, x_b(3), u_b]` (N = 8).
#[derive(Clone, Copy, Debug)]
pub struct SegmentGravity {
    /// Linear density (kg/m).
    pub rho: f64,
    /// Gravitational acceleration (m/s^2).
    pub g: Vector3<f64>,
}

impl SegmentGravity {
    pub fn new(rho: f64, g: Vector3<f64>) -> Self {
        SegmentGravity { rho, g }
    }
}

impl Stencil<8> for SegmentGravity {
    fn value(&self, q: &SVector<f64, 8>) -> f64 {
        let mid = (q.fixed_rows::<3>(0) + q.fixed_rows::<3>(4)) * 0.5;
        -self.rho * (q[7] - q[3]) * self.g.dot(&mid)
    }
    fn gradient(&self, q: &SVector<f64, 8>) -> SVector<f64, 8> {
        let mid = (q.fixed_rows::<3>(0) + q.fixed_rows::<3>(4)) * 0.5;
        let fx = -self.g * (0.5 * self.rho * (q[7] - q[3]));
        let gu = self.rho * self.g.dot(&mid);
        let mut grad = SVector::<f64, 8>::zeros();
        grad.fixed_rows_mut::<3>(0).copy_from(&fx);
        grad.fixed_rows_mut::<3>(4).copy_from(&fx);
        grad[3] = gu;
        grad[7] = -gu;
        grad
    }
    fn hessian(&self, _q: &SVector<f64, 8>) -> SMatrix<f64, 8, 8> {
        let half = self.g * (0.5 * self.rho);
        let mut h = SMatrix::<f64, 8, 8>::zeros();
        for (u, sign) in [(3, 1.0), (7, -1.0)] {
            for x in [0, 4] {
                for k in 0..3 {
                    h[(u, x + k)] = sign * half[k];
                    h[(x + k, u)] = sign * half[k];
                }
            }
        }
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use crate::rod::testutil::Rng;

    #[test]
    fn node_gravity_by_hand() {
        let g = NodeGravity::new(2.0, Vector3::new(0.0, 0.0, -9.81));
        let q = SVector::<f64, 3>::new(5.0, -1.0, 3.0);
        assert!((g.value(&q) - 2.0 * 9.81 * 3.0).abs() < 1e-12);
        check_derivatives(&g, &q, 1e-6, 1e-8);
    }

    #[test]
    fn segment_gravity_by_hand_and_fd() {
        let grav = SegmentGravity::new(0.5, Vector3::new(0.0, 0.0, -10.0));
        // Material length 2 at mean height 3: V = 0.5 * 2 * 10 * 3 = 30.
        let q = SVector::<f64, 8>::from_column_slice(&[0.0, 0.0, 2.0, 1.0, 7.0, 0.0, 4.0, 3.0]);
        assert!((grav.value(&q) - 30.0).abs() < 1e-12);
        let mut rng = Rng::new(31);
        for _ in 0..20 {
            let q = rng.vector::<8>(2.0);
            check_derivatives(&grav, &q, 1e-6, 1e-6);
        }
    }

    #[test]
    fn sliding_material_downhill_lowers_energy() {
        // A chain a-b-c with b the lowest node: moving u_b (more material in
        // the segment b-c whose midpoint is lower) must lower the energy.
        let grav = SegmentGravity::new(1.0, Vector3::new(0.0, 0.0, -1.0));
        let (xa, xb, xc) = (
            Vector3::new(0.0, 0.0, 2.0),
            Vector3::zeros(),
            Vector3::new(1.0, 0.0, 0.5),
        );
        let total = |ub: f64| {
            let seg = |x0: &Vector3<f64>, u0: f64, x1: &Vector3<f64>, u1: f64| {
                let mut q = SVector::<f64, 8>::zeros();
                q.fixed_rows_mut::<3>(0).copy_from(x0);
                q[3] = u0;
                q.fixed_rows_mut::<3>(4).copy_from(x1);
                q[7] = u1;
                grav.value(&q)
            };
            seg(&xa, 0.0, &xb, ub) + seg(&xb, ub, &xc, 3.0)
        };
        // dV/du_b = mid_ab height - mid_bc height = 1 - 0.25 > 0: decreasing u_b helps.
        assert!(((total(1.0 + 1e-6) - total(1.0 - 1e-6)) / 2e-6 - 0.75).abs() < 1e-8);
    }
}
