//! Wrapping at a stitch contact (docs/MODEL.md, "Wrapping" and
//! "Stitch contact layout").
//!
//! A stitch contact is two EoL contact nodes `P` and `Q` shared by yarn A
//! (say the parent loop's head) and yarn B (the child's leg). Between them
//! A turns around B. The wrap angle is how far A's direction turns *about
//! B's axis* from where it reaches the contact to where it leaves it:
//!
//! ```text
//! t1 = P - a_prev        (A arriving at P)
//! t2 = a_next - Q        (A leaving Q)
//! b  = b_next - b_prev   (B's axis: the chord of B across the contact)
//! phi = atan2( b^.(t1 x t2),  t1.t2 - (t1.b^)(t2.b^) ),   b^ = b / |b|
//! V = 1/2 kw wrap(phi - phi_rest)^2
//! ```
//!
//! The two `atan2` arguments are `|p1||p2| sin` and `|p1||p2| cos` of the
//! signed angle between `p1, p2`, the projections of `t1, t2` onto the plane
//! normal to `b`: turning along B (A sliding up the leg) does not count as
//! wrapping, and a signed angle has no kink when A leaves the contact
//! straight (`phi = 0`), unlike an unsigned one. `P` and `Q` enter only
//! through `t1, t2`: the turn at `P`, along the arc and at `Q` add up to the
//! turn from `t1` to `t2`, so coincident `P = Q` is harmless.
//!
//! `phi_rest` comes from the initial configuration ([`Wrapping::at_rest`]).
//! `wrap` maps the difference to `(-pi, pi]`: it only shifts the value, so
//! the energy is smooth while the wrap stays within half a turn of rest. The
//! remaining singularity is genuine: A's arriving or leaving direction
//! parallel to B, where the projected angle is undefined and its
//! derivatives grow like `1 / |p|`. Newton iterates do wander there
//! (a 16x16 stockinette relax hit forces of 1e4 N from it), so the energy
//! is faded out smoothly as the projections vanish:
//!
//! ```text
//! c = |p1|^2 |p2|^2 / (|t1|^2 |t2|^2)       (1 when A crosses B squarely)
//! V = s(c) 1/2 kw wrap(phi - phi_rest)^2,    s = smoothstep from C_OFF to C_ON
//! ```
//!
//! `s = 1` for every real stitch geometry (A crosses B at well over 20
//! degrees); `s = 0` where the angle is undefined, so `V` is `C^1` with a
//! bounded Hessian everywhere except `|b| = 0`.
//!
//! The terms are products of a dozen dot and cross products, so value,
//! gradient and Hessian come from second-order forward differentiation
//! ([`super::jet`]) instead of a hand derivation. A symmetric model adds the
//! same stencil with the roles of A and B swapped.

use super::jet::{Jet, JetVec3};
use crate::energy::psd::project_psd;
use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector, Vector3};
use std::f64::consts::{PI, TAU};

/// Wrapping stencil on `[a_prev(3), p(3), q(3), a_next(3), b_prev(3), b_next(3)]` (N = 18).
#[derive(Clone, Copy, Debug)]
pub struct Wrapping {
    /// Wrapping stiffness (J/rad^2).
    pub kw: f64,
    /// Rest wrap angle (rad, signed about `b_next - b_prev`).
    pub rest_angle: f64,
}

const A_PREV: usize = 0;
const P: usize = 3;
const Q: usize = 6;
const A_NEXT: usize = 9;
const B_PREV: usize = 12;
const B_NEXT: usize = 15;

/// The signed wrap angle of a local vector (module doc), plain `f64`.
pub fn wrap_angle(q: &SVector<f64, 18>) -> f64 {
    let at = |i: usize| Vector3::new(q[i], q[i + 1], q[i + 2]);
    let t1 = at(P) - at(A_PREV);
    let t2 = at(A_NEXT) - at(Q);
    let b = (at(B_NEXT) - at(B_PREV)).normalize();
    b.dot(&t1.cross(&t2)).atan2(t1.dot(&t2) - t1.dot(&b) * t2.dot(&b))
}

/// Below this `c` (module doc) the wrapping energy is off: A within about
/// 8 degrees of B's axis at both ends.
const C_OFF: f64 = 0.02;
/// Above this `c` the wrapping energy is fully on (about 18 degrees).
const C_ON: f64 = 0.1;

/// The fade `s(c)` with its first two derivatives.
fn fade(c: f64) -> (f64, f64, f64) {
    let w = C_ON - C_OFF;
    let x = (c - C_OFF) / w;
    if x <= 0.0 {
        (0.0, 0.0, 0.0)
    } else if x >= 1.0 {
        (1.0, 0.0, 0.0)
    } else {
        (
            x * x * (3.0 - 2.0 * x),
            6.0 * x * (1.0 - x) / w,
            (6.0 - 12.0 * x) / (w * w),
        )
    }
}

/// The fade of a local vector, plain `f64`.
fn fade_value(q: &SVector<f64, 18>) -> f64 {
    let r = reduce(q);
    let at = |i: usize| Vector3::new(r[i], r[i + 1], r[i + 2]);
    let (t1, t2, b) = (at(0), at(3), at(6));
    let bh = b.normalize();
    let p1 = t1 - bh * t1.dot(&bh);
    let p2 = t2 - bh * t2.dot(&bh);
    let c = p1.norm_squared() * p2.norm_squared() / (t1.norm_squared() * t2.norm_squared());
    fade(c).0
}

/// `d` shifted by whole turns into `(-pi, pi]`.
fn wrap_to_half_turn(d: f64) -> f64 {
    let r = d.rem_euclid(TAU);
    if r > PI {
        r - TAU
    } else {
        r
    }
}

impl Wrapping {
    pub fn new(kw: f64, rest_angle: f64) -> Self {
        Wrapping { kw, rest_angle }
    }

    /// A wrapping stencil at rest in configuration `q0`.
    pub fn at_rest(kw: f64, q0: &SVector<f64, 18>) -> Self {
        Wrapping::new(kw, wrap_angle(q0))
    }

    /// The wrap angle as a jet over the reduced variables `[t1, t2, b]`
    /// (9 instead of 18: the angle depends on the six points only through
    /// these differences, so the jet is 4x cheaper), or `None` where it is
    /// undefined.
    fn angle_jet(q: &SVector<f64, 18>) -> Option<(Jet<9>, Jet<9>)> {
        let r = reduce(q);
        let x = |i| JetVec3::variables(&r, i);
        let (t1, t2, b) = (x(0), x(3), x(6));
        let b_len2 = b.dot(&b);
        if b_len2.v <= 0.0 || !b_len2.v.is_finite() {
            return None;
        }
        let bh = b.scale(&b_len2.sqrt().recip());
        let sin_part = bh.dot(&t1.cross(&t2));
        let cos_part = t1.dot(&t2) - t1.dot(&bh) * t2.dot(&bh);
        // |p1|^2 |p2|^2 = sin_part^2 + cos_part^2 (Lagrange's identity in the plane).
        let r2 = sin_part * sin_part + cos_part * cos_part;
        let scale = t1.dot(&t1) * t2.dot(&t2);
        // Also rejects NaN (comparisons with NaN are false).
        if r2.v.is_nan() || r2.v <= 1e-28 * scale.v {
            return None;
        }
        let c = r2 * scale.recip();
        Some((sin_part.atan2(&cos_part), c))
    }

    /// Energy, gradient and Hessian in the reduced variables.
    fn reduced(&self, q: &SVector<f64, 18>) -> Option<(f64, SVector<f64, 9>, SMatrix<f64, 9, 9>)> {
        let (phi, c) = Self::angle_jet(q)?;
        let (s, ds, d2s) = fade(c.v);
        if s == 0.0 {
            return Some((0.0, SVector::zeros(), SMatrix::zeros()));
        }
        let d = wrap_to_half_turn(phi.v - self.rest_angle);
        let e = phi.chain(0.5 * self.kw * d * d, self.kw * d, self.kw);
        if s == 1.0 {
            return Some((e.v, e.g, e.h));
        }
        let e = e * c.chain(s, ds, d2s);
        Some((e.v, e.g, e.h))
    }

    /// Value, gradient and Hessian together.
    pub fn evaluate(&self, q: &SVector<f64, 18>) -> (f64, SVector<f64, 18>, SMatrix<f64, 18, 18>) {
        match self.reduced(q) {
            Some((v, g, h)) => (v, expand_gradient(&g), expand_hessian(&h)),
            None => (self.value(q), SVector::zeros(), SMatrix::zeros()),
        }
    }
}

/// Block `k` of the 18 local coordinates enters the reduced variables as
/// `sign * block[REDUCED[k].0]`: `t1 = P - a_prev`, `t2 = a_next - Q`,
/// `b = b_next - b_prev`.
const REDUCED: [(usize, f64); 6] = [(0, -1.0), (0, 1.0), (1, -1.0), (1, 1.0), (2, -1.0), (2, 1.0)];

fn reduce(q: &SVector<f64, 18>) -> SVector<f64, 9> {
    let at = |i: usize| Vector3::new(q[i], q[i + 1], q[i + 2]);
    let (t1, t2, b) = (at(P) - at(A_PREV), at(A_NEXT) - at(Q), at(B_NEXT) - at(B_PREV));
    SVector::<f64, 9>::from_fn(|i, _| [t1, t2, b][i / 3][i % 3])
}

/// `J^T g` for the constant map `J` of [`REDUCED`].
fn expand_gradient(g: &SVector<f64, 9>) -> SVector<f64, 18> {
    SVector::<f64, 18>::from_fn(|i, _| {
        let (blk, sign) = REDUCED[i / 3];
        sign * g[3 * blk + i % 3]
    })
}

/// `J^T H J`: PSD whenever `H` is, so projecting the 9x9 suffices.
fn expand_hessian(h: &SMatrix<f64, 9, 9>) -> SMatrix<f64, 18, 18> {
    SMatrix::<f64, 18, 18>::from_fn(|i, j| {
        let (bi, si) = REDUCED[i / 3];
        let (bj, sj) = REDUCED[j / 3];
        si * sj * h[(3 * bi + i % 3, 3 * bj + j % 3)]
    })
}

impl Stencil<18> for Wrapping {
    fn value(&self, q: &SVector<f64, 18>) -> f64 {
        // Plain f64: the line search calls this far more often than the derivatives.
        let v = fade_value(q) * 0.5 * self.kw * wrap_to_half_turn(wrap_angle(q) - self.rest_angle).powi(2);
        if v.is_finite() {
            v
        } else {
            0.0
        }
    }
    fn gradient(&self, q: &SVector<f64, 18>) -> SVector<f64, 18> {
        self.evaluate(q).1
    }
    fn hessian(&self, q: &SVector<f64, 18>) -> SMatrix<f64, 18, 18> {
        self.evaluate(q).2
    }
    fn derivatives(&self, q: &SVector<f64, 18>, project: bool) -> (SVector<f64, 18>, SMatrix<f64, 18, 18>) {
        match self.reduced(q) {
            Some((_, g, h)) => {
                let h = if project { project_psd(&h) } else { h };
                (expand_gradient(&g), expand_hessian(&h))
            }
            None => (SVector::zeros(), SMatrix::zeros()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use crate::rod::testutil::{assert_all_finite, put3, Rng};

    /// B along z through the origin; A arrives along +x at P and leaves Q
    /// turned by `phi` about z, with a component `rise` along B.
    fn contact(phi: f64, rise: f64, pq: f64) -> SVector<f64, 18> {
        let mut q = SVector::<f64, 18>::zeros();
        let p = Vector3::new(0.0, 0.0, 0.0);
        let qq = Vector3::new(0.0, pq, 0.1 * pq);
        put3(&mut q, A_PREV, &(p - Vector3::x()));
        put3(&mut q, P, &p);
        put3(&mut q, Q, &qq);
        put3(&mut q, A_NEXT, &(qq + Vector3::new(phi.cos(), phi.sin(), rise) * 1.5));
        put3(&mut q, B_PREV, &Vector3::new(0.1, 0.0, -1.0));
        put3(&mut q, B_NEXT, &Vector3::new(0.1, 0.0, 1.0));
        q
    }

    #[test]
    fn wrap_angle_by_hand() {
        for phi in [0.0, 0.5, 2.0, -2.5] {
            // Rising along B does not change the wrap angle.
            for rise in [0.0, 0.7, -3.0] {
                assert!((wrap_angle(&contact(phi, rise, 0.05)) - phi).abs() < 1e-12);
            }
        }
        // A 120 degree wrap against a 90 degree rest: V = kw/2 (pi/6)^2.
        let w = Wrapping::new(4.0, PI / 2.0);
        assert!((w.value(&contact(2.0 * PI / 3.0, 0.3, 0.05)) - 2.0 * (PI / 6.0).powi(2)).abs() < 1e-12);
        // Flipping B's direction flips the sign of the angle.
        let mut q = contact(1.0, 0.0, 0.05);
        q.swap_rows(B_PREV + 2, B_NEXT + 2);
        assert!((wrap_angle(&q) + 1.0).abs() < 1e-12);
        // At rest: no force.
        let r = Wrapping::at_rest(4.0, &q);
        assert!(r.value(&q) == 0.0 && r.gradient(&q).norm() < 1e-14);
    }

    #[test]
    fn derivatives_random() {
        let mut rng = Rng::new(61);
        for _ in 0..40 {
            let q = rng.vector::<18>(1.0);
            let w = Wrapping::new(2.0, rng.range(-2.0, 2.0));
            // Stay off the branch where the difference from rest is half a turn.
            if wrap_to_half_turn(wrap_angle(&q) - w.rest_angle).abs() > 3.0 {
                continue;
            }
            check_derivatives(&w, &q, 1e-6, 1e-5);
        }
    }

    #[test]
    fn near_degenerate_contacts() {
        let w = Wrapping::new(2.0, 0.0);
        // Straight through (phi ~ 1e-8): no kink for a signed angle.
        check_derivatives(&w, &contact(1e-8, 0.2, 0.05), 1e-7, 1e-5);
        // Folded back (phi ~ pi - 1e-6), against a rest angle near it.
        let folded = Wrapping::new(2.0, PI - 0.1);
        check_derivatives(&folded, &contact(PI - 1e-6, 0.2, 0.05), 1e-8, 1e-5);
        // Coincident contact nodes P = Q.
        let q = contact(1.2, 0.2, 0.0);
        assert_all_finite(&w, &q);
        check_derivatives(&w, &q, 1e-6, 1e-5);
        // A arriving along B (projection undefined), zero-length axis, and
        // coincident a_prev = P: finite.
        let mut along = contact(1.0, 0.0, 0.05);
        put3(&mut along, A_PREV, &Vector3::new(0.0, 0.0, -1.0));
        assert_all_finite(&w, &along);
        let mut no_axis = contact(1.0, 0.0, 0.05);
        put3(&mut no_axis, B_NEXT, &Vector3::new(0.1, 0.0, -1.0));
        assert_all_finite(&w, &no_axis);
        let mut short = contact(1.0, 0.0, 0.05);
        put3(&mut short, A_PREV, &Vector3::zeros());
        assert_all_finite(&w, &short);
    }

    #[test]
    fn fades_out_smoothly_as_a_turns_along_b() {
        // A leaves with direction (cos phi, sin phi, rise): c = 1 / (1 + rise^2).
        let w = Wrapping::new(2.0, 0.3);
        for rise in [3.5, 4.36, 6.0] {
            // c = 0.075, 0.05 (inside the fade) and 0.027 (near its end).
            check_derivatives(&w, &contact(1.0, rise, 0.05), 1e-7, 1e-5);
        }
        // Steep enough that the angle is meaningless: no energy, no force.
        let steep = contact(1.0, 10.0, 0.05);
        assert!(w.value(&steep) == 0.0 && w.gradient(&steep).norm() == 0.0);
        // A square crossing is untouched by the fade: V = kw/2 (1 - 0.3)^2.
        assert!((w.value(&contact(1.0, 0.0, 0.05)) - 0.49).abs() < 1e-12);
    }

    #[test]
    fn reduced_space_projection_is_psd() {
        let mut rng = Rng::new(7);
        let w = Wrapping::new(3.0, 0.4);
        for _ in 0..20 {
            let q = rng.vector::<18>(1.0);
            let (g, h) = w.derivatives(&q, false);
            assert!((g - w.gradient(&q)).norm() < 1e-12 && (h - w.hessian(&q)).norm() < 1e-12);
            let (_, hp) = w.derivatives(&q, true);
            let (ev, _) = crate::energy::psd::sym_eigen(&hp);
            let scale = h.norm().max(1.0);
            assert!(ev.iter().all(|&e| e > -1e-10 * scale), "{ev:?}");
        }
    }
}
