//! Small analytic stencils for the solver's own tests (not physics): a
//! zero-rest-length-capable spring and a uniform gravity field.

use crate::energy::Stencil;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// `k/2 (|a - b| - rest)^2` on two 3D points `(a, b)`.
#[derive(Clone, Copy)]
pub struct Spring {
    pub k: f64,
    pub rest: f64,
}

impl Spring {
    fn split(x: &SVector<f64, 6>) -> Vector3<f64> {
        Vector3::new(x[0] - x[3], x[1] - x[4], x[2] - x[5])
    }
}

impl Stencil<6> for Spring {
    fn value(&self, x: &SVector<f64, 6>) -> f64 {
        let s = Self::split(x).norm() - self.rest;
        0.5 * self.k * s * s
    }

    fn gradient(&self, x: &SVector<f64, 6>) -> SVector<f64, 6> {
        let d = Self::split(x);
        let len = d.norm();
        let f = self.k * (len - self.rest) / len * d;
        SVector::<f64, 6>::from_fn(|i, _| if i < 3 { f[i] } else { -f[i - 3] })
    }

    fn hessian(&self, x: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        let d = Self::split(x);
        let len = d.norm();
        let u = d / len;
        let uu = u * u.transpose();
        let kb: Matrix3<f64> = self.k * (uu + (1.0 - self.rest / len) * (Matrix3::identity() - uu));
        let mut h = SMatrix::<f64, 6, 6>::zeros();
        h.fixed_view_mut::<3, 3>(0, 0).copy_from(&kb);
        h.fixed_view_mut::<3, 3>(3, 3).copy_from(&kb);
        h.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-kb));
        h.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-kb));
        h
    }
}

/// `m g z` for one 3D point: linear, so it only moves the gradient.
pub struct Gravity {
    pub mg: f64,
}

impl Stencil<3> for Gravity {
    fn value(&self, x: &SVector<f64, 3>) -> f64 {
        self.mg * x[2]
    }

    fn gradient(&self, _x: &SVector<f64, 3>) -> SVector<f64, 3> {
        SVector::<f64, 3>::new(0.0, 0.0, self.mg)
    }

    fn hessian(&self, _x: &SVector<f64, 3>) -> SMatrix<f64, 3, 3> {
        SMatrix::<f64, 3, 3>::zeros()
    }
}

#[test]
fn test_stencils_match_finite_differences() {
    use crate::energy::fd::check_derivatives;
    let s = Spring { k: 3.0, rest: 1.2 };
    for x in [
        SVector::<f64, 6>::from_column_slice(&[0.1, 0.2, -0.3, 1.0, 0.5, 0.4]),
        SVector::<f64, 6>::from_column_slice(&[0.0, 0.0, 0.0, 0.3, -0.2, 0.1]),
    ] {
        check_derivatives(&s, &x, 1e-6, 1e-6);
    }
    check_derivatives(&Gravity { mg: 2.0 }, &Vector3::new(1.0, 2.0, 3.0), 1e-6, 1e-6);
}
