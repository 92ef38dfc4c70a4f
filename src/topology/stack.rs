//! Stacking fabrics into layers: one [`Fabric`] holding several patches
//! one above the other in `z`, for scenes where fabrics lie on each other
//! (a two-layer stack, a folded hem, a garment's front over its back).
//!
//! Why no persistent contacts between the layers: an EoL contact is a
//! crossing the *pattern* creates (a loop through its parent, a float over
//! a leg) and stays for the whole run, with one shared node. Layers that
//! merely touch have no such crossing: where and whether they touch is the
//! outcome of the simulation, and they may slide apart again. That is
//! non-persistent contact, the thickness barrier's job (`src/contact`,
//! docs/CONTACT.md), so the stack only places the layers and adds no
//! [`ContactKind::Layer`](super::ContactKind) node.
//!
//! Layer `k` is moved by `k * spacing` along `z` (the fabric's depth axis;
//! `z` up when gravity points down `-z`, so layer 0 is the bottom). The
//! spacing is between the layers' reference frames, not between their
//! surfaces: a compiled fabric has a depth of its own (legs and heads pass
//! in front of and behind each other), so a caller that wants a given
//! clearance adds it to [`depth`] plus one yarn diameter.

use super::error::TopologyError;
use super::fabric::{Fabric, Node, PointRef, Vec3};

/// Extent of a fabric's centrelines along `z` (`max z - min z` over its
/// nodes); 0 for a fabric without nodes.
pub fn depth(f: &Fabric) -> f64 {
    let (lo, hi) = z_range(f);
    if f.nodes.is_empty() {
        0.0
    } else {
        hi - lo
    }
}

/// Smallest and largest node `z` (infinite for a fabric without nodes).
pub fn z_range(f: &Fabric) -> (f64, f64) {
    f.nodes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), n| {
        (lo.min(n.x.z), hi.max(n.x.z))
    })
}

/// The layers as one fabric: yarns and contacts of layer `k` follow those
/// of layer `k - 1`, every index shifted by the counts before it, every
/// yarn of layer `k` tagged `layer = k`, and every node of layer `k` moved
/// by `k * spacing` in `z`. Pins, EIL flags and a
/// simulation's `u` are kept as they are.
///
/// Node order: the contact nodes of all layers first, in contact order,
/// then every other node, layer by layer: the numbering a compiled fabric
/// has (contact `k` at node `k`), kept so a stack reads like one fabric.
///
/// `meta`: the yarn specs of all layers, in layer order (each yarn's `spec`
/// shifted accordingly, so a layer keeps its colours and radii); gauge,
/// construction and looseness of the bottom layer, which a stack has only
/// one of; the largest width and height; the names joined by `" / "`.
/// `sim` is dropped: the stack is a new starting state.
pub fn stack_layers(layers: &[Fabric], spacing: f64) -> Result<Fabric, TopologyError> {
    stack_layers_mapped(layers, spacing).map(|(f, _)| f)
}

/// [`stack_layers`], with where each layer's nodes went: `maps[k][i]` is
/// the stack's index of layer `k`'s node `i`.
pub fn stack_layers_mapped(layers: &[Fabric], spacing: f64) -> Result<(Fabric, Vec<Vec<usize>>), TopologyError> {
    let Some(first) = layers.first() else {
        return Err(TopologyError::BadOption {
            name: "layers",
            value: 0.0,
            why: "a stack needs at least one layer",
        });
    };
    if !spacing.is_finite() {
        return Err(TopologyError::BadOption {
            name: "spacing",
            value: spacing,
            why: "the layer spacing must be finite",
        });
    }
    let n_contacts: usize = layers.iter().map(|l| l.contacts.len()).sum();
    let n_nodes: usize = layers.iter().map(|l| l.nodes.len()).sum();
    let mut out = Fabric {
        meta: first.meta.clone(),
        nodes: vec![
            Node {
                x: Vec3::zeros(),
                pinned: false,
            };
            n_nodes
        ],
        yarns: Vec::new(),
        contacts: Vec::with_capacity(n_contacts),
        sim: None,
    };
    out.meta.yarns.clear();
    let mut names = Vec::with_capacity(layers.len());
    let mut maps = Vec::with_capacity(layers.len());
    // Next free slot for a contact node and for any other node.
    let (mut next_contact, mut next_other) = (0, n_contacts);
    for (k, layer) in layers.iter().enumerate() {
        let (yarn0, spec0) = (out.yarns.len(), out.meta.yarns.len());
        let mut remap = vec![usize::MAX; layer.nodes.len()];
        for c in &layer.contacts {
            match remap.get_mut(c.node) {
                Some(slot) if *slot == usize::MAX => {
                    *slot = next_contact;
                    next_contact += 1;
                }
                _ => {
                    return Err(TopologyError::Internal(format!(
                        "layer {k}: contact node {} is out of range or shared by two contacts",
                        c.node
                    )))
                }
            }
        }
        for slot in remap.iter_mut().filter(|s| **s == usize::MAX) {
            *slot = next_other;
            next_other += 1;
        }
        let dz = k as f64 * spacing;
        for (i, n) in layer.nodes.iter().enumerate() {
            let mut n = n.clone();
            n.x.z += dz;
            out.nodes[remap[i]] = n;
        }
        // The layer's yarns and contacts, pointed at the merged nodes.
        let mut moved = Fabric {
            meta: layer.meta.clone(),
            nodes: Vec::new(),
            yarns: layer.yarns.clone(),
            contacts: layer.contacts.clone(),
            sim: None,
        };
        moved.remap_node_refs(&remap);
        maps.push(remap);
        out.yarns.extend(moved.yarns.into_iter().map(|mut y| {
            y.spec += spec0;
            y.layer = k;
            y
        }));
        let shift = |p: PointRef| PointRef {
            yarn: p.yarn + yarn0,
            point: p.point,
        };
        out.contacts.extend(moved.contacts.into_iter().map(|mut c| {
            c.front = shift(c.front);
            c.back = shift(c.back);
            c
        }));
        out.meta.yarns.extend(layer.meta.yarns.iter().cloned());
        out.meta.width = out.meta.width.max(layer.meta.width);
        out.meta.height = out.meta.height.max(layer.meta.height);
        names.push(layer.meta.name.as_str());
    }
    out.meta.name = names.join(" / ");
    Ok((out, maps))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology::sample::{chart_pattern, tile};
    use crate::topology::{compile, CompileOptions, ContactKind};

    fn patch(chart: &[&str], w: usize, h: usize) -> Fabric {
        let rows = tile(chart, w, h);
        let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
        let p = chart_pattern(&rows, None, crate::pattern::Construction::Flat).expect("chart");
        compile(&p, &CompileOptions::default()).expect("compile")
    }

    #[test]
    fn counts_add_up_indices_stay_valid_and_layers_move_up() {
        let a = patch(&["k"], 4, 4);
        let mut b = patch(&["vk", "kv"], 4, 4);
        b.meta.name = "linen".into();
        let spacing = 2.0 * depth(&a).max(depth(&b)) + 1e-3;
        let layers = [a.clone(), b.clone(), a.clone()];
        let s = stack_layers(&layers, spacing).expect("stack");

        assert_eq!(s.nodes.len(), 2 * a.nodes.len() + b.nodes.len());
        assert_eq!(s.yarns.len(), 2 * a.yarns.len() + b.yarns.len());
        assert_eq!(s.contacts.len(), 2 * a.contacts.len() + b.contacts.len());
        assert_eq!(s.meta.yarns.len(), 2 * a.meta.yarns.len() + b.meta.yarns.len());
        assert_eq!(s.meta.name, format!("{} / linen / {}", a.meta.name, a.meta.name));
        assert!(s.contacts.iter().all(|c| c.kind != ContactKind::Layer));

        // Every node is used, contact k sits on node k (as compiled), and
        // each contact's two points and partner stay on their node.
        let mut used = vec![0; s.nodes.len()];
        for y in &s.yarns {
            assert!(y.spec < s.meta.yarns.len());
            for p in &y.points {
                used[p.node] += 1;
            }
        }
        assert!(used.iter().all(|&n| n > 0));
        for (k, c) in s.contacts.iter().enumerate() {
            assert_eq!(c.node, k);
            assert_eq!(used[k], 2);
            for p in [c.front, c.back] {
                assert_eq!(s.yarns[p.yarn].points[p.point].node, c.node);
            }
            if let Some(n) = c.partner {
                assert_eq!(s.contacts[n].partner, Some(k));
            }
        }

        // Layer k's yarns trace layer k's positions, moved up by k * spacing.
        let (mut yarn0, mut spec0) = (0, 0);
        for (k, layer) in layers.iter().enumerate() {
            for (yi, y) in layer.yarns.iter().enumerate() {
                let stacked = &s.yarns[yarn0 + yi];
                assert_eq!(stacked.spec, y.spec + spec0);
                for (p, q) in y.points.iter().zip(&stacked.points) {
                    let (from, to) = (layer.nodes[p.node].x, s.nodes[q.node].x);
                    assert_eq!((to.x, to.y, q.u), (from.x, from.y, p.u));
                    assert!((to.z - from.z - k as f64 * spacing).abs() < 1e-15);
                }
            }
            yarn0 += layer.yarns.len();
            spec0 += layer.meta.yarns.len();
        }
        // With that spacing the layers do not overlap in z.
        assert!(z_range(&b).0 + spacing > z_range(&a).1);
    }

    #[test]
    fn no_layers_or_bad_spacing_is_an_error() {
        assert!(stack_layers(&[], 1e-3).is_err());
        assert!(stack_layers(&[patch(&["k"], 2, 2)], f64::NAN).is_err());
        let one = patch(&["k"], 2, 2);
        assert_eq!(
            stack_layers(std::slice::from_ref(&one), 5.0).expect("one layer").nodes,
            one.nodes
        );
    }
}
