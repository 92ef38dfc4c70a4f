//! The yarn-level model: yarns as sorted lists of `(u, x)` points over shared
//! spatial nodes, and the persistent EoL contacts between them.
//!
//! Why nodes and yarn points are separate: an EoL contact is *one* spatial
//! position `x` seen by *two* yarns, each with its own material coordinate
//! (docs/MODEL.md, "Kinematics": one position and two sliding coordinates). So a [`Node`]
//! holds `x`, and each yarn keeps a list of [`YarnPoint`]s `(node, u)`. A
//! Lagrangian node is referenced by one yarn point, a contact node by two.
//!
//! The same type is the simulation state: the compiler writes the initial
//! geometry and the relaxer overwrites `x`, `u` and the EIL flags. So every
//! exporter takes a `&Fabric`, whatever produced it.

use crate::pattern::Meta;
use serde::{Deserialize, Serialize};

pub type Vec3 = nalgebra::Vector3<f64>;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fabric {
    pub meta: Meta,
    pub nodes: Vec<Node>,
    pub yarns: Vec<Yarn>,
    pub contacts: Vec<Contact>,
    /// Set once a simulation has written this state.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sim: Option<SimInfo>,
}

/// A spatial point. Contact nodes are shared by two yarn points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub x: Vec3,
    /// Position prescribed (pinned) by a scene.
    #[serde(default, skip_serializing_if = "is_false")]
    pub pinned: bool,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Yarn {
    /// Which layer of a stacked scene the yarn belongs to (0, the bottom,
    /// for a single fabric; `topology::stack`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub layer: usize,
    /// Index into `meta.yarns` (colour, radius, material).
    pub spec: usize,
    /// Rest length `L`; every point has `u` in `[0, L]`.
    pub rest_length: f64,
    /// Sorted by `u` (strictly increasing in a compiled fabric).
    pub points: Vec<YarnPoint>,
}

/// One node as seen along one yarn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct YarnPoint {
    pub node: usize,
    /// Material (Eulerian) coordinate: rest arc length from the yarn start.
    pub u: f64,
    /// `u` is not a degree of freedom: yarn ends and resolution nodes.
    pub fixed_u: bool,
    /// This point is currently EIL: its `x` is interpolated from its
    /// non-EIL neighbours on this yarn (docs/MODEL.md, "Kinematics").
    #[serde(default, skip_serializing_if = "is_false")]
    pub eil: bool,
}

/// Address of a yarn point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PointRef {
    pub yarn: usize,
    pub point: usize,
}

/// A persistent EoL contact: two yarn points sharing `node`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    pub node: usize,
    /// The yarn point lying on the RS side at this crossing (front).
    pub front: PointRef,
    /// The yarn point lying on the WS side at this crossing (back).
    pub back: PointRef,
    pub kind: ContactKind,
    /// The other node of the same stitch contact (the two ends of the arc
    /// where a head wraps a leg); the wrapping energy acts on this pair.
    pub partner: Option<usize>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ContactKind {
    /// A loop leg passing through its parent's head (knit or purl stitch).
    Stitch,
    /// A float (slip stitch, or a jacquard strand) crossing a loop leg.
    Float,
    /// A tuck loop crossing the legs of the loop it sits on.
    Tuck,
    /// Between two layers of fabric (stacked scenes): slides, and may
    /// separate (`topology::layers`).
    Layer,
    /// A sewing stitch joining two layers: fixed `u` on both yarns, never
    /// removed (`topology::layers::sew`).
    Seam,
}

/// What a node is, as the exporters colour it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum NodeKind {
    Lagrangian = 0,
    Eol = 1,
    Eil = 2,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SimInfo {
    pub time: f64,
    pub newton_iterations: usize,
    pub residual: f64,
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_zero(v: &usize) -> bool {
    *v == 0
}

impl Fabric {
    /// Points every yarn point, contact node and partner at `remap[old]`.
    /// The callers that drop or merge nodes (`topology::thin`,
    /// `topology::stack`) build the map and move the nodes themselves.
    pub(crate) fn remap_node_refs(&mut self, remap: &[usize]) {
        for p in self.yarns.iter_mut().flat_map(|y| &mut y.points) {
            p.node = remap[p.node];
        }
        for c in &mut self.contacts {
            c.node = remap[c.node];
            c.partner = c.partner.map(|n| remap[n]);
        }
    }

    /// The point's spatial position: the node's `x`, or for an EIL point the
    /// interpolation between its non-EIL neighbours on the yarn.
    pub fn point_position(&self, p: PointRef) -> Vec3 {
        let yarn = &self.yarns[p.yarn];
        let pt = &yarn.points[p.point];
        if !pt.eil {
            return self.nodes[pt.node].x;
        }
        let prev = yarn.points[..p.point].iter().rev().find(|q| !q.eil);
        let next = yarn.points[p.point + 1..].iter().find(|q| !q.eil);
        match (prev, next) {
            (Some(a), Some(b)) if b.u > a.u => {
                let s = (pt.u - a.u) / (b.u - a.u);
                self.nodes[a.node].x * (1.0 - s) + self.nodes[b.node].x * s
            }
            (Some(a), _) => self.nodes[a.node].x,
            (_, Some(b)) => self.nodes[b.node].x,
            _ => self.nodes[pt.node].x,
        }
    }

    /// Kind of a yarn point, for export.
    pub fn point_kind(&self, p: PointRef) -> NodeKind {
        let pt = &self.yarns[p.yarn].points[p.point];
        if pt.eil {
            NodeKind::Eil
        } else if self.node_refcounts()[pt.node] > 1 {
            NodeKind::Eol
        } else {
            NodeKind::Lagrangian
        }
    }

    /// How many yarn points reference each node (1 = Lagrangian, 2 = contact).
    pub fn node_refcounts(&self) -> Vec<u8> {
        let mut c = vec![0u8; self.nodes.len()];
        for y in &self.yarns {
            for p in &y.points {
                c[p.node] = c[p.node].saturating_add(1);
            }
        }
        c
    }

    /// Centre line of every yarn with per-point kind and `u`: the view the
    /// exporters draw. Kinds are computed once for the whole fabric.
    pub fn curves(&self) -> Vec<YarnCurve> {
        let refs = self.node_refcounts();
        self.yarns
            .iter()
            .enumerate()
            .map(|(yi, y)| YarnCurve {
                yarn: yi,
                spec: y.spec,
                points: (0..y.points.len())
                    .map(|pi| {
                        let pt = &y.points[pi];
                        let kind = if pt.eil {
                            NodeKind::Eil
                        } else if refs[pt.node] > 1 {
                            NodeKind::Eol
                        } else {
                            NodeKind::Lagrangian
                        };
                        CurvePoint {
                            x: self.point_position(PointRef { yarn: yi, point: pi }),
                            u: pt.u,
                            kind,
                        }
                    })
                    .collect(),
            })
            .collect()
    }
}

/// One yarn's centre line, ready to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct YarnCurve {
    pub yarn: usize,
    pub spec: usize,
    pub points: Vec<CurvePoint>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    pub x: Vec3,
    pub u: f64,
    pub kind: NodeKind,
}
