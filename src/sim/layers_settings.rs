//! The layers of a scene (`"layers"`): copies of the draped fabric placed
//! on each other, joined where their yarns touch, and optionally sewn
//! together along edges (a pocket, a tag). `knitsim drape` builds them
//! after relaxing the fabric once (`app::drape::layers`); a relaxation
//! ignores them. The joining itself is `topology::layers`.

use super::dynamics_settings::Edge;
use serde::{Deserialize, Serialize};

/// `"layers"` in a scene. Every key has a default; no patches = one layer,
/// the fabric as it is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LayersParams {
    /// One entry per layer, bottom first: where that copy of the fabric goes.
    pub patches: Vec<PatchPlacement>,
    /// Yarns of two layers closer than `reach` times the sum of their radii
    /// get a persistent layer contact at the start.
    #[serde(deserialize_with = "crate::checked::positive")]
    pub reach: f64,
    /// Seams sewing one layer onto another.
    pub seams: Vec<Seam>,
    /// Patch `k` is first lifted by `k` times the fabric's depth plus this
    /// gap (m) along `z`, so that layers start apart and touch across the
    /// gap only; `null` = one diameter of the thickest yarn. A flat fabric
    /// (a weave) can lie in one surface with its layers: 0.
    #[serde(deserialize_with = "crate::checked::optional_non_negative")]
    pub gap: Option<f64>,
}

impl Default for LayersParams {
    fn default() -> Self {
        LayersParams {
            patches: Vec::new(),
            reach: 1.5,
            seams: Vec::new(),
            gap: None,
        }
    }
}

/// Where one copy goes: turned about its own centre by `rotate_deg`
/// (degrees about x, then y, then z), then moved by `translate` (m); and
/// how stiff its yarns are, as a multiple of the scene's `rod.ks` and
/// `rod.kb` (a tag several times stiffer than the shirt under it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PatchPlacement {
    pub translate: [f64; 3],
    pub rotate_deg: [f64; 3],
    #[serde(deserialize_with = "crate::checked::positive")]
    pub stiffness: f64,
}

impl Default for PatchPlacement {
    fn default() -> Self {
        PatchPlacement {
            translate: [0.0; 3],
            rotate_deg: [0.0; 3],
            stiffness: 1.0,
        }
    }
}

/// Sews patch `top` onto patch `bottom` along `edges` of `top` (its edges
/// before placement: `left` smallest `x`, and so on): every yarn point of
/// `top` within `margin` (m) of such an edge, and close enough to a yarn
/// of `bottom`, becomes a seam contact.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Seam {
    pub top: usize,
    pub bottom: usize,
    pub edges: Vec<Edge>,
    #[serde(default = "default_margin", deserialize_with = "crate::checked::positive")]
    pub margin: f64,
}

fn default_margin() -> f64 {
    2e-3
}
