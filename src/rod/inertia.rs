//! The inertia term of the incremental potential (docs/MODEL.md,
//! "Incremental potential"):
//! `1/(2 h^2) |q - q_pred|_M^2` summed over segments between consecutive
//! non-EIL points, with the EoL segment mass matrix (docs/MODEL.md, "Segment mass matrix")
//! evaluated at the start of the step and held constant. EIL points carry no
//! mass, which is what makes their `u` obey statics.

use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector};

/// Quadratic inertia on a segment's `[x_a, u_a, x_b, u_b]`.
#[derive(Clone, Debug)]
pub struct Inertia {
    /// `M_seg / h^2`.
    pub m_over_h2: SMatrix<f64, 8, 8>,
    /// The predicted (explicit) local coordinates.
    pub pred: SVector<f64, 8>,
}

impl Stencil<8> for Inertia {
    fn value(&self, x: &SVector<f64, 8>) -> f64 {
        let d = x - self.pred;
        0.5 * d.dot(&(self.m_over_h2 * d))
    }
    fn gradient(&self, x: &SVector<f64, 8>) -> SVector<f64, 8> {
        self.m_over_h2 * (x - self.pred)
    }
    fn hessian(&self, _x: &SVector<f64, 8>) -> SMatrix<f64, 8, 8> {
        self.m_over_h2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use crate::rod::mass::segment_mass;

    #[test]
    fn inertia_derivatives_and_rigid_translation() {
        let q0 = SVector::<f64, 8>::from_column_slice(&[0.0, 0.0, 0.0, 0.1, 0.01, 0.002, 0.0, 0.11]);
        let h = 1e-3;
        let s = Inertia {
            m_over_h2: segment_mass(5e-4, &q0) / (h * h),
            pred: q0,
        };
        let mut x = q0;
        x[0] += 1e-4;
        x[3] += 2e-5;
        check_derivatives(&s, &x, 1e-7, 1e-6);
        // A rigid translation by v h costs 1/2 m v^2 with m = rho du.
        let v = 0.3;
        let mut t = q0;
        for i in [2, 6] {
            t[i] += v * h;
        }
        let expect = 0.5 * 5e-4 * 0.01 * v * v;
        assert!(
            (s.value(&t) - expect).abs() < 1e-12 * expect.max(1.0) + 1e-15,
            "{} vs {expect}",
            s.value(&t)
        );
    }
}
