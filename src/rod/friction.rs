//! Sliding friction on an Eulerian coordinate (docs/MODEL.md, "Friction
//! anchors").
//!
//! Each Eulerian coordinate of a contact (both yarns' `u` at an EoL contact,
//! the free `u` of an EIL point) is tied to an anchor by a spring of
//! stiffness `kf` whose force is capped at the Coulomb limit `F = mu |f_n|`:
//!
//! ```text
//! Vf(s) = 1/2 kf s^2              |s| <= F / kf      (stick)
//!       = F |s| - F^2 / (2 kf)    otherwise          (slip)
//! s = u - u_anchor
//! ```
//!
//! This is the anchored spring with the anchor update done *inside* the
//! step (a return mapping, as in elasto-plasticity) rather than after it.
//! The spring still gives static friction with an elastic stick of at most
//! `F / kf`; past it the force is exactly `F`, whatever the slip in the step.
//! Updating the anchor only after each step instead (the first version of
//! this module) caps the slip of one step at `(f_drive - F) / kf`: sliding
//! becomes a viscous drag of coefficient `kf h`, and a yarn that should
//! slide down a 50 degree incline at `g (sin - mu cos)` crept at 3 um/s.
//! The normal force `f_n` is lagged (taken at the start of the step, as IPC
//! lags it), so the energy is a fixed convex C1 function inside a step.
//! [`coulomb_update`] then moves the anchor to where the return mapping
//! put it.

use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector};

/// Anchored friction spring with a Coulomb force cap on `[u]` (N = 1).
#[derive(Clone, Copy, Debug)]
pub struct FrictionSpring {
    /// Spring stiffness (N per metre of Eulerian slip).
    pub kf: f64,
    /// Anchor position in Eulerian coordinates (m).
    pub anchor: f64,
    /// Largest friction force `mu |f_n|` (N); infinite = a plain spring.
    pub limit: f64,
}

impl FrictionSpring {
    pub fn new(kf: f64, anchor: f64, limit: f64) -> Self {
        FrictionSpring {
            kf,
            anchor,
            limit: limit.abs(),
        }
    }

    /// The stick range `F / kf`.
    fn reach(&self) -> f64 {
        self.limit / self.kf
    }
}

impl Stencil<1> for FrictionSpring {
    fn value(&self, q: &SVector<f64, 1>) -> f64 {
        let s = q[0] - self.anchor;
        if s.abs() <= self.reach() {
            0.5 * self.kf * s * s
        } else {
            self.limit * (s.abs() - 0.5 * self.reach())
        }
    }
    fn gradient(&self, q: &SVector<f64, 1>) -> SVector<f64, 1> {
        let f = self.kf * (q[0] - self.anchor);
        SVector::<f64, 1>::new(f.clamp(-self.limit, self.limit))
    }
    fn hessian(&self, q: &SVector<f64, 1>) -> SMatrix<f64, 1, 1> {
        let stick = (q[0] - self.anchor).abs() <= self.reach();
        SMatrix::<f64, 1, 1>::new(if stick { self.kf } else { 0.0 })
    }
}

/// The anchor after a step ending at `u`: unchanged while the spring force
/// `kf |u - anchor|` is within `limit = mu |f_n|`, otherwise moved toward
/// `u` until the force equals the limit. A non-positive `kf` has no spring
/// to limit and returns `u` (no friction memory).
pub fn coulomb_update(anchor: f64, u: f64, kf: f64, limit: f64) -> f64 {
    if kf <= 0.0 {
        return u;
    }
    let max_stretch = limit.abs() / kf;
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
        let f = FrictionSpring::new(4.0, 1.0, f64::INFINITY);
        let q = SVector::<f64, 1>::new(1.5);
        assert!((f.value(&q) - 0.5).abs() < 1e-15);
        assert!((f.gradient(&q)[0] - 2.0).abs() < 1e-15);
        check_derivatives(&f, &q, 1e-6, 1e-8);
    }

    #[test]
    fn capped_spring_derivatives_in_stick_and_slip() {
        // Reach 2 N / 4 N/m = 0.5 m around the anchor at 1.
        let f = FrictionSpring::new(4.0, 1.0, 2.0);
        for u in [0.2, 0.9, 1.0, 1.3, 1.8, 40.0, -3.0] {
            check_derivatives(&f, &SVector::<f64, 1>::new(u), 1e-7, 1e-6);
        }
        // Value and force are continuous at the kink (C1).
        let at = |u: f64| {
            (
                f.value(&SVector::<f64, 1>::new(u)),
                f.gradient(&SVector::<f64, 1>::new(u))[0],
            )
        };
        let (e0, g0) = at(1.5 - 1e-12);
        let (e1, g1) = at(1.5 + 1e-12);
        assert!((e0 - e1).abs() < 1e-10 && (g0 - g1).abs() < 1e-10);
        assert!((g1 - 2.0).abs() < 1e-10);
        // Slip: the force is the Coulomb limit whatever the slip.
        assert_eq!(at(40.0).1, 2.0);
        assert_eq!(at(-3.0).1, -2.0);
    }

    #[test]
    fn zero_normal_force_is_frictionless() {
        let f = FrictionSpring::new(4.0, 1.0, 0.0);
        for u in [0.5, 1.0, 2.0] {
            let q = SVector::<f64, 1>::new(u);
            assert_eq!(f.gradient(&q)[0], 0.0);
            assert!(f.value(&q).abs() < 1e-15);
        }
    }

    #[test]
    fn anchor_sticks_below_the_limit() {
        // Force 100 * 0.01 = 1 N < 1.5 N.
        assert_eq!(coulomb_update(0.0, 0.01, 100.0, 1.5), 0.0);
        // The limit's sign does not matter.
        assert_eq!(coulomb_update(0.0, -0.01, 100.0, -1.5), 0.0);
    }

    #[test]
    fn anchor_slides_at_the_limit() {
        // Limit 1 N = 100 N/m * 0.01 m: the anchor trails u by 0.01.
        for (u, expect) in [(0.3, 0.29), (-0.3, -0.29)] {
            let a = coulomb_update(0.0, u, 100.0, 1.0);
            assert!((a - expect).abs() < 1e-15, "u = {u}: anchor {a}");
            let f = FrictionSpring::new(100.0, a, 1.0);
            let force = f.gradient(&SVector::<f64, 1>::new(u))[0];
            assert!((force.abs() - 1.0).abs() < 1e-12);
        }
        // No normal force: no friction, the anchor jumps to u.
        assert_eq!(coulomb_update(0.0, 0.3, 100.0, 0.0), 0.3);
    }
}
