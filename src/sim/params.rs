//! What a simulation includes and how stiff it is: every setting of the
//! `sim` pipeline, in one file at the bottom of its layers.
//!
//! Every term can be switched off, and a term that is off builds no stencil
//! at all: a scene pays only for what it uses (obstacles, gravity, friction,
//! inertia in quasi-static relaxation).
//!
//! The settings of each mechanism live here and not beside the mechanism,
//! because [`SimParams`] holds them all and every mechanism reads
//! `SimParams`: kept beside their mechanisms they made `params` and the
//! mechanisms import each other. Here every layer above can read them.

use super::dynamics_settings::DynamicsParams;
use super::layers_settings::LayersParams;
use crate::contact::ContactMode;
use crate::rod::bending::BendingHessian;
use crate::rod::obstacle::Shape;
use crate::rod::params::RodParams;
use crate::topology::{ContactKind, Fabric};
use serde::{Deserialize, Serialize};

/// Which energy terms exist.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Terms {
    pub bending: bool,
    pub friction: bool,
    pub wrapping: bool,
    pub shear: bool,
    pub parallel: bool,
    pub gravity: bool,
    /// Yarn tails are woven in: the outermost contacts keep their distance
    /// from the yarn ends (see `sim::terms::end_stops`).
    pub secured_ends: bool,
}

impl Default for Terms {
    fn default() -> Self {
        Terms {
            bending: true,
            friction: true,
            wrapping: true,
            shear: true,
            parallel: true,
            gravity: false,
            secured_ends: true,
        }
    }
}

/// Which radius each yarn is simulated with: where two yarns of different
/// thickness meet, the distances the rod model keeps between them (the
/// parallel-contact distance, the secured ends' stop, the clearance over an
/// obstacle) are sums of the radii actually there.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum YarnRadii {
    /// `rod.radius` for every yarn (a scene that sets `rod.radius` means
    /// this, and so does a `SimParams` built in code).
    #[default]
    Uniform,
    /// Each yarn's own radius from its pattern spec (`meta.yarns[spec]`);
    /// `rod.radius` for a yarn whose spec has no usable radius.
    /// `scene::params_for` picks this unless the scene sets `rod.radius`.
    Pattern,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimParams {
    pub rod: RodParams,
    /// Per-yarn radii or one for all (see [`YarnRadii`]).
    pub radii: YarnRadii,
    pub assign: AssignParams,
    pub terms: Terms,
    pub obstacles: Vec<Shape>,
    /// Penalty stiffness of obstacles (N/m).
    #[serde(deserialize_with = "crate::checked::positive")]
    pub obstacle_stiffness: f64,
    /// Non-persistent yarn-yarn contact; `None` (no `"contact"` key) = off
    /// and free. See `sim::terms::thickness_contact`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactParams>,
    /// Remove a contact once its `u` leaves a yarn (`sim::events::removal`); a
    /// check per contact point per step, and a rebuild only when it fires.
    pub remove_slid_off: bool,
    /// Remove a contact whose normal force pulls its yarns together (the
    /// sign test, `sim::events::separation`); `None` (no `"separation"` key) = off
    /// and free: no normals are tracked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation: Option<SeparationParams>,
    /// The PSD Hessian model of the bending stencils (`"eigen"`, the
    /// default, or `"split"`; `rod::bending::BendingHessian`).
    pub bending_hessian: BendingHessian,
    /// Settings of dynamic runs (`knitsim drape`): gravity, damping,
    /// obstacle friction, time stepping, pins and motions
    /// (`sim::dynamics_settings`).
    pub dynamics: DynamicsParams,
    /// Stacked and sewn copies of the fabric (`knitsim drape`;
    /// `sim::layers_settings`); `None` = one layer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layers: Option<LayersParams>,
}

impl Default for SimParams {
    fn default() -> Self {
        SimParams {
            rod: RodParams::default(),
            radii: YarnRadii::default(),
            assign: AssignParams::default(),
            terms: Terms::default(),
            obstacles: Vec::new(),
            obstacle_stiffness: 1e5,
            contact: None,
            remove_slid_off: true,
            separation: None,
            bending_hessian: BendingHessian::default(),
            dynamics: DynamicsParams::default(),
            layers: None,
        }
    }
}

impl SimParams {
    /// The rod material of a yarn of stacked layer `layer` (`Yarn::layer`):
    /// `rod` with `ks` and `kb` scaled by that patch's `stiffness`
    /// (`layers.patches`; 1 without layers).
    pub fn yarn_rod(&self, layer: usize) -> RodParams {
        let scale = self
            .layers
            .as_ref()
            .and_then(|l| l.patches.get(layer))
            .map_or(1.0, |p| p.stiffness);
        let mut rod = self.rod.clone();
        rod.ks *= scale;
        rod.kb *= scale;
        rod
    }

    /// Whether thickness contact between yarns is on (a `"contact"` whose
    /// mode is not `none`).
    pub fn contact_on(&self) -> bool {
        self.contact.as_ref().is_some_and(|c| c.mode != ContactModeName::None)
    }

    /// The radius of every yarn of `f` (m), by [`SimParams::radii`].
    pub fn yarn_radii(&self, f: &Fabric) -> Vec<f64> {
        f.yarns
            .iter()
            .map(|y| match self.radii {
                YarnRadii::Uniform => self.rod.radius,
                YarnRadii::Pattern => f
                    .meta
                    .yarns
                    .get(y.spec)
                    .map(|s| s.radius)
                    .filter(|r| r.is_finite() && *r > 0.0)
                    .unwrap_or(self.rod.radius),
            })
            .collect()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AssignParams {
    /// Safety distance as a fraction of the rest segment length (0.1, docs/MODEL.md, "Node assignment").
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub safety_fraction: f64,
    /// `false` disables EIL entirely (plain EoL), to show why EIL matters.
    pub enable_eil: bool,
    /// An EIL point turns real again only once it is this fraction of the
    /// rest segment from the previous real point and from the next point
    /// that stays real (hysteresis; at least
    /// `safety_fraction`). Without it a point hovering at the safety
    /// distance flips kind every step, and every flip restarts Newton from
    /// a perturbed state.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub release_fraction: f64,
    /// Within a step, a sliding real point stops when its segment to a
    /// real neighbour is this fraction of the rest segment (below
    /// `safety_fraction`, so the next re-assignment makes it EIL); 0 = no
    /// stop (the default; 0.05 is half the safety distance). Opt-in: see
    /// `sim::problem::slide_stops` and docs/RELAX.md, "Slide stops", for what it does to
    /// the relaxation.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub stop_fraction: f64,
    /// Within a relaxation step, a real segment shorter than this fraction
    /// of the rest segment ends the step (`sim::problem::tripwire`), so the next
    /// re-assignment hands its sliding point to EIL; 0 = off. Below
    /// `safety_fraction`, so a tripped segment is always re-assigned.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub close_fraction: f64,
}

impl Default for AssignParams {
    fn default() -> Self {
        AssignParams {
            safety_fraction: 0.1,
            enable_eil: true,
            release_fraction: 0.2,
            stop_fraction: 0.0,
            close_fraction: 1e-5,
        }
    }
}

/// The contact treatment, as scenes and the CLI spell it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactModeName {
    None,
    Penalty,
    Barrier,
    Culled,
    #[default]
    Filtered,
}

impl std::str::FromStr for ContactModeName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(Self::None),
            "penalty" => Ok(Self::Penalty),
            "barrier" => Ok(Self::Barrier),
            "culled" => Ok(Self::Culled),
            "filtered" => Ok(Self::Filtered),
            _ => Err(format!(
                "unknown contact mode '{s}' (none, penalty, barrier, culled, filtered)"
            )),
        }
    }
}

/// Settings of non-persistent contact (see the module doc).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ContactParams {
    pub mode: ContactModeName,
    /// Material thickness `h` (m); `None` = the thickest yarn's diameter
    /// (`SimParams::yarn_radii`; `2 rod.radius` when all yarns share it).
    #[serde(deserialize_with = "crate::checked::optional_positive")]
    pub thickness: Option<f64>,
    /// Hard core `eta = core_fraction * h` of full-thickness pairs (docs/MODEL.md,
    /// "Thickness contact"; 0 = single phase).
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub core_fraction: f64,
    /// Culling window (segments) of the `culled` mode; default 11.
    pub cull_window: u32,
    /// Exclusion radius around persistent EoL contacts, in units of `h`.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub eol_exclusion: f64,
    /// Candidate margin in units of `h`: pairs within `(1 + margin) h` are
    /// listed per solve; nodes may move `0.45 margin h` before a rebuild.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub margin: f64,
    /// `kappa_min = stiffness_scale * kb / h^3`.
    #[serde(deserialize_with = "crate::checked::positive")]
    pub stiffness_scale: f64,
    /// `kappa_max = max_stiffness_factor * kappa_min`.
    #[serde(deserialize_with = "crate::checked::positive")]
    pub max_stiffness_factor: f64,
    /// kappa doubles while the smallest gap shrinks below `close_gap * h`.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub close_gap: f64,
    /// Stiffness of the `penalty` mode (N/m).
    #[serde(deserialize_with = "crate::checked::positive")]
    pub penalty_stiffness: f64,
}

impl Default for ContactParams {
    fn default() -> Self {
        ContactParams {
            mode: ContactModeName::Filtered,
            thickness: None,
            core_fraction: 0.0,
            cull_window: 11,
            eol_exclusion: 1.0,
            margin: 1.0,
            stiffness_scale: 1.0,
            max_stiffness_factor: 1e4,
            close_gap: 1e-3,
            penalty_stiffness: 1e3,
        }
    }
}

impl ContactParams {
    pub fn mode(&self) -> ContactMode {
        match self.mode {
            ContactModeName::None => ContactMode::None,
            ContactModeName::Penalty => ContactMode::Penalty,
            ContactModeName::Barrier => ContactMode::Barrier,
            ContactModeName::Culled => ContactMode::Culled {
                window: self.cull_window,
            },
            ContactModeName::Filtered => ContactMode::Filtered,
        }
    }

    /// Thickness `h` for a yarn of radius `radius`.
    pub fn thickness_for(&self, radius: f64) -> f64 {
        self.thickness.unwrap_or(2.0 * radius)
    }
}

/// The sign test's settings; `SimParams::separation` is `None` (off) by default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SeparationParams {
    /// Contact kinds that may separate (see the module docs).
    pub kinds: Vec<ContactKind>,
    /// A contact goes when its normal force is below `-min_pull` (N). The
    /// default 0 removes any contact that pulls at all.
    #[serde(deserialize_with = "crate::checked::non_negative")]
    pub min_pull: f64,
}

impl Default for SeparationParams {
    fn default() -> Self {
        SeparationParams {
            kinds: vec![ContactKind::Layer],
            min_pull: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_keys_select_the_mode() {
        let off: SimParams = serde_json::from_str("{}").expect("empty scene");
        assert_eq!(off.contact, None, "contact is off unless a scene asks for it");
        let on: SimParams = serde_json::from_str(r#"{"contact": {}}"#).expect("contact object");
        assert_eq!(on.contact.as_ref().map(|c| c.mode()), Some(ContactMode::Filtered));
        let culled: SimParams =
            serde_json::from_str(r#"{"contact": {"mode": "culled", "cull_window": 5}}"#).expect("culled");
        assert_eq!(
            culled.contact.as_ref().map(|c| c.mode()),
            Some(ContactMode::Culled { window: 5 })
        );
        assert!(serde_json::from_str::<SimParams>(r#"{"contact": {"mode": "tight"}}"#).is_err());
        assert_eq!("barrier".parse(), Ok(ContactModeName::Barrier));
        assert!("bogus".parse::<ContactModeName>().is_err());
    }
}
