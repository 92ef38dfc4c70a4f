//! Building a scene's layers (`"layers"`, `sim::layers_settings`): one
//! copy of the relaxed fabric per patch, lifted above the ones before it
//! (by the fabric's depth plus `gap`), placed, merged into one fabric, sewn
//! along the scene's seams and joined by layer contacts where yarns of two
//! layers touch (`topology::layers`).

use crate::sim::dynamics_settings::Edge;
use crate::sim::LayersParams;
use crate::topology::layers::{join_layers, place, sew, Placement};
use crate::topology::stack::depth;
use crate::topology::{stack_layers_mapped, Fabric, TopologyError, Vec3};

/// The layered fabric and what was built.
pub struct Layered {
    pub fabric: Fabric,
    /// `node_maps[k][i]`: the layered fabric's index of patch `k`'s node `i`.
    pub node_maps: Vec<Vec<usize>>,
    pub layer_contacts: usize,
    pub seam_contacts: usize,
}

#[derive(Debug, thiserror::Error)]
pub enum LayersError {
    #[error("layers.seams[{index}] sews patch {top} onto patch {bottom}, but the scene has {count} patches")]
    SeamPatch {
        index: usize,
        top: usize,
        bottom: usize,
        count: usize,
    },
    #[error(transparent)]
    Topology(#[from] TopologyError),
}

/// Places one copy of `base` per patch and joins and sews them.
pub fn build_layers(base: &Fabric, lp: &LayersParams) -> Result<Layered, LayersError> {
    let count = lp.patches.len();
    if let Some((index, s)) = lp
        .seams
        .iter()
        .enumerate()
        .find(|(_, s)| s.top >= count || s.bottom >= count || s.top == s.bottom)
    {
        return Err(LayersError::SeamPatch {
            index,
            top: s.top,
            bottom: s.bottom,
            count,
        });
    }
    let thickest = base.meta.yarns.iter().map(|y| y.radius).fold(0.0, f64::max);
    let lift = depth(base) + lp.gap.unwrap_or(2.0 * thickest);
    let patches: Vec<Fabric> = lp
        .patches
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let mut f = base.clone();
            place(
                &mut f,
                &Placement {
                    translate: Vec3::from(p.translate) + Vec3::z() * (k as f64 * lift),
                    rotate_deg: Vec3::from(p.rotate_deg),
                },
            );
            f
        })
        .collect();
    let (mut fabric, node_maps) = stack_layers_mapped(&patches, 0.0)?;
    // Seam points are chosen on the unplaced fabric: its own edges.
    let (lo, hi) = base.nodes.iter().fold(
        (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
        |(lo, hi), n| (lo.inf(&n.x), hi.sup(&n.x)),
    );
    let n_yarns = base.yarns.len();
    let mut seam_contacts = 0;
    for seam in &lp.seams {
        let near_edge = |x: &Vec3| {
            seam.edges.iter().any(|e| match e {
                Edge::Left => x.x - lo.x < seam.margin,
                Edge::Right => hi.x - x.x < seam.margin,
                Edge::Bottom => x.y - lo.y < seam.margin,
                Edge::Top => hi.y - x.y < seam.margin,
            })
        };
        // Where material point `u` of a yarn of `top` lies on the unplaced
        // fabric: a copy keeps its yarns' `u`, whatever points were inserted.
        let along = |yarn: usize, u: f64| {
            let Some(y) = yarn.checked_sub(seam.top * n_yarns).and_then(|y| base.yarns.get(y)) else {
                return false;
            };
            let k = y.points.partition_point(|p| p.u <= u);
            let (Some(p0), Some(p1)) = (k.checked_sub(1).and_then(|k| y.points.get(k)), y.points.get(k)) else {
                return false;
            };
            let s = (u - p0.u) / (p1.u - p0.u);
            near_edge(&base.nodes[p0.node].x.lerp(&base.nodes[p1.node].x, s))
        };
        seam_contacts += sew(&mut fabric, (seam.top, seam.bottom), lp.reach, &along)?;
    }
    // After the seams, so that they get the crossings they ask for.
    let layer_contacts = join_layers(&mut fabric, lp.reach)?;
    Ok(Layered {
        fabric,
        node_maps,
        layer_contacts,
        seam_contacts,
    })
}
