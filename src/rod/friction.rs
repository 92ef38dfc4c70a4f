//! Sliding friction on an Eulerian coordinate (Cirio 2014; seed 000 sec. 4.2).
//!
//! Each Eulerian coordinate of a contact (both yarns' `u` at an EoL contact,
//! the free `u` of an EIL point) is tied to an anchor by a spring
//!
//! ```text
//! Vf = 1/2 kf (u - u_anchor)^2
//! ```
//!
//! The spring is the "stick" part of Coulomb friction. After each time step
//! [`coulomb_update`] drags the anchor along so the spring force never
//! exceeds the Coulomb limit `mu |f_n|`: below the limit the anchor stays
//! (static friction, the contact springs back), above it the anchor follows
//! at the limit distance (kinetic friction, the contact slides with a
//! resisting force `mu |f_n|`). Keeping the anchor out of the Newton solve
//! makes the energy a plain quadratic inside a step.

use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector};

/// Anchored friction spring on `[u]` (N = 1).
#[derive(Clone, Copy, Debug)]
pub struct FrictionSpring {
    /// Spring stiffness (N per metre of Eulerian slip).
    pub kf: f64,
    /// Anchor position in Eulerian coordinates (m).
    pub anchor: f64,
}

impl FrictionSpring {
    pub fn new(kf: f64, anchor: f64) -> Self {
        FrictionSpring { kf, anchor }
    }
}

impl Stencil<1> for FrictionSpring {
    fn value(&self, q: &SVector<f64, 1>) -> f64 {
        0.5 * self.kf * (q[0] - self.anchor).powi(2)
    }
    fn gradient(&self, q: &SVector<f64, 1>) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(self.kf * (q[0] - self.anchor))
    }
    fn hessian(&self, _q: &SVector<f64, 1>) -> SMatrix<f64, 1, 1> {
        SMatrix::<f64, 1, 1>::new(self.kf)
    }
}

/// The anchor after a step ending at `u`: unchanged while the spring force
/// `kf |u - anchor|` is within `mu |normal_force|`, otherwise moved toward
/// `u` until the force equals the limit. A non-positive `kf` has no spring
/// to limit and returns `u` (no friction memory).
pub fn coulomb_update(anchor: f64, u: f64, kf: f64, mu: f64, normal_force: f64) -> f64 {
    if kf <= 0.0 {
        return u;
    }
    let max_stretch = mu.abs() * normal_force.abs() / kf;
    let stretch = u - anchor;
    if stretch.abs() <= max_stretch {
        anchor
    } else {
        u - stretch.signum() * max_stretch
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;

    #[test]
    fn spring_value_and_derivatives() {
        let f = FrictionSpring::new(4.0, 1.0);
        let q = SVector::<f64, 1>::new(1.5);
        assert!((f.value(&q) - 0.5).abs() < 1e-15);
        assert!((f.gradient(&q)[0] - 2.0).abs() < 1e-15);
        check_derivatives(&f, &q, 1e-6, 1e-8);
    }

    #[test]
    fn anchor_sticks_below_the_limit() {
        // Force 100 * 0.01 = 1 N < 0.5 * 3 N.
        assert_eq!(coulomb_update(0.0, 0.01, 100.0, 0.5, 3.0), 0.0);
        // The normal force's sign does not matter.
        assert_eq!(coulomb_update(0.0, -0.01, 100.0, 0.5, -3.0), 0.0);
    }

    #[test]
    fn anchor_slides_at_the_limit() {
        // Limit 0.5 * 2 N = 1 N = 100 N/m * 0.01 m: the anchor trails u by 0.01.
        for (u, expect) in [(0.3, 0.29), (-0.3, -0.29)] {
            let a = coulomb_update(0.0, u, 100.0, 0.5, 2.0);
            assert!((a - expect).abs() < 1e-15, "u = {u}: anchor {a}");
            let force = 100.0 * (u - a);
            assert!((force.abs() - 1.0).abs() < 1e-12);
        }
        // No normal force: no friction, the anchor jumps to u.
        assert_eq!(coulomb_update(0.0, 0.3, 100.0, 0.5, 0.0), 0.3);
    }
}
