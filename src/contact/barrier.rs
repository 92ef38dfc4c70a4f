//! The IPC log barrier on distances, its biphasic (hard-core) form, and the
//! adaptive barrier stiffness of IPC.
//!
//! **Barrier** (docs/MODEL.md, "Thickness contact"):
//! `b(d, a) = -(d - a)^2 ln(d / a)` for `0 < d < a`, zero for `d >= a`,
//! `+inf` for `d <= 0`. It is C2 at `d = a` (value, slope and curvature all
//! vanish there), which is what lets Newton cross the activation boundary.
//!
//! **Convention.** We apply `b` to the *unsquared* distance `d`. ipc-toolkit's
//! `BarrierPotential` evaluates the same scalar function on squared distances,
//! `b(d^2, dhat^2)` (checked against ipctk 1.6.1: a pair at `d = 0.3`,
//! `dhat = 0.5` gives `ipctk.barrier(0.09, 0.25)`). The biphasic form needs
//! the unsquared distance (`d - eta` is not a function of `d^2 - eta^2`), so
//! we keep `d` throughout; the scalar functions `ipctk.barrier(d, dhat)`,
//! `barrier_first_derivative` and `barrier_second_derivative` are then
//! identical to [`barrier`], [`barrier_d1`] and [`barrier_d2`] with
//! `d -> d`, `dhat -> a` (the fixtures compare them 1:1).
//!
//! **Biphasic** (*Codimensional IPC*): `b(d, a, eta) =
//! b(d - eta, a - eta)`. The barrier diverges at the hard core `d = eta`
//! and is soft on `(eta, a)`. [`BarrierShape`] carries `(a, eta)` per stencil
//! because the filter gives different stencils different shapes.
//!
//! **Adaptive stiffness** (as in *Incremental Potential Contact*):
//! kappa starts at the value that best balances the elastic gradient against
//! the barrier gradient (least squares), clamped to `[kappa_min, kappa_max]`
//! where `kappa_min` makes the barrier's curvature at a tiny gap comparable to
//! the mass scale; it doubles whenever the smallest gap keeps shrinking below
//! a tiny fraction of the scene size. See [`AdaptiveStiffness`].

/// `b(d, a)`: the IPC barrier on a distance `d` with activation distance `a`.
pub fn barrier(d: f64, a: f64) -> f64 {
    if d >= a {
        0.0
    } else if d <= 0.0 {
        f64::INFINITY
    } else {
        -(d - a) * (d - a) * (d / a).ln()
    }
}

/// `db/dd = (a - d) (2 ln(d/a) - a/d + 1)`; zero for `d >= a`.
pub fn barrier_d1(d: f64, a: f64) -> f64 {
    if d >= a {
        0.0
    } else {
        (a - d) * (2.0 * (d / a).ln() - a / d + 1.0)
    }
}

/// `d2b/dd2 = (a/d)^2 + 2 a/d - 2 ln(d/a) - 3`; zero for `d >= a`.
pub fn barrier_d2(d: f64, a: f64) -> f64 {
    if d >= a {
        0.0
    } else {
        let r = a / d;
        r * r + 2.0 * r - 2.0 * (d / a).ln() - 3.0
    }
}

/// The barrier of one stencil: activation distance `a` and hard core `eta`
/// (`0 <= eta < a`; `eta = 0` is the single-phase barrier).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarrierShape {
    /// Distance at which the barrier switches on.
    pub activation: f64,
    /// Distance at which it diverges (the thickness offset of *Codimensional IPC*).
    pub core: f64,
}

impl BarrierShape {
    pub fn single_phase(activation: f64) -> Self {
        Self { activation, core: 0.0 }
    }

    pub fn biphasic(activation: f64, core: f64) -> Self {
        Self { activation, core }
    }

    /// Whether a distance `d` is inside the activation range (the stencil exists).
    pub fn is_active(&self, d: f64) -> bool {
        d < self.activation
    }

    /// `b(d, a, eta)`.
    pub fn value(&self, d: f64) -> f64 {
        barrier(d - self.core, self.activation - self.core)
    }

    /// First derivative with respect to `d`.
    pub fn d1(&self, d: f64) -> f64 {
        barrier_d1(d - self.core, self.activation - self.core)
    }

    /// Second derivative with respect to `d`.
    pub fn d2(&self, d: f64) -> f64 {
        barrier_d2(d - self.core, self.activation - self.core)
    }
}

/// Settings of IPC's adaptive barrier stiffness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarrierParams {
    /// `kappa_min` makes `kappa * b''` at the tiny reference gap equal to
    /// `min_stiffness_scale * mean_mass` (IPC uses 1e11).
    pub min_stiffness_scale: f64,
    /// `kappa_max = max_stiffness_factor * kappa_min` (IPC: 100).
    pub max_stiffness_factor: f64,
    /// Reference gap for `kappa_min`, as a fraction of the scene's bounding
    /// box diagonal (IPC: 1e-8).
    pub reference_gap_fraction: f64,
    /// kappa doubles when the smallest gap shrinks below this fraction of
    /// the bounding box diagonal (IPC: 1e-9).
    pub close_gap_fraction: f64,
}

impl Default for BarrierParams {
    fn default() -> Self {
        Self {
            min_stiffness_scale: 1e11,
            max_stiffness_factor: 100.0,
            reference_gap_fraction: 1e-8,
            close_gap_fraction: 1e-9,
        }
    }
}

/// The current barrier stiffness and its bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveStiffness {
    pub kappa: f64,
    pub kappa_min: f64,
    pub kappa_max: f64,
}

impl AdaptiveStiffness {
    /// Initial stiffness at the start of a solve.
    ///
    /// `grad_energy` is the gradient of everything but the barrier,
    /// `grad_barrier` the gradient of the unit-stiffness barrier sum (same
    /// layout). kappa minimises `|grad_energy + kappa grad_barrier|`, then is
    /// clamped to `[kappa_min, kappa_max]`. `shape` is the (widest) barrier
    /// of the scene; `bbox_diagonal` its size; `mean_mass` the mean nodal mass.
    pub fn initial(
        params: &BarrierParams,
        shape: BarrierShape,
        bbox_diagonal: f64,
        mean_mass: f64,
        grad_energy: &[f64],
        grad_barrier: &[f64],
    ) -> Self {
        let soft_range = shape.activation - shape.core;
        // The reference gap must lie inside the soft range or b'' vanishes.
        let gap = (params.reference_gap_fraction * bbox_diagonal).min(0.5 * soft_range);
        let curvature = barrier_d2(gap, soft_range);
        let kappa_min = if curvature > 0.0 && curvature.is_finite() {
            params.min_stiffness_scale * mean_mass / curvature
        } else {
            0.0
        };
        let kappa_max = params.max_stiffness_factor * kappa_min;
        Self::balanced(kappa_min, kappa_max, grad_energy, grad_barrier)
    }

    /// The least-squares balance of the two gradients (see [`Self::initial`])
    /// clamped to caller-given bounds. Quasi-static solves have no mass
    /// scale, so the simulator derives its bounds from the bending
    /// stiffness instead (`sim::terms::thickness_contact`).
    pub fn balanced(kappa_min: f64, kappa_max: f64, grad_energy: &[f64], grad_barrier: &[f64]) -> Self {
        let gb2: f64 = grad_barrier.iter().map(|g| g * g).sum();
        let ge_gb: f64 = grad_energy.iter().zip(grad_barrier).map(|(e, b)| e * b).sum();
        let balance = if gb2 > 0.0 { -ge_gb / gb2 } else { kappa_min };
        let kappa = balance.max(kappa_min).min(kappa_max.max(kappa_min));
        Self {
            kappa,
            kappa_min,
            kappa_max,
        }
    }

    /// Doubles kappa (up to `kappa_max`) when the smallest gap `d - eta`
    /// over all stencils decreased since the last Newton iterate and is
    /// already tiny. Returns whether kappa changed.
    pub fn update(&mut self, params: &BarrierParams, prev_min_gap: f64, min_gap: f64, bbox_diagonal: f64) -> bool {
        let close = params.close_gap_fraction * bbox_diagonal;
        if prev_min_gap < close && min_gap < prev_min_gap && self.kappa < self.kappa_max {
            self.kappa = (2.0 * self.kappa).min(self.kappa_max);
            return true;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_values() {
        // b(a/e, a) = -(a/e - a)^2 ln(1/e) = (a (1 - 1/e))^2
        let a = 2.0;
        let e = std::f64::consts::E;
        assert!((barrier(a / e, a) - (a * (1.0 - 1.0 / e)).powi(2)).abs() < 1e-14);
        assert_eq!(barrier(a, a), 0.0);
        assert_eq!(barrier(3.0, a), 0.0);
        assert_eq!(barrier(0.0, a), f64::INFINITY);
        // Smooth switch-on: value, slope and curvature vanish at d = a.
        let d = a * (1.0 - 1e-7);
        assert!(barrier(d, a) < 1e-20 && barrier_d1(d, a).abs() < 1e-12 && barrier_d2(d, a).abs() < 1e-5);
    }

    #[test]
    fn derivatives_match_differences() {
        for &(d, a) in &[(0.1, 1.0), (0.5, 1.0), (0.93, 1.0), (1e-3, 2e-3), (0.25, 0.3)] {
            let h = 1e-6 * d;
            let fd1 = (barrier(d + h, a) - barrier(d - h, a)) / (2.0 * h);
            let fd2 = (barrier_d1(d + h, a) - barrier_d1(d - h, a)) / (2.0 * h);
            assert!(
                (fd1 - barrier_d1(d, a)).abs() <= 1e-7 * fd1.abs().max(a),
                "d1 at {d}, {a}"
            );
            assert!(
                (fd2 - barrier_d2(d, a)).abs() <= 1e-6 * fd2.abs().max(1.0),
                "d2 at {d}, {a}"
            );
        }
    }

    #[test]
    fn biphasic_diverges_at_core() {
        let s = BarrierShape::biphasic(1.0, 0.6);
        assert_eq!(s.value(0.6), f64::INFINITY);
        assert!((s.value(0.8) - barrier(0.2, 0.4)).abs() < 1e-15);
        assert_eq!(s.value(1.0), 0.0);
        assert!(s.d1(0.7) < 0.0 && s.d2(0.7) > 0.0);
    }

    #[test]
    fn stiffness_balances_gradients_and_doubles() {
        let p = BarrierParams::default();
        let shape = BarrierShape::single_phase(1e-3);
        // Barrier gradient opposite to the elastic one: kappa = 3 balances them.
        let ge = [3.0, -6.0];
        let gb = [-1.0, 2.0];
        // Mean mass chosen so that kappa_min ~ 0.1 and the balance lies in range.
        let mass = 1e-2;
        let k = AdaptiveStiffness::initial(&p, shape, 1.0, mass, &ge, &gb);
        let kmin = 1e11 * mass / barrier_d2(1e-8, 1e-3);
        assert!((k.kappa_min - kmin).abs() < 1e-12 * kmin);
        assert!(kmin < 3.0 && 3.0 < k.kappa_max);
        assert!((k.kappa - 3.0).abs() < 1e-12);
        // Outside the range the balance is clamped.
        let soft = AdaptiveStiffness::initial(&p, shape, 1.0, 1.0, &ge, &gb);
        assert_eq!(soft.kappa, soft.kappa_min);
        let mut k2 = k;
        assert!(!k2.update(&p, 1e-3, 5e-4, 1.0), "gap not tiny: no change");
        assert!(k2.update(&p, 1e-10, 5e-11, 1.0));
        assert_eq!(k2.kappa, (2.0 * k.kappa).min(k.kappa_max));
    }
}
