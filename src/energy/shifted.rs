//! A stencil evaluated at its local vector plus a constant shift.
//!
//! `Shifted { inner, shift }` is the potential `x -> inner(x + shift)`.
//! Its gradient and Hessian are `inner`'s at the shifted point: the shift
//! is a translation of the local coordinates, so no chain-rule factor
//! appears. The rod terms use it to move a yarn's centre line off a node
//! it shares with another yarn (`sim::terms::interlock_offsets`) without a
//! stencil of its own for every offset energy.

use super::Stencil;
use nalgebra::{SMatrix, SVector};

/// `inner` evaluated at `x + shift`.
#[derive(Clone, Copy, Debug)]
pub struct Shifted<S, const N: usize> {
    pub inner: S,
    pub shift: SVector<f64, N>,
}

impl<S: Stencil<N>, const N: usize> Stencil<N> for Shifted<S, N> {
    fn value(&self, x: &SVector<f64, N>) -> f64 {
        self.inner.value(&(x + self.shift))
    }

    fn gradient(&self, x: &SVector<f64, N>) -> SVector<f64, N> {
        self.inner.gradient(&(x + self.shift))
    }

    fn hessian(&self, x: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        self.inner.hessian(&(x + self.shift))
    }

    fn derivatives(&self, x: &SVector<f64, N>, project: bool) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        self.inner.derivatives(&(x + self.shift), project)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use crate::rod::bending::Bending;
    use crate::rod::stretch::Stretch;
    use nalgebra::Vector3;

    fn bent(theta: f64) -> SVector<f64, 12> {
        let (a, b, c) = (
            Vector3::new(-1.0, 0.0, 0.0),
            Vector3::zeros(),
            Vector3::new(theta.cos(), theta.sin(), 0.0),
        );
        SVector::<f64, 12>::from_column_slice(&[a.x, a.y, a.z, 0.0, b.x, b.y, b.z, 1.0, c.x, c.y, c.z, 2.0])
    }

    fn middle_shift(d: Vector3<f64>) -> SVector<f64, 12> {
        let mut s = SVector::<f64, 12>::zeros();
        s.fixed_rows_mut::<3>(4).copy_from(&d);
        s
    }

    #[test]
    fn a_shifted_stencil_is_its_inner_stencil_at_the_shifted_point() {
        let b = Bending::new(0.3);
        let x = bent(0.4);
        let shift = middle_shift(Vector3::new(0.0, 0.1, 0.2));
        let s = Shifted { inner: b, shift };
        assert_eq!(s.value(&x), b.value(&(x + shift)));
        assert_eq!(s.gradient(&x), b.gradient(&(x + shift)));
        // Lifting the middle point out of a straight line bends the rod:
        // the shift is not a no-op.
        let straight = bent(0.0);
        assert!(b.value(&straight) < 1e-20);
        assert!(s.value(&straight) > 1e-3);
    }

    #[test]
    fn shifted_bending_and_stretch_derivatives_match_finite_differences() {
        for (theta, lift) in [(0.3, 0.2), (1e-7, 0.0), (1e-7, 1e-6), (3.1, 0.05)] {
            let s = Shifted {
                inner: Bending::new(0.7),
                shift: middle_shift(Vector3::new(0.0, 0.0, lift)),
            };
            check_derivatives(&s, &bent(theta), 1e-6, 1e-4);
        }
        let mut shift = SVector::<f64, 8>::zeros();
        shift[2] = 0.3;
        let st = Shifted {
            inner: Stretch::new(50.0),
            shift,
        };
        let x = SVector::<f64, 8>::from_column_slice(&[0.0, 0.0, 0.0, 0.0, 0.8, 0.1, -0.2, 1.0]);
        check_derivatives(&st, &x, 1e-6, 1e-5);
    }
}
