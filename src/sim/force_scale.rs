//! The force scale a relaxation is measured against (docs/RELAX.md,
//! "Stopping test").
//!
//! A free force is small or large only next to the forces that shape the
//! fabric. A knitted loop is held in shape by bending: a loop of rest
//! length `l` in a yarn of bending rigidity `kb` pushes on its neighbours
//! with forces of order `kb / l^2`. With gravity on, the weight of one loop,
//! `rho g l`, is a second scale, and the smaller of the two is the one
//! that a converged state must resolve. The stopping test divides the
//! largest free force by this scale, so the same tolerance means the same
//! thing for a fingering swatch and a chunky one, and does not change when
//! the axial stiffness `ks` (which sets no shape) does.

use super::params::SimParams;
use crate::topology::Fabric;
use serde::Serialize;

/// The scales of a scene (N), and the one the stopping test uses.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ForceScale {
    /// Mean rest yarn length per stitch (m).
    pub loop_length: f64,
    /// `kb / l^2`.
    pub bending: f64,
    /// `rho |g| l`, when gravity is on.
    pub weight: Option<f64>,
    /// The smallest active scale: what forces are divided by.
    pub value: f64,
}

impl ForceScale {
    /// The scale of `f` simulated with `p`.
    pub fn of(f: &Fabric, p: &SimParams) -> Self {
        let yarn: f64 = f.yarns.iter().map(|y| y.rest_length).sum();
        let stitches = f.meta.width * f.meta.height;
        // A fabric that is not a swatch (a test rope, a stack) falls back
        // to a loop of four contact nodes' worth of yarn.
        let loops = if stitches > 0 {
            stitches
        } else {
            (f.contacts.len() / 4).max(1)
        };
        let l = if yarn > 0.0 { yarn / loops as f64 } else { 1e-2 };
        let bending = p.rod.kb / (l * l);
        let weight = p.terms.gravity.then(|| p.rod.rho * p.rod.gravity.norm() * l);
        let value = weight
            .filter(|w| *w > 0.0)
            .map_or(bending, |w| w.min(bending))
            .max(f64::MIN_POSITIVE);
        ForceScale {
            loop_length: l,
            bending,
            weight,
            value,
        }
    }

    /// A tolerance in units of this scale, as a fraction of the axial
    /// stiffness `ks` (what `RelaxOptions::tol` holds).
    pub fn to_ks_units(&self, tol: f64, ks: f64) -> f64 {
        tol * self.value / ks
    }

    /// A residual over `ks` (what `Simulation::static_residual` returns),
    /// in units of this scale.
    pub fn from_ks_units(&self, residual: f64, ks: f64) -> f64 {
        residual * ks / self.value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_is_a_loops_bending_force_or_its_weight() {
        let mut f = crate::io::fixtures::crossing();
        f.meta.width = 2;
        f.meta.height = 1;
        let yarn: f64 = f.yarns.iter().map(|y| y.rest_length).sum();
        let mut p = SimParams::default();
        let s = ForceScale::of(&f, &p);
        let l = yarn / 2.0;
        assert!((s.loop_length - l).abs() < 1e-15);
        assert!((s.value - p.rod.kb / (l * l)).abs() < 1e-12 * s.value);
        // Gravity on: the smaller of the two.
        p.terms.gravity = true;
        let g = ForceScale::of(&f, &p);
        let w = p.rod.rho * 9.81 * l;
        assert!((g.value - w.min(s.bending)).abs() < 1e-12 * g.value);
        // Round trip through ks units.
        let r = g.to_ks_units(3.0, p.rod.ks);
        assert!((g.from_ks_units(r, p.rod.ks) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn doubling_ks_leaves_the_scale_alone() {
        let f = crate::io::fixtures::crossing();
        let mut p = SimParams::default();
        let a = ForceScale::of(&f, &p);
        p.rod.ks *= 2.0;
        assert_eq!(a, ForceScale::of(&f, &p));
    }
}
