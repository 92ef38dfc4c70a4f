//! Pins and prescribed motions.
//!
//! Two ways to hold a node, chosen by the scene:
//!
//! - **Soft pin** ([`SoftPin`]): `V = 1/2 kp |x - target|^2`. The target may
//!   move each step (prescribed motion). Cheap and always consistent with
//!   the Newton solve, at the price of a small lag `f / kp` under load.
//! - **Hard pin**: the pinned coordinates are not unknowns. The solver keeps
//!   the system size fixed and cancels their rows and columns (identity on
//!   the diagonal, zero right-hand side), exactly as for the Lagrangian DOFs
//!   of EIL nodes (docs/MODEL.md, "Fixed system size"), after setting them to
//!   the target. That is the lead's assembly; no stencil is involved.

use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector, Vector3};

/// Zero-rest-length spring to a target on `[x]` (N = 3).
#[derive(Clone, Copy, Debug)]
pub struct SoftPin {
    /// Spring stiffness (N/m).
    pub kp: f64,
    /// Target position (m).
    pub target: Vector3<f64>,
}

impl SoftPin {
    pub fn new(kp: f64, target: Vector3<f64>) -> Self {
        SoftPin { kp, target }
    }
}

impl Stencil<3> for SoftPin {
    fn value(&self, q: &SVector<f64, 3>) -> f64 {
        0.5 * self.kp * (q - self.target).norm_squared()
    }
    fn gradient(&self, q: &SVector<f64, 3>) -> SVector<f64, 3> {
        (q - self.target) * self.kp
    }
    fn hessian(&self, _q: &SVector<f64, 3>) -> SMatrix<f64, 3, 3> {
        SMatrix::identity() * self.kp
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;

    #[test]
    fn pin_by_hand() {
        let p = SoftPin::new(4.0, Vector3::new(1.0, 1.0, 1.0));
        let q = SVector::<f64, 3>::new(1.0, 4.0, 5.0);
        // Distance 5: V = 2 * 25.
        assert!((p.value(&q) - 50.0).abs() < 1e-12);
        assert!((p.gradient(&q) - Vector3::new(0.0, 12.0, 16.0)).norm() < 1e-12);
        check_derivatives(&p, &q, 1e-6, 1e-8);
    }
}
