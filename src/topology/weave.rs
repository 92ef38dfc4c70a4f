//! A plain weave: warp yarns along `y` and weft yarns along `x` crossing
//! at persistent EoL contacts, over and under in a checkerboard, as the
//! tablecloths of *Robust Eulerian-on-Lagrangian Rods* (Figs. 1 and 7:
//! thick-yarn plain weaves). For scenes that stack cloths: a knit's loops
//! stand out of its surface, a weave lies flat, so weave layers can touch
//! across their whole area.
//!
//! As for a knit, both yarns of a crossing share its node (thickness is
//! added when rendering), so the cloth lies in the plane `z = 0`, centred
//! on the origin. A crossing is a [`ContactKind::Float`]: a yarn lying on
//! another, whose front yarn alternates like the weave's over and under.
//! Every `u` is free except at the yarn ends, which run `tail` past the
//! outermost crossings.

use super::error::TopologyError;
use super::fabric::{Contact, ContactKind, Fabric, Node, PointRef, Vec3, Yarn, YarnPoint};
use crate::pattern::{Construction, Gauge, Meta, YarnSpec};

/// The weave's size and yarn.
#[derive(Clone, Debug, PartialEq)]
pub struct WeaveOptions {
    /// Yarns along `x` (wefts) and along `y` (warps).
    pub wefts: usize,
    pub warps: usize,
    /// Distance between neighbouring yarns (m).
    pub pitch: f64,
    /// Yarn radius (m).
    pub radius: f64,
    /// Free yarn past the outermost crossing at each end (m).
    pub tail: f64,
    pub color: [u8; 3],
}

impl Default for WeaveOptions {
    /// The seed paper's tablecloth yarn: 5.6 mm apart, radius 2.25 mm.
    fn default() -> Self {
        WeaveOptions {
            wefts: 16,
            warps: 16,
            pitch: 5.6e-3,
            radius: 2.25e-3,
            tail: 2.8e-3,
            color: [60, 140, 80],
        }
    }
}

/// The plain weave of `o` (module docs).
pub fn plain_weave(o: &WeaveOptions) -> Result<Fabric, TopologyError> {
    for (name, v) in [("pitch", o.pitch), ("radius", o.radius), ("tail", o.tail)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(TopologyError::BadOption {
                name,
                value: v,
                why: "a weave's pitch, radius and tail must be positive and finite",
            });
        }
    }
    if o.wefts == 0 || o.warps == 0 {
        return Err(TopologyError::Empty {
            width: o.warps,
            rows: o.wefts,
        });
    }
    let per_10cm = 0.1 / o.pitch;
    let mut f = Fabric {
        meta: Meta {
            name: format!("plain weave {} x {}", o.warps, o.wefts),
            gauge: Gauge {
                stitches_per_10cm: per_10cm,
                rows_per_10cm: per_10cm,
            },
            yarns: vec![YarnSpec {
                name: "cloth".into(),
                color: o.color,
                radius: o.radius,
                material: None,
            }],
            construction: Construction::Flat,
            width: o.warps,
            height: o.wefts,
            looseness: 1.0,
        },
        nodes: Vec::new(),
        yarns: Vec::new(),
        contacts: Vec::new(),
        sim: None,
    };
    // Crossing (i, j) of warp i and weft j sits at node i * wefts + j.
    let at = |k: usize, n: usize| (k as f64 - (n - 1) as f64 / 2.0) * o.pitch;
    for i in 0..o.warps {
        for j in 0..o.wefts {
            f.nodes.push(Node {
                x: Vec3::new(at(i, o.warps), at(j, o.wefts), 0.0),
                pinned: false,
            });
        }
    }
    let crossing = |i: usize, j: usize| i * o.wefts + j;
    let wefts: Vec<usize> = (0..o.wefts)
        .map(|j| {
            let nodes: Vec<usize> = (0..o.warps).map(|i| crossing(i, j)).collect();
            add_yarn(&mut f, &nodes, Vec3::x(), o.tail)
        })
        .collect();
    for i in 0..o.warps {
        let nodes: Vec<usize> = (0..o.wefts).map(|j| crossing(i, j)).collect();
        let warp = add_yarn(&mut f, &nodes, Vec3::y(), o.tail);
        for (j, &weft) in wefts.iter().enumerate() {
            let (weft_point, warp_point) = (
                PointRef {
                    yarn: weft,
                    point: 1 + i,
                },
                PointRef {
                    yarn: warp,
                    point: 1 + j,
                },
            );
            let (front, back) = if (i + j) % 2 == 0 {
                (weft_point, warp_point)
            } else {
                (warp_point, weft_point)
            };
            f.contacts.push(Contact {
                node: crossing(i, j),
                front,
                back,
                kind: ContactKind::Float,
                partner: None,
            });
        }
    }
    Ok(f)
}

/// A straight yarn through `crossings` (in order along `dir`), with a
/// fixed-`u` end `tail` beyond each outermost crossing.
fn add_yarn(f: &mut Fabric, crossings: &[usize], dir: Vec3, tail: f64) -> usize {
    let first = f.nodes[crossings[0]].x - dir * tail;
    let last = f.nodes[crossings[crossings.len() - 1]].x + dir * tail;
    let mut nodes = vec![f.nodes.len()];
    f.nodes.push(Node {
        x: first,
        pinned: false,
    });
    nodes.extend_from_slice(crossings);
    nodes.push(f.nodes.len());
    f.nodes.push(Node { x: last, pinned: false });
    let mut u = 0.0;
    let mut points = Vec::with_capacity(nodes.len());
    for (k, &n) in nodes.iter().enumerate() {
        if k > 0 {
            u += (f.nodes[n].x - f.nodes[nodes[k - 1]].x).norm();
        }
        points.push(YarnPoint {
            node: n,
            u,
            fixed_u: k == 0 || k + 1 == nodes.len(),
            eil: false,
        });
    }
    f.yarns.push(Yarn {
        layer: 0,
        spec: 0,
        rest_length: u,
        points,
    });
    f.yarns.len() - 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_weave_crosses_every_warp_with_every_weft_over_and_under_in_turn() {
        let o = WeaveOptions {
            wefts: 3,
            warps: 4,
            ..WeaveOptions::default()
        };
        let f = plain_weave(&o).expect("weave");
        assert_eq!(f.contacts.len(), 12);
        assert_eq!(f.yarns.len(), 7);
        for c in &f.contacts {
            let (fp, bp) = (
                &f.yarns[c.front.yarn].points[c.front.point],
                &f.yarns[c.back.yarn].points[c.back.point],
            );
            assert_eq!((fp.node, bp.node), (c.node, c.node));
            assert!(!fp.fixed_u && !bp.fixed_u);
        }
        // Along a weft, the front yarn alternates.
        let weft0: Vec<bool> = f
            .contacts
            .iter()
            .filter(|c| c.node % 3 == 0)
            .map(|c| c.front.yarn == 0)
            .collect();
        assert!(weft0.windows(2).all(|w| w[0] != w[1]), "{weft0:?}");
        for y in &f.yarns {
            assert!(y
                .points
                .windows(2)
                .all(|w| (w[1].u - w[0].u - o.pitch).abs() < 1e-12 || w[1].u > w[0].u));
            assert!((y.rest_length - y.points.last().unwrap().u).abs() < 1e-15);
        }
        let bad = WeaveOptions {
            pitch: f64::NAN,
            ..WeaveOptions::default()
        };
        assert!(plain_weave(&bad).is_err());
    }
}
