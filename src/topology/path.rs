//! Yarn paths under construction: node references plus, per segment, the
//! stitch element that owns it (so rest lengths can be handed out per loop
//! and per float), and the contact table that pairs the two yarn points of
//! every contact node.

use super::error::TopologyError;
use super::fabric::{Contact, ContactKind, Node, PointRef, Vec3};

/// Which element a segment belongs to, for the rest-length budget.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Owner {
    /// A loop: everything from its left sinker to its right sinker.
    Loop(usize),
    /// A float cell: the float over one column, with the climbs from the
    /// sinkers next to it.
    Float(usize),
    /// Edge turns, carried strands: no stitch owns them.
    Connector,
}

/// Side of a contact a yarn point lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Front,
    Back,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    pub node: usize,
    pub contact: Option<(usize, Role)>,
    pub fixed_u: bool,
    /// The point lies on its loop's head (the arc through its child's
    /// legs); a segment between two head points of one loop is head yarn
    /// (`rest_length::segment_weights`).
    pub head: bool,
}

impl PathPoint {
    /// This point, marked as lying on its loop's head.
    pub fn on_head(self) -> Self {
        PathPoint { head: true, ..self }
    }
}

/// A polyline over nodes; `owners[i]` owns the segment from point `i` to `i+1`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Path {
    pub points: Vec<PathPoint>,
    pub owners: Vec<Owner>,
}

impl Path {
    /// Appends a point; `owner` owns the segment that reaches it (ignored
    /// for the first point).
    pub fn push(&mut self, p: PathPoint, owner: Owner) {
        if !self.points.is_empty() {
            self.owners.push(owner);
        }
        self.points.push(p);
    }
    pub fn append(&mut self, other: Path, joint: Owner) {
        let mut owners = other.owners.into_iter();
        for (i, p) in other.points.into_iter().enumerate() {
            let owner = if i == 0 { joint } else { owners.next().unwrap_or(joint) };
            self.push(p, owner);
        }
    }
    pub fn reverse(&mut self) {
        self.points.reverse();
        self.owners.reverse();
    }
    pub fn last(&self) -> Option<&PathPoint> {
        self.points.last()
    }
}

/// Nodes and contacts as they are created.
#[derive(Debug, Default)]
pub struct NodeStore {
    pub nodes: Vec<Node>,
    pub contacts: Vec<PendingContact>,
}

#[derive(Clone, Debug)]
pub struct PendingContact {
    pub node: usize,
    pub kind: ContactKind,
    pub partner: Option<usize>,
    pub front: Option<PointRef>,
    pub back: Option<PointRef>,
}

impl NodeStore {
    pub fn node(&mut self, x: Vec3) -> usize {
        self.nodes.push(Node { x, pinned: false });
        self.nodes.len() - 1
    }
    /// A free (Lagrangian) point at `x`.
    pub fn free(&mut self, x: Vec3) -> PathPoint {
        PathPoint {
            node: self.node(x),
            contact: None,
            fixed_u: true,
            head: false,
        }
    }
    /// A new contact node at `x`; returns the contact id.
    pub fn contact(&mut self, x: Vec3, kind: ContactKind) -> usize {
        let node = self.node(x);
        self.contacts.push(PendingContact {
            node,
            kind,
            partner: None,
            front: None,
            back: None,
        });
        self.contacts.len() - 1
    }
    /// Links the two nodes of one stitch contact (the ends of a wrap).
    pub fn pair(&mut self, a: usize, b: usize) {
        let (na, nb) = (self.contacts[a].node, self.contacts[b].node);
        self.contacts[a].partner = Some(nb);
        self.contacts[b].partner = Some(na);
    }
    /// The path point through contact `id` for a yarn on side `role`.
    pub fn at(&self, id: usize, role: Role) -> PathPoint {
        PathPoint {
            node: self.contacts[id].node,
            contact: Some((id, role)),
            fixed_u: false,
            head: false,
        }
    }
    pub fn position(&self, p: &PathPoint) -> Vec3 {
        self.nodes[p.node].x
    }
    /// Records that yarn point `at` passes through contact `id` on `role`.
    pub fn visit(&mut self, id: usize, role: Role, at: PointRef) -> Result<(), TopologyError> {
        let c = &mut self.contacts[id];
        let slot = match role {
            Role::Front => &mut c.front,
            Role::Back => &mut c.back,
        };
        if slot.is_some() {
            return Err(TopologyError::Internal(format!(
                "contact {id} visited twice on the {role:?} side"
            )));
        }
        *slot = Some(at);
        Ok(())
    }
    pub fn finish_contacts(&self) -> Result<Vec<Contact>, TopologyError> {
        self.contacts
            .iter()
            .enumerate()
            .map(|(id, c)| match (c.front, c.back) {
                (Some(front), Some(back)) => Ok(Contact {
                    node: c.node,
                    front,
                    back,
                    kind: c.kind,
                    partner: c.partner,
                }),
                _ => Err(TopologyError::Internal(format!(
                    "contact {id} ({:?}) is not reached by two yarns",
                    c.kind
                ))),
            })
            .collect()
    }
}
