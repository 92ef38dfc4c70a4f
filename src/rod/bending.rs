//! Bending at an interior EoL node (docs/MODEL.md, "Bending"):
//!
//! ```text
//! Vb = kb (theta - theta_rest)^2 / (du1 + du2)
//! theta = angle(x1 - x0, x2 - x1),  du1 = u1 - u0,  du2 = u2 - u1
//! ```
//!
//! With `kb = EI` this is the discrete `1/2 EI integral kappa^2` for curvature
//! `2 theta / (du1 + du2)` over the Voronoi length `(du1 + du2) / 2`
//! (see `params.rs`). Only `u0` and `u2` enter, through `D = u2 - u0`; `u1`
//! sits in the local vector so the stencil layout matches the node triple.
//!
//! `f(theta) = kb (theta - rest)^2` is differentiated through `cos(theta)`
//! (`angle.rs`), which is exact at `theta = 0` for the default `rest = 0`.
//! At a fold (`theta -> pi`) the energy has a concave cone point; derivatives
//! stay finite (large) and the PSD projection removes the negative part.
//! The `1/D` factor adds
//!
//! ```text
//! grad V = grad f / D - f grad D / D^2
//! hess V = hess f / D - (grad f grad D^T + grad D grad f^T) / D^2 + 2 f grad D grad D^T / D^3
//! ```
//!
//! with `grad D` = -1 at `u0`, +1 at `u2`.

use super::angle::{angle_energy, angle_gradient, angle_value, QuadraticAngle};
use crate::energy::Stencil;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Which PSD Hessian Newton gets from a bending stencil.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BendingHessian {
    /// The exact Hessian with its negative eigenvalues clamped (an 8x8
    /// eigen-decomposition per stencil): the nearest PSD matrix.
    #[default]
    Eigen,
    /// The closed-form model of `bending_psd`: Gauss-Newton part plus the
    /// positive eigenpairs of the angle's curvature, no eigen-decomposition.
    /// Stiffer than `Eigen` wherever the two differ; docs/RELAX.md,
    /// "Bending Hessian", measures what that does to a relaxation.
    Split,
}

impl std::str::FromStr for BendingHessian {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "eigen" => Ok(Self::Eigen),
            "split" => Ok(Self::Split),
            _ => Err(format!("unknown bending Hessian '{s}' (eigen, split)")),
        }
    }
}

/// Bending stencil on `[x0(3), u0, x1(3), u1, x2(3), u2]` (N = 12).
#[derive(Clone, Copy, Debug)]
pub struct Bending {
    /// Bending rigidity `EI` (N m^2).
    pub kb: f64,
    /// Rest turning angle (rad); 0 for a naturally straight yarn.
    pub rest_angle: f64,
    /// The PSD Hessian of [`Stencil::derivatives`] with projection on.
    pub hessian: BendingHessian,
}

/// Bending reads its local vector only through differences from `(x0, u0)`:
/// its Hessian is projected in those coordinates (`project_psd_reduced`),
/// which are the contiguous `x1, u1, x2, u2` (`kept_block` relies on it).
const KEPT: [usize; 8] = [4, 5, 6, 7, 8, 9, 10, 11];
const ANCHOR: [usize; 8] = [0, 1, 2, 3, 0, 1, 2, 3];

const X0: usize = 0;
const U0: usize = 3;
const X1: usize = 4;
const X2: usize = 8;
const U2: usize = 11;

impl Bending {
    /// A naturally straight yarn.
    pub fn new(kb: f64) -> Self {
        Self::with_rest_angle(kb, 0.0)
    }

    pub fn with_rest_angle(kb: f64, rest_angle: f64) -> Self {
        Bending {
            kb,
            rest_angle,
            hessian: BendingHessian::Eigen,
        }
    }

    /// The same stencil with another PSD Hessian model.
    pub fn with_hessian(self, hessian: BendingHessian) -> Self {
        Bending { hessian, ..self }
    }

    fn edges(q: &SVector<f64, 12>) -> (Vector3<f64>, Vector3<f64>, f64) {
        let x0 = q.fixed_rows::<3>(X0);
        let x1 = q.fixed_rows::<3>(X1);
        let x2 = q.fixed_rows::<3>(X2);
        (x1 - x0, x2 - x1, q[U2] - q[U0])
    }

    fn profile(&self) -> QuadraticAngle {
        QuadraticAngle {
            k: self.kb,
            rest: self.rest_angle,
        }
    }

    /// Value, gradient and Hessian together.
    pub fn evaluate(&self, q: &SVector<f64, 12>) -> (f64, SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        let (e1, e2, d) = Self::edges(q);
        let (f, g6, h6) = angle_energy(&e1, &e2, &self.profile());
        if d <= 0.0 {
            return (f64::INFINITY, SVector::zeros(), SMatrix::zeros());
        }
        let s = edge_map();
        let (value, grad, gf, gd) = value_gradient(&s, f, &g6, d);
        let hf = s.transpose() * h6 * s;
        let cross = gf * gd.transpose();
        let hess = hf / d - (cross + cross.transpose()) / (d * d) + gd * gd.transpose() * (2.0 * f / (d * d * d));
        (value, grad, hess)
    }

    /// The gradient and a PSD Hessian for Newton. With
    /// [`BendingHessian::Split`], the closed-form model of `bending_psd`
    /// where the bend plane is defined; otherwise (and by default) the
    /// exact Hessian projected by eigen-decomposition in the coordinates
    /// relative to `(x0, u0)` (bending is unchanged when the three nodes
    /// translate or the three `u` shift together).
    fn projected(&self, q: &SVector<f64, 12>) -> (SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        let (e1, e2, d) = Self::edges(q);
        if self.hessian == BendingHessian::Split && d > 0.0 {
            if let Some(h) = super::bending_psd::projected_hessian(self.kb, self.rest_angle, &e1, &e2, d) {
                let (f, g6) = angle_gradient(&e1, &e2, &self.profile());
                return (value_gradient(&edge_map(), f, &g6, d).1, h);
            }
        }
        let (g, block) = self.kept_block(q);
        (g, crate::energy::psd::project_psd_block(&block, &KEPT, &ANCHOR))
    }

    /// The gradient and the `KEPT x KEPT` block of the Hessian, all the
    /// projection reads: [`evaluate`](Self::evaluate)'s operations on
    /// those entries only (the same bits; 64 of the 144 entries and their
    /// divisions, and half the products through the edge map).
    fn kept_block(&self, q: &SVector<f64, 12>) -> (SVector<f64, 12>, SMatrix<f64, 8, 8>) {
        let (e1, e2, d) = Self::edges(q);
        let (f, g6, h6) = angle_energy(&e1, &e2, &self.profile());
        if d <= 0.0 {
            return (SVector::zeros(), SMatrix::zeros());
        }
        let s = edge_map();
        let (_, grad, gf, gd) = value_gradient(&s, f, &g6, d);
        let s_kept = s.fixed_columns::<8>(KEPT[0]);
        let hf = s_kept.transpose() * h6 * s_kept;
        let (gf, gd) = (gf.fixed_rows::<8>(KEPT[0]), gd.fixed_rows::<8>(KEPT[0]));
        let cross = gf * gd.transpose();
        let hess = hf / d - (cross + cross.transpose()) / (d * d) + gd * gd.transpose() * (2.0 * f / (d * d * d));
        (grad, hess)
    }
}

/// The edge vectors as a linear map of the local vector: `(e1, e2) = S q`.
fn edge_map() -> SMatrix<f64, 6, 12> {
    let mut s = SMatrix::<f64, 6, 12>::zeros();
    let id = Matrix3::identity();
    s.fixed_view_mut::<3, 3>(0, X0).copy_from(&(-id));
    s.fixed_view_mut::<3, 3>(0, X1).copy_from(&id);
    s.fixed_view_mut::<3, 3>(3, X1).copy_from(&(-id));
    s.fixed_view_mut::<3, 3>(3, X2).copy_from(&id);
    s
}

/// `V = f / D` and its gradient from `f(theta)` and its edge gradient
/// `g6`, with the pieces the Hessian reuses: `S^T g6` and `grad D`.
fn value_gradient(
    s: &SMatrix<f64, 6, 12>,
    f: f64,
    g6: &SVector<f64, 6>,
    d: f64,
) -> (f64, SVector<f64, 12>, SVector<f64, 12>, SVector<f64, 12>) {
    let gf = s.transpose() * g6;
    let mut gd = SVector::<f64, 12>::zeros();
    gd[U0] = -1.0;
    gd[U2] = 1.0;
    let grad = gf / d - gd * (f / (d * d));
    (f / d, grad, gf, gd)
}

impl Stencil<12> for Bending {
    /// Without the derivatives (`angle_value`): the same bits as `evaluate`.
    fn value(&self, q: &SVector<f64, 12>) -> f64 {
        let (e1, e2, d) = Self::edges(q);
        if d <= 0.0 {
            return f64::INFINITY;
        }
        angle_value(&e1, &e2, &self.profile()) / d
    }
    fn gradient(&self, q: &SVector<f64, 12>) -> SVector<f64, 12> {
        self.evaluate(q).1
    }
    fn hessian(&self, q: &SVector<f64, 12>) -> SMatrix<f64, 12, 12> {
        self.evaluate(q).2
    }
    fn derivatives(&self, q: &SVector<f64, 12>, project: bool) -> (SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        if project {
            return self.projected(q);
        }
        let (_, g, h) = self.evaluate(q);
        (g, h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use crate::rod::testutil::{assert_all_finite, put3, Rng};
    use std::f64::consts::{FRAC_PI_2, PI};

    fn local(x: [Vector3<f64>; 3], u: [f64; 3]) -> SVector<f64, 12> {
        let mut q = SVector::<f64, 12>::zeros();
        for k in 0..3 {
            put3(&mut q, 4 * k, &x[k]);
            q[4 * k + 3] = u[k];
        }
        q
    }

    /// Nodes x0, x1, x2 with turning angle `theta` at x1, random orientation.
    fn bent(rng: &mut Rng, theta: f64, l1: f64, l2: f64) -> SVector<f64, 12> {
        let t = rng.vec3(1.0).normalize();
        let n = rng.orthogonal_unit(&t);
        let x1 = rng.vec3(0.1);
        let x0 = x1 - t * l1;
        let x2 = x1 + (t * theta.cos() + n * theta.sin()) * l2;
        let u0 = rng.range(-1.0, 1.0);
        local([x0, x1, x2], [u0, u0 + l1, u0 + l1 + l2])
    }

    #[test]
    fn the_kept_block_is_the_full_hessians_bit_for_bit() {
        let mut rng = Rng::new(23);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let mut cases: Vec<(Bending, SVector<f64, 12>)> = Vec::new();
        for theta in [0.0, 1e-9, 1e-4, 0.3, 1.0, 2.0, PI - 1e-4, PI - 1e-9, PI] {
            for rest in [0.0, 0.4] {
                let (l1, l2) = (rng.range(1e-6, 2.0), rng.range(1e-6, 2.0));
                cases.push((Bending::with_rest_angle(2.0, rest), bent(&mut rng, theta, l1, l2)));
            }
        }
        // Coincident nodes, and a `u` gap that is zero or negative.
        let mut q = bent(&mut rng, 1.0, 1.0, 1.0);
        let x1 = q.fixed_rows::<3>(X1).clone_owned();
        q.fixed_rows_mut::<3>(X2).copy_from(&x1);
        cases.push((Bending::new(1.0), q));
        for gap in [0.0, -0.5] {
            let mut q = bent(&mut rng, 1.0, 1.0, 1.0);
            q[U2] = q[U0] + gap;
            cases.push((Bending::new(1.0), q));
        }
        for (b, q) in &cases {
            let (_, g, h) = b.evaluate(q);
            let (gk, block) = b.kept_block(q);
            let want = if q[U2] - q[U0] > 0.0 {
                SMatrix::<f64, 8, 8>::from_fn(|k, l| h[(KEPT[k], KEPT[l])])
            } else {
                SMatrix::zeros()
            };
            assert_eq!(bits(gk.as_slice()), bits(g.as_slice()));
            assert_eq!(bits(block.as_slice()), bits(want.as_slice()));
        }
    }

    #[test]
    fn right_angle_bend_by_hand() {
        // theta = pi/2, du1 + du2 = 2: V = kb (pi/2)^2 / 2.
        let b = Bending::new(3.0);
        let q = local(
            [Vector3::zeros(), Vector3::x(), Vector3::x() + Vector3::y()],
            [0.0, 1.0, 2.0],
        );
        assert!((b.value(&q) - 3.0 * FRAC_PI_2 * FRAC_PI_2 / 2.0).abs() < 1e-14);
        // Sliding material in (larger D) lowers the energy: dV/du2 = -V / D.
        let g = b.gradient(&q);
        assert!((g[U2] + b.value(&q) / 2.0).abs() < 1e-14);
        // A rest angle of pi/2 makes this the rest state.
        let r = Bending::with_rest_angle(3.0, FRAC_PI_2);
        assert!(r.value(&q).abs() < 1e-15 && r.gradient(&q).norm() < 1e-13);
    }

    #[test]
    fn value_alone_has_the_bits_of_evaluate() {
        // The line search calls `value`, assembly `evaluate`: a last-bit
        // difference would change the relaxation path (docs/RELAX.md, "PSD projections").
        let mut rng = Rng::new(12);
        let stencils = [Bending::new(2.0), Bending::with_rest_angle(2.0, 0.7)];
        for k in 0..200 {
            let theta = [1e-9, 1e-3, 0.5, 2.0, PI - 1e-6, PI][k % 6];
            let (l1, l2) = (rng.range(1e-9, 2.0), rng.range(0.3, 2.0));
            let mut q = bent(&mut rng, theta, l1, l2);
            if k % 7 == 0 {
                let x1 = q.fixed_rows::<3>(X1).into_owned();
                put3(&mut q, X0, &x1); // coincident nodes
            }
            if k % 11 == 0 {
                q[U2] = q[U0]; // no material: infinite
            }
            for b in &stencils {
                assert_eq!(b.value(&q).to_bits(), b.evaluate(&q).0.to_bits(), "{q:?}");
            }
        }
    }

    #[test]
    fn derivatives_random() {
        let mut rng = Rng::new(11);
        let b = Bending::new(2.0);
        let r = Bending::with_rest_angle(2.0, 0.7);
        for _ in 0..50 {
            let theta = rng.range(0.05, 3.0);
            let (l1, l2) = (rng.range(0.3, 2.0), rng.range(0.3, 2.0));
            let q = bent(&mut rng, theta, l1, l2);
            check_derivatives(&b, &q, 1e-6, 1e-5);
            check_derivatives(&r, &q, 1e-6, 1e-5);
        }
    }

    #[test]
    fn projected_hessian_is_psd_and_keeps_translations_free() {
        let mut rng = Rng::new(5);
        let b = Bending::with_rest_angle(2.0, 0.3);
        for _ in 0..30 {
            let (theta, l1, l2) = (rng.range(0.05, 3.0), rng.range(0.3, 2.0), rng.range(0.3, 2.0));
            let q = bent(&mut rng, theta, l1, l2);
            let (g, hp) = b.derivatives(&q, true);
            assert!((g - b.gradient(&q)).norm() < 1e-12);
            let (ev, _) = crate::energy::psd::sym_eigen(&hp);
            assert!(ev.iter().all(|&e| e > -1e-10 * hp.norm().max(1.0)), "{ev:?}");
            // A common translation of the nodes and shift of the u stays a null vector.
            let t = SVector::<f64, 12>::from_fn(|i, _| if i % 4 == 3 { 0.7 } else { [0.3, -0.2, 0.5][i % 4] });
            assert!((hp * t).norm() < 1e-10 * hp.norm().max(1.0));
        }
    }

    #[test]
    fn straight_is_exact_and_finite() {
        let mut rng = Rng::new(12);
        let b = Bending::new(2.0);
        for theta in [0.0, 1e-8, 1e-5] {
            let q = bent(&mut rng, theta, 1.0, 0.7);
            assert_all_finite(&b, &q);
            // The gradient is ~0 here, so the FD truncation error (h^2) is
            // measured against the checker's 1e-8 floor: keep h small.
            check_derivatives(&b, &q, 1e-7, 1e-5);
        }
        // Exactly straight: zero energy and force; the bending stiffness
        // transverse to the yarn is positive (not 0/0).
        let q = local([Vector3::zeros(), Vector3::x(), Vector3::x() * 2.0], [0.0, 1.0, 2.0]);
        assert_eq!(b.value(&q), 0.0);
        assert!(b.gradient(&q).norm() < 1e-15);
        // Moving x1 by y: theta ~ 2y, V = 2 (2y)^2 / 2 = 4 y^2, so d2V/dy1^2 = 8.
        assert!((b.hessian(&q)[(5, 5)] - 8.0).abs() < 1e-12);
    }

    #[test]
    fn folded_and_tiny_du_are_finite() {
        let mut rng = Rng::new(13);
        let b = Bending::new(2.0);
        let q = bent(&mut rng, PI - 1e-6, 1.0, 0.8);
        assert_all_finite(&b, &q);
        check_derivatives(&b, &q, 1e-9, 1e-4);
        assert!((b.value(&q) - 2.0 * (PI - 1e-6).powi(2) / 1.8).abs() < 1e-9);
        // Exactly folded and coincident nodes stay finite.
        let folded = local([Vector3::zeros(), Vector3::x(), Vector3::zeros()], [0.0, 1.0, 2.0]);
        assert_all_finite(&b, &folded);
        let coincident = local([Vector3::zeros(), Vector3::zeros(), Vector3::x()], [0.0, 1.0, 2.0]);
        assert_all_finite(&b, &coincident);
        // Tiny material lengths (1e-6): stiff but exact.
        let q = bent(&mut rng, 0.4, 1e-6, 1e-6);
        assert_all_finite(&b, &q);
        check_derivatives(&b, &q, 1e-12, 1e-4);
    }
}
