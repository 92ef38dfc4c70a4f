//! Material parameters of a yarn-level fabric, in SI units.
//!
//! Defaults describe a DK-weight wool yarn: radius 0.75 mm, about 2 g per
//! 4 m. The numbers are order-of-magnitude textile values, chosen so the
//! relaxed fabric looks right and the Newton solve stays well conditioned:
//!
//! - `ks` is the axial stiffness `EA` (N). A loosely twisted wool yarn
//!   stretches ~1% under 1 N, so `EA ~ 100 N`. The stretch energy
//!   (docs/MODEL.md, "Stretch") gives a segment stiffness `ks / du`.
//! - `kb` is the bending rigidity `EI` (N m^2). The bending energy (docs/MODEL.md, "Bending") is exactly the
//!   discrete `1/2 EI integral kappa^2` with curvature `2 theta / (du1 + du2)`
//!   integrated over the Voronoi length `(du1 + du2) / 2`, so `kb = EI`.
//!   Measured yarn rigidities are 0.01-0.1 cN cm^2 (1e-8..1e-7 N m^2); with
//!   `rho` below the bending length `(EI / rho g)^(1/3)` is about 2.7 cm, the
//!   hand-feel of a soft wool yarn.
//! - `kc_factor`: the EIL contact spring is `kc_factor * ks / du_rest`.
//!   *Robust Eulerian-on-Lagrangian Rods* uses 1000; the default here
//!   is 10 (docs/MODEL.md, "EIL constraint spring"). Every EoL/EIL
//!   transition starts that spring off its rest by up to a sagitta (~0.1 mm
//!   at a stitch), and at 1000 that is ~0.4 J against a relaxed 8x8 linen
//!   stitch's 7e-3 J: a quasi-static relaxation spends whole Newton solves
//!   undoing it and the linen stitch stopped converging. At 10 the spring is
//!   still ~1e6 N/m; a 1 N contact force opens a 1.3 um gap (0.2% of the
//!   radius), which `cargo run --release --example relax_diagnose -- gaps` reports.
//! - `kf`, `mu`: friction anchor spring (N/m) and Coulomb coefficient
//!   (wool on wool 0.2-0.5). `kf` is soft next to the stretch stiffness
//!   `ks / du ~ 3e4 N/m` so stick-slip does not dominate conditioning; a
//!   typical 0.05 N friction force then allows 0.05 mm of elastic stick.
//! - `kw_factor`, `ksh_factor`: the wrapping and crossing-shear stiffnesses
//!   (J/rad^2) as multiples of `EI / d`, the bending stiffness of yarn
//!   bent over one diameter (`RodParams::kw`, `RodParams::ksh`). Both are
//!   angle energies of yarn turning around another yarn, so they scale
//!   with the yarn: a thicker yarn knitted at a coarser gauge keeps the
//!   ratio of wrapping to bending, and its stockinette measures its own
//!   gauge (docs/MODEL.md, "Wrapping"). At 0.27 a 0.45 mm model radius
//!   (a 0.75 mm stated yarn) gets 3e-5 J/rad^2.
//! - Shear jamming: past `shear_jam_angle` (rad, from rest) the stiffness
//!   grows by `2 * shear_jam_gain` per radian (see `shear.rs`).
//! - `kp` (N/m): parallel-contact penalty; like the stretch stiffness of a
//!   short segment so yarns cannot be pushed through each other cheaply.
//! - `rho` (kg/m): linear density; `gravity` (m/s^2).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Rod material and contact parameters (SI units, see the module doc).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RodParams {
    /// Yarn radius (m); the parallel-contact distance is the diameter.
    /// `knitsim` sets it from the pattern's thickest yarn unless a scene
    /// gives it (`scene::params_for`).
    #[serde(deserialize_with = "crate::checked::positive")]
    pub radius: f64,
    /// Axial stiffness `EA` (N).
    #[serde(deserialize_with = "crate::checked::positive")]
    pub ks: f64,
    /// Bending rigidity `EI` (N m^2).
    #[serde(deserialize_with = "crate::checked::positive")]
    pub kb: f64,
    /// EIL contact stiffness as a multiple of `ks / du_rest`.
    #[serde(deserialize_with = "crate::checked::positive")]
    pub kc_factor: f64,
    /// Friction anchor spring stiffness (N/m of Eulerian slip).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub kf: f64,
    /// Coulomb friction coefficient.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub mu: f64,
    /// Wrapping stiffness as a multiple of `kb / d` ([`RodParams::kw`]).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub kw_factor: f64,
    /// Crossing shear stiffness as a multiple of `kb / d` ([`RodParams::ksh`]).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub ksh_factor: f64,
    /// Shear deviation from rest where jamming starts (rad).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub shear_jam_angle: f64,
    /// Jamming stiffening rate (1/rad).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub shear_jam_gain: f64,
    /// Parallel-contact penalty stiffness (N/m).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub kp: f64,
    /// Linear density (kg/m).
    #[serde(deserialize_with = "crate::checked::positive")]
    pub rho: f64,
    /// Gravitational acceleration (m/s^2).
    pub gravity: Vector3<f64>,
}

impl Default for RodParams {
    fn default() -> Self {
        RodParams {
            radius: 0.75e-3,
            ks: 100.0,
            kb: 1e-7,
            kc_factor: 10.0,
            kf: 1e3,
            mu: 0.3,
            kw_factor: 0.27,
            ksh_factor: 0.27,
            shear_jam_angle: 0.5,
            shear_jam_gain: 50.0,
            kp: 3e4,
            rho: 5e-4,
            gravity: Vector3::new(0.0, 0.0, -9.81),
        }
    }
}

impl RodParams {
    /// EIL contact spring stiffness `kc = kc_factor * ks / du_rest` (docs/MODEL.md, "EIL constraint spring").
    pub fn contact_stiffness(&self, du_rest: f64) -> f64 {
        self.kc_factor * self.ks / du_rest
    }

    /// Wrapping stiffness `kw_factor kb / d` (J/rad^2, docs/MODEL.md, "Wrapping").
    pub fn kw(&self) -> f64 {
        self.kw_factor * self.kb / self.diameter()
    }

    /// Crossing shear stiffness `ksh_factor kb / d` (J/rad^2, docs/MODEL.md, "Crossing shear").
    pub fn ksh(&self) -> f64 {
        self.ksh_factor * self.kb / self.diameter()
    }

    /// Diameter at `radius`: with one radius for every yarn
    /// (`sim::YarnRadii::Uniform`), the smallest Eulerian distance between
    /// parallel contacts; per-yarn radii use the sum of the two crossing
    /// yarns' radii instead (`sim::terms`).
    pub fn diameter(&self) -> f64 {
        2.0 * self.radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contact_stiffness_is_kc_factor_times_segment_stiffness() {
        let p = RodParams::default();
        // 10 * 100 N / 2 mm = 5e5 N/m.
        assert!((p.contact_stiffness(2e-3) - 5e5).abs() < 1e-6);
        let bending_length = (p.kb / (p.rho * p.gravity.norm())).cbrt();
        assert!((0.01..0.05).contains(&bending_length));
    }

    #[test]
    fn angle_stiffnesses_follow_bending_over_one_diameter() {
        // The stated 0.75 mm yarn is simulated at 0.45 mm: 0.27 * 1e-7 / 0.9e-3.
        let p = RodParams {
            radius: 0.45e-3,
            ..RodParams::default()
        };
        assert!((p.kw() - 3e-5).abs() < 1e-12 && (p.ksh() - 3e-5).abs() < 1e-12);
        // Twice the yarn at twice the rigidity turns alike: kw doubles with kb and halves with d.
        let q = RodParams {
            radius: 0.9e-3,
            kb: 4e-7,
            ..RodParams::default()
        };
        assert!((q.kw() - 2.0 * p.kw()).abs() < 1e-12);
    }
}
