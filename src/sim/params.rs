//! What a simulation includes and how stiff it is.
//!
//! Every term can be switched off, and a term that is off builds no stencil
//! at all: a scene pays only for what it uses (obstacles, gravity, friction,
//! inertia in quasi-static relaxation).

use crate::rod::bending::BendingHessian;
use crate::rod::params::RodParams;
use crate::scene::Shape;
use crate::sim::assignment::AssignParams;
use crate::sim::contact_terms::ContactParams;
use crate::sim::separation::SeparationParams;
use crate::topology::Fabric;
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
    /// from the yarn ends (see `sim::end_stops`).
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
    #[serde(deserialize_with = "crate::scene::positive")]
    pub obstacle_stiffness: f64,
    /// Non-persistent yarn-yarn contact; `None` (no `"contact"` key) = off
    /// and free. See `sim::contact_terms`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactParams>,
    /// Remove a contact once its `u` leaves a yarn (`sim::removal`); a
    /// check per contact point per step, and a rebuild only when it fires.
    pub remove_slid_off: bool,
    /// Remove a contact whose normal force pulls its yarns together (the
    /// sign test, `sim::separation`); `None` (no `"separation"` key) = off
    /// and free: no normals are tracked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation: Option<SeparationParams>,
    /// The PSD Hessian model of the bending stencils (`"eigen"`, the
    /// default, or `"split"`; `rod::bending::BendingHessian`).
    pub bending_hessian: BendingHessian,
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
        }
    }
}

impl SimParams {
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
