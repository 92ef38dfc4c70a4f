//! Coulomb friction between a yarn node and an obstacle, as a term of the
//! incremental potential (the lagged, smoothed friction of Incremental
//! Potential Contact, Li et al. 2020).
//!
//! Within a step of length `h` the node's tangential displacement is
//! `t = P (x - x0)`, with `x0` its position at the step's start and
//! `P = I - n n^T` the projector onto the obstacle's tangent plane at `x0`.
//! The normal force `lambda` is lagged (taken at the step's start from the
//! obstacle penalty). The friction potential is
//!
//! ```text
//! D(x) = mu lambda f0(|t|),
//! f0(y) = y                                  for y >= eps,
//! f0(y) = -y^3 / (3 eps^2) + y^2 / eps + eps / 3   for y < eps,
//! ```
//!
//! with `eps = v_eps h`: its force has magnitude `mu lambda` once the node
//! slides faster than `v_eps`, and below that it is a stiff viscous force
//! that holds a sticking node (static friction up to round-off of `eps`).
//! `f0` is C1 at `eps` and its Hessian
//! `mu lambda [g(y) P + g'(y) / y t t^T]`, `g = f0' / y`, is positive
//! semi-definite everywhere (the eigenvalue along `t` is
//! `2 / eps - 2 y / eps^2 >= 0` below `eps`, `0` above it), so Newton needs
//! no projection.

use crate::energy::Stencil;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Friction of one node against one obstacle during one step.
#[derive(Clone, Copy, Debug)]
pub struct ObstacleFriction {
    /// `mu lambda` (N): the sliding friction force.
    pub force: f64,
    /// Smoothing length `eps = v_eps h` (m).
    pub eps: f64,
    /// Position at the step's start.
    pub x0: Vector3<f64>,
    /// Projector onto the tangent plane at `x0`.
    pub tangent: Matrix3<f64>,
}

impl ObstacleFriction {
    /// Friction in the tangent plane of unit normal `n`.
    pub fn new(force: f64, eps: f64, x0: Vector3<f64>, n: Vector3<f64>) -> Self {
        ObstacleFriction {
            force,
            eps,
            x0,
            tangent: Matrix3::identity() - n * n.transpose(),
        }
    }

    fn slip(&self, x: &SVector<f64, 3>) -> Vector3<f64> {
        self.tangent * (x - self.x0)
    }

    /// `g(y) = f0'(y) / y`.
    fn g(&self, y: f64) -> f64 {
        if y < self.eps {
            2.0 / self.eps - y / (self.eps * self.eps)
        } else {
            1.0 / y
        }
    }
}

impl Stencil<3> for ObstacleFriction {
    fn value(&self, x: &SVector<f64, 3>) -> f64 {
        let y = self.slip(x).norm();
        let e = self.eps;
        let f0 = if y < e {
            -y * y * y / (3.0 * e * e) + y * y / e + e / 3.0
        } else {
            y
        };
        self.force * f0
    }

    fn gradient(&self, x: &SVector<f64, 3>) -> SVector<f64, 3> {
        let t = self.slip(x);
        t * (self.force * self.g(t.norm()))
    }

    fn hessian(&self, x: &SVector<f64, 3>) -> SMatrix<f64, 3, 3> {
        let t = self.slip(x);
        let y = t.norm();
        let e = self.eps;
        // g'(y) / y: -1 / eps^2 / y below eps, -1 / y^3 above.
        let curvature = if y < 1e-300 {
            0.0
        } else if y < e {
            -1.0 / (e * e * y)
        } else {
            -1.0 / (y * y * y)
        };
        (self.tangent * self.g(y) + t * t.transpose() * curvature) * self.force
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;

    fn friction() -> ObstacleFriction {
        ObstacleFriction::new(0.02, 1e-6, Vector3::new(0.01, 0.0, 0.0), Vector3::new(0.0, 0.6, 0.8))
    }

    #[test]
    fn derivatives_match_finite_differences_in_both_regimes() {
        let f = friction();
        // Sticking (slip below eps) and sliding (above), plus normal motion.
        for d in [
            Vector3::new(3e-7, -2e-7, 1e-7),
            Vector3::new(4e-5, 1e-5, -2e-5),
            Vector3::new(-2e-3, 5e-4, 1e-3),
        ] {
            check_derivatives(&f, &(f.x0 + d), 1e-9_f64.min(d.norm() * 1e-3), 1e-5);
        }
    }

    #[test]
    fn sliding_force_is_mu_lambda_along_the_slip_and_hessian_is_psd() {
        let f = friction();
        let slip = Vector3::new(1e-3, 0.0, 0.0);
        let g = f.gradient(&(f.x0 + slip));
        assert!((g.norm() - 0.02).abs() < 1e-12, "{}", g.norm());
        // Moving along the normal costs nothing.
        let n = Vector3::new(0.0, 0.6, 0.8);
        assert!(f.gradient(&(f.x0 + n * 1e-3)).norm() < 1e-12);
        for d in [Vector3::new(3e-7, -2e-7, 1e-7), slip] {
            let e = f.hessian(&(f.x0 + d)).symmetric_eigen();
            assert!(e.eigenvalues.min() > -1e-9 * e.eigenvalues.max(), "{:?}", e.eigenvalues);
        }
    }
}
