//! Stretch of an EoL segment (docs/MODEL.md, "Stretch"):
//!
//! ```text
//! Vs = 1/2 ks du (|dx| / du - 1)^2 = ks (l - du)^2 / (2 du)
//! dx = x_b - x_a,  l = |dx|,  du = u_b - u_a > 0
//! ```
//!
//! The energy depends on the Eulerian coordinates too: sliding material into
//! a segment (`du` grows at fixed `l`) relaxes it. That is the EoL coupling
//! that makes contacts slide. The second form gives the derivatives in the
//! two scalars `(l, du)`:
//!
//! ```text
//! dV/dl = ks (l - du) / du         dV/ddu = ks/2 (1 - l^2 / du^2)
//! d2V/dl2 = ks / du   d2V/dl ddu = -ks l / du^2   d2V/ddu2 = ks l^2 / du^3
//! ```
//!
//! and `grad l = n = dx / l`, `hess l = (I - n n^T) / l`.
//!
//! Degenerate cases. Coincident nodes (`l = 0`) are a cone point of the
//! energy: the subgradient 0 is returned for the direction term and the
//! Hessian `ks/du I`, the second derivative along every line through the
//! cone. `du <= 0` is outside the model (consecutive EoL nodes are at least
//! the EIL threshold apart, docs/MODEL.md, "Node assignment"): the value is `+inf` so a line
//! search rejects the step, and the derivatives are zero.

use crate::energy::Stencil;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Stretch stencil on `[x_a(3), u_a, x_b(3), u_b]` (N = 8).
#[derive(Clone, Copy, Debug)]
pub struct Stretch {
    /// Axial stiffness `EA` (N).
    pub ks: f64,
}

impl Stretch {
    pub fn new(ks: f64) -> Self {
        Stretch { ks }
    }
}

/// `(dx, l, du)` of a local vector.
fn strain_vars(q: &SVector<f64, 8>) -> (Vector3<f64>, f64, f64) {
    let dx = q.fixed_rows::<3>(4) - q.fixed_rows::<3>(0);
    (dx, dx.norm(), q[7] - q[3])
}

/// Gradient and Hessian in the reduced variables `y = (dx, du)`.
fn reduced(ks: f64, dx: &Vector3<f64>, l: f64, du: f64) -> (SVector<f64, 4>, SMatrix<f64, 4, 4>) {
    let mut g = SVector::<f64, 4>::zeros();
    let mut h = SMatrix::<f64, 4, 4>::zeros();
    let (v_l, v_u) = (ks * (l - du) / du, 0.5 * ks * (1.0 - (l / du) * (l / du)));
    let (v_ll, v_lu, v_uu) = (ks / du, -ks * l / (du * du), ks * l * l / (du * du * du));
    let (n, h_dx) = if l > 0.0 {
        let n = dx / l;
        let nn = n * n.transpose();
        (n, nn * v_ll + (Matrix3::identity() - nn) * (v_l / l))
    } else {
        (Vector3::zeros(), Matrix3::identity() * v_ll)
    };
    g.fixed_rows_mut::<3>(0).copy_from(&(n * v_l));
    g[3] = v_u;
    h.fixed_view_mut::<3, 3>(0, 0).copy_from(&h_dx);
    h.fixed_view_mut::<3, 1>(0, 3).copy_from(&(n * v_lu));
    h.fixed_view_mut::<1, 3>(3, 0).copy_from(&(n * v_lu).transpose());
    h[(3, 3)] = v_uu;
    (g, h)
}

/// Maps reduced derivatives in `y = y_b - y_a` to the 8 local coordinates.
fn scatter(g: &SVector<f64, 4>, h: &SMatrix<f64, 4, 4>) -> (SVector<f64, 8>, SMatrix<f64, 8, 8>) {
    let mut gq = SVector::<f64, 8>::zeros();
    gq.fixed_rows_mut::<4>(0).copy_from(&(-g));
    gq.fixed_rows_mut::<4>(4).copy_from(g);
    let mut hq = SMatrix::<f64, 8, 8>::zeros();
    hq.fixed_view_mut::<4, 4>(0, 0).copy_from(h);
    hq.fixed_view_mut::<4, 4>(4, 4).copy_from(h);
    hq.fixed_view_mut::<4, 4>(0, 4).copy_from(&(-h));
    hq.fixed_view_mut::<4, 4>(4, 0).copy_from(&(-h));
    (gq, hq)
}

impl Stencil<8> for Stretch {
    fn value(&self, q: &SVector<f64, 8>) -> f64 {
        let (_, l, du) = strain_vars(q);
        if du <= 0.0 {
            return f64::INFINITY;
        }
        0.5 * self.ks * (l - du) * (l - du) / du
    }

    fn gradient(&self, q: &SVector<f64, 8>) -> SVector<f64, 8> {
        self.grad_hess(q, false).0
    }

    fn hessian(&self, q: &SVector<f64, 8>) -> SMatrix<f64, 8, 8> {
        self.grad_hess(q, false).1
    }

    fn derivatives(&self, q: &SVector<f64, 8>, project: bool) -> (SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        self.grad_hess(q, project)
    }
}

impl Stretch {
    /// Gradient and Hessian together (they share all intermediate terms);
    /// with `project`, the 4x4 Hessian in `(dx, du)` is projected before
    /// scattering (see `psd::project_psd_reduced` for why that suffices).
    pub fn grad_hess(&self, q: &SVector<f64, 8>, project: bool) -> (SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        let (dx, l, du) = strain_vars(q);
        if du <= 0.0 {
            return (SVector::zeros(), SMatrix::zeros());
        }
        let (g, h) = reduced(self.ks, &dx, l, du);
        let h = if project {
            crate::energy::psd::project_psd(&h)
        } else {
            h
        };
        scatter(&g, &h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use crate::rod::testutil::{assert_all_finite, put3, Rng};

    fn local(xa: Vector3<f64>, ua: f64, xb: Vector3<f64>, ub: f64) -> SVector<f64, 8> {
        let mut q = SVector::<f64, 8>::zeros();
        put3(&mut q, 0, &xa);
        q[3] = ua;
        put3(&mut q, 4, &xb);
        q[7] = ub;
        q
    }

    #[test]
    fn stretched_segment_energy_by_hand() {
        // du = 2, l = 3: strain 0.5, V = 1/2 * 10 * 2 * 0.25 = 2.5.
        let s = Stretch::new(10.0);
        let q = local(Vector3::new(1.0, 1.0, 0.0), 1.0, Vector3::new(1.0, 1.0, 3.0), 3.0);
        assert!((s.value(&q) - 2.5).abs() < 1e-14);
        // Tension ks * strain = 5 N pulls a and b together.
        let g = s.gradient(&q);
        assert!((g[6] - 5.0).abs() < 1e-13 && (g[2] + 5.0).abs() < 1e-13);
        // Rest state: zero energy and force.
        let r = local(Vector3::zeros(), 0.0, Vector3::new(0.6, 0.8, 0.0), 1.0);
        assert!(s.value(&r).abs() < 1e-15 && s.gradient(&r).norm() < 1e-14);
    }

    #[test]
    fn derivatives_random() {
        let mut rng = Rng::new(1);
        let s = Stretch::new(100.0);
        for _ in 0..50 {
            let xa = rng.vec3(1.0);
            let xb = rng.vec3(1.0);
            let ua = rng.range(-1.0, 1.0);
            let q = local(xa, ua, xb, ua + rng.range(0.2, 3.0));
            check_derivatives(&s, &q, 1e-6, 1e-5);
        }
    }

    #[test]
    fn derivatives_tiny_du() {
        let mut rng = Rng::new(2);
        let s = Stretch::new(100.0);
        for _ in 0..20 {
            let dir = rng.vec3(1.0).normalize();
            let du = 1e-6;
            // Stretched by up to 50% and compressed, with a transverse offset.
            let l = du * rng.range(0.5, 1.5);
            let q = local(Vector3::zeros(), 0.3, dir * l, 0.3 + du);
            assert_all_finite(&s, &q);
            check_derivatives(&s, &q, 1e-11, 1e-4);
        }
    }

    #[test]
    fn coincident_nodes_are_finite() {
        let s = Stretch::new(100.0);
        let q = local(Vector3::new(1.0, 2.0, 3.0), 0.0, Vector3::new(1.0, 2.0, 3.0), 0.5);
        assert_all_finite(&s, &q);
        // Fully collapsed: V = ks du / 2; radial stiffness ks/du.
        assert!((s.value(&q) - 25.0).abs() < 1e-12);
        assert!((s.hessian(&q)[(0, 0)] - 200.0).abs() < 1e-10);
        // Nearly coincident (l = 2e-8 du): exact derivatives still hold. The
        // nodes sit at the origin so the FD step is not lost in rounding.
        let near = local(Vector3::zeros(), 0.0, Vector3::new(1e-8, 0.0, 0.0), 0.5);
        check_derivatives(&s, &near, 1e-11, 1e-4);
    }
}
