//! Angle energies between two edge vectors, with exact finite derivatives.
//!
//! Bending (docs/MODEL.md, "Bending") and shear need `f(theta)` for the angle `theta`
//! between vectors `a` and `b`. Differentiating `theta` directly divides by
//! `sin(theta)`, which is 0/0 for straight yarns although `theta^2` is smooth
//! there. Instead, every energy is written as `F(c) = f(acos(c))` of the
//! cosine `c = a.b / (|a||b|)`, a smooth function of `(a, b)` with simple
//! derivatives, and the chain rule gives
//!
//! ```text
//! grad = F'(c) grad(c),   hess = F''(c) grad(c) grad(c)^T + F'(c) hess(c)
//! F'(c)  = -f'(theta) / sin(theta)
//! F''(c) = (f''(theta) sin(theta) - f'(theta) cos(theta)) / sin(theta)^3
//! ```
//!
//! For `f = k theta^2` these ratios tend to `-2k` and `2k/3` at `theta = 0`
//! and are evaluated by Taylor series there, so the straight configuration is
//! exact. `theta` itself comes from `atan2(|a x b|, a.b)`, accurate at both
//! ends of `[0, pi]`.
//!
//! Genuine singularities remain and are documented rather than hidden: at
//! `theta = pi` (a fold) `theta^2` has a concave cone point, and an energy
//! with `f'(0) != 0` (a nonzero rest angle) has a kink at `theta = 0`. There
//! `sin(theta)` is floored at [`SIN_FLOOR`] so results stay finite; the
//! Hessian is then huge and indefinite, and the solver's PSD projection
//! handles it.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Smallest `sin(theta)` used in divisions (keeps the kinks finite).
pub const SIN_FLOOR: f64 = 1e-12;

/// Below this angle the `theta -> 0` ratios use their Taylor series.
const SERIES_BELOW: f64 = 1e-3;

/// Angle between `a` and `b` in `[0, pi]`, accurate near 0 and pi.
pub fn angle_between(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

/// An energy profile `f(theta)`, reported in cosine form.
pub trait AngleProfile {
    /// Returns `(f(theta), F'(c), F''(c))` with `c = cos(theta)` (module doc).
    fn eval(&self, theta: f64, sin: f64, cos: f64) -> (f64, f64, f64);
}

/// Converts `(f, f', f'')` in `theta` to the cosine form, with a floored sine.
pub fn cosine_form(sin: f64, cos: f64, f: f64, df: f64, d2f: f64) -> (f64, f64, f64) {
    let s = sin.max(SIN_FLOOR);
    (f, -df / s, (d2f * s - df * cos) / (s * s * s))
}

/// `k (theta - rest)^2`, smooth at `theta = 0` when `rest == 0`.
#[derive(Clone, Copy, Debug)]
pub struct QuadraticAngle {
    pub k: f64,
    pub rest: f64,
}

impl AngleProfile for QuadraticAngle {
    fn eval(&self, theta: f64, sin: f64, cos: f64) -> (f64, f64, f64) {
        let d = theta - self.rest;
        if self.rest == 0.0 {
            let (t2, k) = (theta * theta, self.k);
            // theta/sin and (sin - theta cos)/sin^3, the two ratios of F' and F''.
            let (ratio1, ratio2) = if theta < SERIES_BELOW {
                (1.0 + t2 / 6.0 + 7.0 * t2 * t2 / 360.0, 1.0 / 3.0 + 2.0 * t2 / 15.0)
            } else {
                let s = sin.max(SIN_FLOOR);
                (theta / s, (sin - theta * cos) / (s * s * s))
            };
            return (k * t2, -2.0 * k * ratio1, 2.0 * k * ratio2);
        }
        cosine_form(sin, cos, self.k * d * d, 2.0 * self.k * d, 2.0 * self.k)
    }
}

/// The cosine of the angle between two vectors and its gradient, with the
/// normalised vectors the Hessian reuses.
struct CosineGradient {
    la: f64,
    lb: f64,
    ah: Vector3<f64>,
    bh: Vector3<f64>,
    c: f64,
    g: SVector<f64, 6>,
}

fn cosine_gradient(a: &Vector3<f64>, b: &Vector3<f64>) -> CosineGradient {
    let (la, lb) = (a.norm(), b.norm());
    let (ah, bh) = (a / la, b / lb);
    let c = ah.dot(&bh);
    let mut g = SVector::<f64, 6>::zeros();
    g.fixed_rows_mut::<3>(0).copy_from(&((bh - ah * c) / la));
    g.fixed_rows_mut::<3>(3).copy_from(&((ah - bh * c) / lb));
    CosineGradient { la, lb, ah, bh, c, g }
}

/// The cosine `c` of the angle between `a` and `b`, with its gradient and
/// Hessian with respect to `(a, b)` (6 coordinates, `a` first).
pub fn cosine_with_derivatives(a: &Vector3<f64>, b: &Vector3<f64>) -> (f64, SVector<f64, 6>, SMatrix<f64, 6, 6>) {
    let CosineGradient { la, lb, ah, bh, c, g } = cosine_gradient(a, b);
    let id = Matrix3::identity();
    let (aa, bb, ab) = (ah * ah.transpose(), bh * bh.transpose(), ah * bh.transpose());
    let h_aa = (-ab - ab.transpose() + aa * (3.0 * c) - id * c) / (la * la);
    let h_bb = (-ab - ab.transpose() + bb * (3.0 * c) - id * c) / (lb * lb);
    let h_ab = (id - bb - aa + ab * c) / (la * lb);
    let mut h = SMatrix::<f64, 6, 6>::zeros();
    h.fixed_view_mut::<3, 3>(0, 0).copy_from(&h_aa);
    h.fixed_view_mut::<3, 3>(3, 3).copy_from(&h_bb);
    h.fixed_view_mut::<3, 3>(0, 3).copy_from(&h_ab);
    h.fixed_view_mut::<3, 3>(3, 0).copy_from(&h_ab.transpose());
    (c, g, h)
}

/// `f(theta(a, b))` with gradient and Hessian with respect to `(a, b)`.
///
/// A zero-length vector has no direction: the energy is then taken at
/// `theta = 0` with zero derivatives (the stencil is inactive until the edge
/// has a length again).
pub fn angle_energy<P: AngleProfile>(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    profile: &P,
) -> (f64, SVector<f64, 6>, SMatrix<f64, 6, 6>) {
    let Some((theta, sin, cos)) = angle_terms(a, b) else {
        let (f, _, _) = profile.eval(0.0, 0.0, 1.0);
        return (f, SVector::zeros(), SMatrix::zeros());
    };
    let (f, df, d2f) = profile.eval(theta, sin, cos);
    let (_, gc, hc) = cosine_with_derivatives(a, b);
    (f, gc * df, gc * gc.transpose() * d2f + hc * df)
}

/// The value and gradient of [`angle_energy`] without its Hessian (for a
/// caller that models the Hessian otherwise): the same floating-point
/// operations, so the same bits.
pub fn angle_gradient<P: AngleProfile>(a: &Vector3<f64>, b: &Vector3<f64>, profile: &P) -> (f64, SVector<f64, 6>) {
    let Some((theta, sin, cos)) = angle_terms(a, b) else {
        let (f, _, _) = profile.eval(0.0, 0.0, 1.0);
        return (f, SVector::zeros());
    };
    let (f, df, _) = profile.eval(theta, sin, cos);
    (f, cosine_gradient(a, b).g * df)
}

/// The value of [`angle_energy`] alone. The line search evaluates energies
/// many times per Newton iteration and needs no derivatives; this runs the
/// same floating-point operations as `angle_energy`'s value, so both agree
/// to the bit and the relaxation path does not depend on which was called.
pub fn angle_value<P: AngleProfile>(a: &Vector3<f64>, b: &Vector3<f64>, profile: &P) -> f64 {
    match angle_terms(a, b) {
        Some((theta, sin, cos)) => profile.eval(theta, sin, cos).0,
        None => profile.eval(0.0, 0.0, 1.0).0,
    }
}

/// `(theta, sin theta, cos theta)` between `a` and `b`; `None` when either
/// has no direction (zero or subnormal length product).
fn angle_terms(a: &Vector3<f64>, b: &Vector3<f64>) -> Option<(f64, f64, f64)> {
    let (la, lb) = (a.norm(), b.norm());
    if la == 0.0 || lb == 0.0 || !(la * lb).is_normal() {
        return None;
    }
    let cross = a.cross(b).norm();
    let dot = a.dot(b);
    let theta = cross.atan2(dot);
    Some((theta, cross / (la * lb), dot / (la * lb)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_matches_direct_ratios() {
        // Direct formulas at theta = 0.01 are accurate to ~1e-11; the series
        // must agree there to its truncation error (~theta^4).
        let t: f64 = 0.01;
        let direct = (t / t.sin(), (t.sin() - t * t.cos()) / t.sin().powi(3));
        let t2 = t * t;
        let series = (1.0 + t2 / 6.0 + 7.0 * t2 * t2 / 360.0, 1.0 / 3.0 + 2.0 * t2 / 15.0);
        assert!((direct.0 - series.0).abs() < 1e-12);
        assert!((direct.1 - series.1).abs() < 1e-8);
    }

    #[test]
    fn the_gradient_alone_has_the_bits_of_angle_energy() {
        let profile = QuadraticAngle { k: 2.0, rest: 0.0 };
        for (a, b) in [
            (Vector3::new(1.0, 0.2, -0.3), Vector3::new(0.4, 1.1, 0.2)),
            (Vector3::new(1.0, 0.0, 0.0), Vector3::new(2.0, 1e-9, 0.0)),
            (Vector3::zeros(), Vector3::new(0.0, 1.0, 0.0)),
        ] {
            let (f, g, _) = angle_energy(&a, &b, &profile);
            assert_eq!((f, g), angle_gradient(&a, &b, &profile));
        }
    }

    #[test]
    fn right_angle_value() {
        let (a, b) = (Vector3::x(), Vector3::y() * 2.0);
        assert!((angle_between(&a, &b) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let (f, _, _) = angle_energy(&a, &b, &QuadraticAngle { k: 2.0, rest: 0.0 });
        assert!((f - 2.0 * std::f64::consts::FRAC_PI_2.powi(2)).abs() < 1e-14);
    }
}
