//! Damping as a term of the incremental potential.
//!
//! Implicit Euler minimises `E(q) = 1/(2 h^2) |q - q_pred|_M^2 + V(q)`
//! (docs/MODEL.md, "Incremental potential"). A viscous force `-D qdot` with `qdot = (q - q_n) / h`
//! is the gradient of
//!
//! ```text
//! Vd(q) = 1/(2h) (q - q_n)^T D (q - q_n)
//! ```
//!
//! so damping enters the same minimisation as a quadratic stencil
//! ([`ViscousDamping`]) on any group of coordinates, e.g. an EoL segment's
//! 8 coordinates with `D` from [`rayleigh`]. Rayleigh damping
//! `D = alpha M + beta K` damps low modes through the mass (`alpha`, 1/s) and
//! high modes through a stiffness matrix (`beta`, s), here a stencil's
//! Hessian evaluated at the start of the step (PSD-projected, so `Vd` is
//! convex). Which terms get damped, and the coefficients, are the solver's
//! choice.

use crate::energy::psd::project_psd;
use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector};

/// `alpha M + beta project_psd(K)`.
pub fn rayleigh<const N: usize>(
    mass: &SMatrix<f64, N, N>,
    stiffness: &SMatrix<f64, N, N>,
    alpha: f64,
    beta: f64,
) -> SMatrix<f64, N, N> {
    mass * alpha + project_psd(stiffness) * beta
}

/// Viscous damping potential on `N` coordinates (module doc).
#[derive(Clone, Copy, Debug)]
pub struct ViscousDamping<const N: usize> {
    /// Damping matrix `D` (symmetric PSD).
    pub d: SMatrix<f64, N, N>,
    /// Coordinates at the start of the step.
    pub q_start: SVector<f64, N>,
    /// Time step (s).
    pub h: f64,
}

impl<const N: usize> Stencil<N> for ViscousDamping<N> {
    fn value(&self, q: &SVector<f64, N>) -> f64 {
        let dq = q - self.q_start;
        0.5 * dq.dot(&(self.d * dq)) / self.h
    }
    fn gradient(&self, q: &SVector<f64, N>) -> SVector<f64, N> {
        self.d * (q - self.q_start) / self.h
    }
    fn hessian(&self, _q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        self.d / self.h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use nalgebra::{Matrix2, Vector2};

    #[test]
    fn viscous_force_is_minus_d_velocity() {
        let d = rayleigh(
            &Matrix2::new(2.0, 0.0, 0.0, 2.0),
            &Matrix2::new(1.0, -1.0, -1.0, 1.0),
            0.5,
            0.1,
        );
        // 0.5 * 2 I + 0.1 [[1,-1],[-1,1]].
        assert!((d - Matrix2::new(1.1, -0.1, -0.1, 1.1)).norm() < 1e-15);
        let damp = ViscousDamping {
            d,
            q_start: Vector2::new(1.0, 0.0),
            h: 0.01,
        };
        // Moving coordinate 0 at velocity 1 (dq = h): force D * (1, 0) = (1.1, -0.1).
        let g = damp.gradient(&Vector2::new(1.01, 0.0));
        assert!((g - Vector2::new(1.1, -0.1)).norm() < 1e-12);
        check_derivatives(&damp, &Vector2::new(1.3, -0.2), 1e-6, 1e-8);
        // A negative stiffness mode is not turned into negative damping.
        let d_neg = rayleigh(&Matrix2::zeros(), &Matrix2::new(-1.0, 0.0, 0.0, 2.0), 0.0, 1.0);
        assert_eq!(d_neg[(0, 0)], 0.0);
    }
}
