//! Shear at a yarn crossing, with jamming (docs/MODEL.md, "Crossing shear").
//!
//! Two yarns crossing at a contact can rotate about it (the in-plane shear of
//! a woven or knitted fabric). The angle `alpha` between their tangents is
//! penalised against its rest value, and stiffens sharply once the deviation
//! passes a jamming angle, where the yarns start to squeeze each other:
//!
//! ```text
//! gamma = alpha - alpha_rest,  e = max(0, |gamma| - gamma_jam)
//! V = ksh (gamma^2 / 2 + G e^3 / 3)
//! V'' = ksh (1 + 2 G e)
//! ```
//!
//! The cubic onset keeps `V` twice differentiable at the jam angle; beyond
//! it the stiffness grows by `2 G ksh` per radian. Each tangent is the chord
//! between the crossing node's neighbours on its yarn, `t = x_next - x_prev`,
//! so the crossing node itself does not enter (the tangent is the centred
//! difference there). If a neighbour is an EIL point the solver maps this
//! stencil's gradient through `eil::eil_jacobian`.
//!
//! Derivatives go through `cos(alpha)` (`angle.rs`). With a rest angle
//! near 90 degrees the singular ends `alpha = 0, pi` (yarns parallel) are far
//! outside the jammed range; there the energy has a genuine kink, and the
//! derivatives are kept finite by the floored sine.

use super::angle::{angle_between, angle_energy, angle_value, cosine_form, AngleProfile};
use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector, Vector3};

/// Crossing shear on `[a_prev(3), a_next(3), b_prev(3), b_next(3)]` (N = 12).
#[derive(Clone, Copy, Debug)]
pub struct Shear {
    /// Shear stiffness (J/rad^2).
    pub ksh: f64,
    /// Rest crossing angle (rad).
    pub rest_angle: f64,
    /// Deviation from rest where jamming starts (rad).
    pub jam_angle: f64,
    /// Jamming stiffening rate `G` (1/rad).
    pub jam_gain: f64,
}

impl AngleProfile for Shear {
    fn eval(&self, theta: f64, sin: f64, cos: f64) -> (f64, f64, f64) {
        let gamma = theta - self.rest_angle;
        let e = (gamma.abs() - self.jam_angle).max(0.0);
        let g = self.jam_gain;
        let f = self.ksh * (0.5 * gamma * gamma + g * e * e * e / 3.0);
        let df = self.ksh * (gamma + g * e * e * gamma.signum());
        let d2f = self.ksh * (1.0 + 2.0 * g * e);
        cosine_form(sin, cos, f, df, d2f)
    }
}

impl Shear {
    pub fn new(ksh: f64, rest_angle: f64, jam_angle: f64, jam_gain: f64) -> Self {
        Shear {
            ksh,
            rest_angle,
            jam_angle,
            jam_gain,
        }
    }

    /// A shear stencil whose rest angle is the crossing angle in `q0`.
    pub fn at_rest(ksh: f64, jam_angle: f64, jam_gain: f64, q0: &SVector<f64, 12>) -> Self {
        let (ta, tb) = tangents(q0);
        Shear::new(ksh, angle_between(&ta, &tb), jam_angle, jam_gain)
    }

    /// Value, gradient and Hessian together.
    pub fn evaluate(&self, q: &SVector<f64, 12>) -> (f64, SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        let (ta, tb) = tangents(q);
        let (f, g6, h6) = angle_energy(&ta, &tb, self);
        // t_a = q[3..6] - q[0..3], t_b = q[9..12] - q[6..9]: signs per block.
        let sign = [-1.0, 1.0, -1.0, 1.0];
        let block = [0, 0, 3, 3];
        let mut g = SVector::<f64, 12>::zeros();
        let mut h = SMatrix::<f64, 12, 12>::zeros();
        for i in 0..4 {
            g.fixed_rows_mut::<3>(3 * i)
                .copy_from(&(g6.fixed_rows::<3>(block[i]) * sign[i]));
            for j in 0..4 {
                let hb = h6.fixed_view::<3, 3>(block[i], block[j]) * (sign[i] * sign[j]);
                h.fixed_view_mut::<3, 3>(3 * i, 3 * j).copy_from(&hb);
            }
        }
        (f, g, h)
    }
}

fn tangents(q: &SVector<f64, 12>) -> (Vector3<f64>, Vector3<f64>) {
    (
        q.fixed_rows::<3>(3) - q.fixed_rows::<3>(0),
        q.fixed_rows::<3>(9) - q.fixed_rows::<3>(6),
    )
}

impl Stencil<12> for Shear {
    /// Without the derivatives (`angle_value`): the same bits as `evaluate`.
    fn value(&self, q: &SVector<f64, 12>) -> f64 {
        let (ta, tb) = tangents(q);
        angle_value(&ta, &tb, self)
    }
    fn gradient(&self, q: &SVector<f64, 12>) -> SVector<f64, 12> {
        self.evaluate(q).1
    }
    fn hessian(&self, q: &SVector<f64, 12>) -> SMatrix<f64, 12, 12> {
        self.evaluate(q).2
    }
    fn derivatives(&self, q: &SVector<f64, 12>, project: bool) -> (SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        let (_, g, h) = self.evaluate(q);
        if !project {
            return (g, h);
        }
        // The crossing angle depends only on the two chords `a_next - a_prev`
        // and `b_next - b_prev`: project in those six differences.
        const KEPT: [usize; 6] = [3, 4, 5, 9, 10, 11];
        const ANCHOR: [usize; 6] = [0, 1, 2, 6, 7, 8];
        (g, crate::energy::psd::project_psd_reduced(&h, &KEPT, &ANCHOR))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use crate::rod::testutil::{assert_all_finite, put3, Rng};
    use std::f64::consts::{FRAC_PI_2, PI};

    /// Yarn A along `t`, yarn B at angle `alpha` from it in a random plane.
    fn crossing(rng: &mut Rng, alpha: f64) -> SVector<f64, 12> {
        crossing_with_offset(rng, alpha, 0.05)
    }

    /// As `crossing`; B's previous node is shifted by up to `offset` so the
    /// tangents do not all pass through one point.
    fn crossing_with_offset(rng: &mut Rng, alpha: f64, offset: f64) -> SVector<f64, 12> {
        let t = rng.vec3(1.0).normalize();
        let n = rng.orthogonal_unit(&t);
        let c = rng.vec3(0.1);
        let tb = t * alpha.cos() + n * alpha.sin();
        let (la, lb) = (rng.range(0.5, 2.0), rng.range(0.5, 2.0));
        let mut q = SVector::<f64, 12>::zeros();
        put3(&mut q, 0, &(c - t * la));
        put3(&mut q, 3, &(c + t * la));
        let shift = tb * rng.range(-offset, offset);
        put3(&mut q, 6, &(c - tb * lb + shift));
        put3(&mut q, 9, &(c + tb * lb));
        q
    }

    #[test]
    fn energy_by_hand_below_and_past_jamming() {
        let mut rng = Rng::new(51);
        let s = Shear::new(2.0, FRAC_PI_2, 0.5, 10.0);
        // Exact alpha: B's prev/next without the random offset.
        let mut q = crossing(&mut rng, FRAC_PI_2 + 0.2);
        let (ta, _) = tangents(&q);
        let c = (q.fixed_rows::<3>(0) + q.fixed_rows::<3>(3)) * 0.5;
        let n = rng.orthogonal_unit(&ta);
        for (alpha, expect) in [
            (FRAC_PI_2 + 0.2, 2.0 * 0.02),
            (FRAC_PI_2 - 0.7, 2.0 * (0.245 + 10.0 * 0.008 / 3.0)),
        ] {
            let tb = ta.normalize() * alpha.cos() + n * alpha.sin();
            put3(&mut q, 6, &(c - tb));
            put3(&mut q, 9, &(c + tb * 2.0));
            assert!((s.value(&q) - expect).abs() < 1e-12, "alpha {alpha}");
        }
        // Rest state from the configuration: zero energy and force.
        let r = Shear::at_rest(2.0, 0.5, 10.0, &q);
        assert!(r.value(&q).abs() < 1e-20 && r.gradient(&q).norm() < 1e-10);
    }

    #[test]
    fn value_alone_has_the_bits_of_evaluate() {
        let mut rng = Rng::new(54);
        let s = Shear::new(1.0, 1.4, 0.3, 20.0);
        for k in 0..200 {
            let mut q = rng.vector::<12>(1.0);
            if k % 5 == 0 {
                let a = q.fixed_rows::<3>(0).into_owned();
                q.fixed_rows_mut::<3>(3).copy_from(&a); // zero-length tangent
            }
            if k % 7 == 0 {
                let (a0, a1) = (q.fixed_rows::<3>(0).into_owned(), q.fixed_rows::<3>(3).into_owned());
                q.fixed_rows_mut::<3>(6).copy_from(&a0);
                q.fixed_rows_mut::<3>(9).copy_from(&(a0 + (a1 - a0) * 2.0)); // parallel tangents
            }
            assert_eq!(s.value(&q).to_bits(), s.evaluate(&q).0.to_bits(), "{q:?}");
        }
    }

    #[test]
    fn derivatives_random_and_jammed() {
        let mut rng = Rng::new(52);
        let s = Shear::new(1.0, 1.4, 0.3, 20.0);
        for _ in 0..60 {
            let alpha = rng.range(0.2, 2.9);
            let q = crossing(&mut rng, alpha);
            check_derivatives(&s, &q, 1e-6, 1e-5);
        }
    }

    #[test]
    fn parallel_tangents_are_finite() {
        let mut rng = Rng::new(53);
        let s = Shear::new(1.0, FRAC_PI_2, 0.5, 20.0);
        for alpha in [0.0, 1e-8, PI - 1e-8, PI] {
            let q = crossing_with_offset(&mut rng, alpha, 0.0);
            assert_all_finite(&s, &q);
            // Parallel yarns are 90 degrees from rest: V = ksh (pi/2)^2 / 2
            // plus the jamming term with e = pi/2 - 0.5.
            let e: f64 = FRAC_PI_2 - 0.5;
            let expect = 0.5 * FRAC_PI_2 * FRAC_PI_2 + 20.0 * e.powi(3) / 3.0;
            assert!((s.value(&q) - expect).abs() < 1e-6, "alpha {alpha}");
        }
        // Close to parallel but off the kink, derivatives stay exact.
        let q = crossing(&mut rng, 1e-3);
        check_derivatives(&s, &q, 1e-8, 1e-4);
        // Coincident neighbours (zero tangent): finite, inactive.
        let mut q = crossing(&mut rng, 1.0);
        let a_prev = q.fixed_rows::<3>(0).into_owned();
        put3(&mut q, 3, &a_prev);
        assert_all_finite(&s, &q);
    }
}
