//! Starting positions: every loop, float and contact node in the flat layout.
//!
//! Stitch and tuck contact nodes lie on the mid-plane `z = 0`: in the
//! centre-line model the two yarns of a contact share one point, and which
//! yarn is in front is carried by where their neighbouring points go
//! (`±leg_z`), not by the node itself. Float contacts lie at the float's
//! depth instead: a float stays straight (as a strand under tension does)
//! and the crossed leg bends out to meet it. Diving floats were tried
//! first; two colours changing places at a column boundary then pass each
//! other at under half a diameter, whatever the layer spacing.
//!
//! One loop, drawn left to right (its legs `a = w/4` either side of the
//! column centre; a tuck has the same outline as the loop it is laid on,
//! `tuck_depth` behind it, head nodes included):
//! - **foot**: from the left sinker (below the row's interlock, `z = ∓leg_z`)
//!   through the heads of its parents. Each head is wrapped over a short
//!   diagonal `A -> B` (outer-low to inner-high, `wrap_step` in x and y):
//!   the head comes up from its own leg and leaves to its apex, the child
//!   comes in from its sinker and leaves up its leg, so the two yarns share
//!   the segment `A B` and swap sides along it (docs/MODEL.md, "Stitch contact
//!   layout": a stitch contact is the two ends of that wrap);
//! - **legs**: one point per row spanned at mid-row on the loop's side
//!   (`+leg_z` knit, `-leg_z` purl and tuck); where floats cross, the crossing
//!   nodes replace it and the leg bends away from the float just above and
//!   below;
//! - **head**: through its child's `A B` pairs and over an apex
//!   `apex_rise` above the interlock, behind the child for a knit child, in
//!   front for a purl child; open heads (last row) just turn.
//!
//! A float runs straight at mid-row (a second float over the same column
//! `float_spread` lower), `float_z` in front or behind, each yarn in its own
//! depth layer (`float_layer` apart). How loops and floats are strung into a
//! pass, sinkers, drops and the tube's seam, is in [`super::passes`].
//!
//! The clearances these lengths give were derived for the worst pairs
//! (neighbouring legs `w/2 - wrap_step` apart; a back float passing the apex
//! of the head below, separated by `h/2 - apex_rise` in y and
//! `float_z - leg_z` in z; stacked tuck heads `tuck_depth` apart) and are
//! checked by `clearance` on every structure in the tests.

use super::fabric::{ContactKind, Vec3};
use super::knit_graph::{Cell, FloatKind, FloatSide, KnitGraph, LoopId, LoopKind};
use super::layout::Layout;
use super::path::{NodeStore, PathPoint, Role};

/// A contact node on one leg of a loop.
#[derive(Clone, Copy, Debug)]
struct LegEvent {
    y: f64,
    band: usize,
    contact: usize,
    role: Role,
    /// For float crossings: the float's side (+1 front, -1 back).
    float_side: Option<f64>,
}

#[derive(Clone, Debug)]
pub(super) struct FloatCell {
    pub(super) id: usize,
    pub(super) y: f64,
    pub(super) z: f64,
    /// (x, contact, role of the float) sorted by x.
    pub(super) crossings: Vec<(f64, usize, Role)>,
}

/// Which side of its loop a leg is on.
const LEFT: usize = 0;
const RIGHT: usize = 1;

pub struct Geometry<'a> {
    pub(super) g: &'a KnitGraph,
    pub(super) lay: &'a Layout,
    pub store: NodeStore,
    /// `interlocks[child][j]`: contacts `[A_left, B_left, B_right, A_right]`
    /// with the child's `j`-th parent.
    interlocks: Vec<Vec<[usize; 4]>>,
    legs: Vec<[Vec<LegEvent>; 2]>,
    tucks: Vec<Option<[usize; 2]>>,
    pub(super) floats: Vec<Vec<Option<FloatCell>>>,
    /// Kind of each float cell, by id.
    pub float_kinds: Vec<FloatKind>,
    /// Float depth layer of each yarn spec: a yarn keeps its layer in every
    /// row, so one colour's row end and the next colour's row start (which
    /// meet on a tube's seam) are never at the same depth.
    pub spec_layer: Vec<usize>,
}

/// z sign of a loop's legs: knit legs on the RS, purl legs and tucks behind.
fn leg_sign(kind: LoopKind) -> f64 {
    match kind {
        LoopKind::Knit | LoopKind::CastOn => 1.0,
        LoopKind::Purl | LoopKind::Tuck => -1.0,
    }
}

/// z sign of the sinkers next to a loop (a tuck's yarn stays behind).
pub(super) fn sinker_sign(kind: LoopKind) -> f64 {
    match kind {
        LoopKind::Purl => 1.0,
        _ => -1.0,
    }
}

/// The child is the front yarn of a knit interlock, the parent of a purl one.
fn child_role(child: LoopKind) -> Role {
    match child {
        LoopKind::Purl => Role::Back,
        _ => Role::Front,
    }
}

fn other(r: Role) -> Role {
    match r {
        Role::Front => Role::Back,
        Role::Back => Role::Front,
    }
}

impl<'a> Geometry<'a> {
    /// Creates every contact node of the fabric.
    pub fn new(g: &'a KnitGraph, lay: &'a Layout) -> Self {
        let n = g.loops.len();
        let mut geo = Self {
            g,
            lay,
            store: NodeStore::default(),
            interlocks: vec![Vec::new(); n],
            legs: vec![[Vec::new(), Vec::new()]; n],
            tucks: vec![None; n],
            floats: Vec::with_capacity(g.passes.len()),
            float_kinds: Vec::new(),
            spec_layer: Vec::new(),
        };
        let mut specs: Vec<usize> = g.passes.iter().map(|p| p.spec).collect();
        specs.sort_unstable();
        specs.dedup();
        let n_specs = specs.last().map_or(0, |&s| s + 1);
        geo.spec_layer = vec![0; n_specs];
        for (layer, &s) in specs.iter().enumerate() {
            geo.spec_layer[s] = layer;
        }
        geo.make_interlocks();
        geo.make_tucks();
        geo.make_floats();
        geo
    }

    fn make_interlocks(&mut self) {
        let half = 0.5 * self.lay.wrap_step;
        for (child, l) in self.g.loops.iter().enumerate() {
            let yb = self.lay.y_interlock(l.row);
            for &parent in &l.parents {
                let p = &self.g.loops[parent];
                let x = self.lay.x_center(p.col);
                let a = self.lay.leg_offset();
                let z = -self.lay.slot_depth(p.slot);
                let mut at = |dx: f64, dy: f64| self.store.contact(Vec3::new(x + dx, yb + dy, z), ContactKind::Stitch);
                let ids = [
                    at(-a - half, -half),
                    at(-a + half, half),
                    at(a - half, half),
                    at(a + half, -half),
                ];
                self.store.pair(ids[0], ids[1]);
                self.store.pair(ids[3], ids[2]);
                self.interlocks[child].push(ids);
            }
        }
    }

    fn make_tucks(&mut self) {
        for (id, t) in self.g.loops.iter().enumerate() {
            let Some(held) = t.tucked_on else { continue };
            let p = &self.g.loops[held];
            let x = self.lay.x_center(p.col);
            let a = self.lay.leg_offset();
            let y = self.lay.y_interlock(t.row);
            let mut ids = [0; 2];
            for (side, sign) in [(LEFT, -1.0), (RIGHT, 1.0)] {
                let c = self.store.contact(Vec3::new(x + sign * a, y, 0.0), ContactKind::Tuck);
                ids[side] = c;
                self.legs[held][side].push(LegEvent {
                    y,
                    band: t.row,
                    contact: c,
                    role: Role::Front,
                    float_side: None,
                });
            }
            self.tucks[id] = Some(ids);
        }
    }

    /// Rank of each float among the floats of its row at its column: floats
    /// sharing a column cross the same legs, so later ones cross lower.
    fn float_ranks(&self) -> Vec<Vec<usize>> {
        let mut taken: std::collections::HashMap<(usize, usize), usize> = std::collections::HashMap::new();
        self.g
            .passes
            .iter()
            .map(|pass| {
                (0..pass.cells.len())
                    .map(|col| {
                        let n = taken.entry((pass.row, col)).or_insert(0);
                        let rank = *n;
                        if matches!(pass.cells[col], Cell::Float { .. }) {
                            *n += 1;
                        }
                        rank
                    })
                    .collect()
            })
            .collect()
    }

    fn make_floats(&mut self) {
        let ranks = self.float_ranks();
        for (pi, pass) in self.g.passes.iter().enumerate() {
            let mut row_cells = Vec::with_capacity(pass.cells.len());
            for cell in &pass.cells {
                let Cell::Float {
                    col,
                    side,
                    kind,
                    crosses,
                } = cell
                else {
                    row_cells.push(None);
                    continue;
                };
                let sign = match side {
                    FloatSide::Front => 1.0,
                    FloatSide::Back => -1.0,
                };
                let float_role = if sign > 0.0 { Role::Front } else { Role::Back };
                let y = self.lay.y_float(pass.row, ranks[pi][*col]);
                let z = self.lay.z_float(self.spec_layer[pass.spec], sign);
                let x = self.lay.x_center(*col);
                let mut crossings = Vec::with_capacity(2 * crosses.len());
                for &l in crosses {
                    let a = self.lay.leg_offset();
                    for (leg, s) in [(LEFT, -1.0), (RIGHT, 1.0)] {
                        let c = self.store.contact(Vec3::new(x + s * a, y, z), ContactKind::Float);
                        crossings.push((x + s * a, c, float_role));
                        self.legs[l][leg].push(LegEvent {
                            y,
                            band: pass.row,
                            contact: c,
                            role: other(float_role),
                            float_side: Some(sign),
                        });
                    }
                }
                crossings.sort_by(|p, q| p.0.total_cmp(&q.0));
                self.float_kinds.push(*kind);
                row_cells.push(Some(FloatCell {
                    id: self.float_kinds.len() - 1,
                    y,
                    z,
                    crossings,
                }));
            }
            self.floats.push(row_cells);
        }
    }

    /// Points of one leg, bottom to top (contacts and shape points).
    fn leg(&mut self, id: LoopId, side: usize) -> Vec<PathPoint> {
        let l = &self.g.loops[id];
        let sign = if side == LEFT { -1.0 } else { 1.0 };
        let x = self.lay.x_center(l.col) + sign * self.lay.leg_offset();
        let z_leg = self.leg_z(id);
        let events = self.legs[id][side].clone();
        let mut stations: Vec<(f64, PathPoint)> = Vec::new();
        for band in l.row..l.top_row {
            let mut floats = events
                .iter()
                .filter(|e| e.band == band)
                .filter_map(|e| e.float_side.map(|s| (e.y, s)));
            match floats.next() {
                None => {
                    let y = (band as f64 + 0.5) * self.lay.h;
                    stations.push((y, self.store.free(Vec3::new(x, y, z_leg))));
                }
                Some(first) => {
                    let (mut lo, mut hi) = (first, first);
                    for f in floats {
                        if f.0 < lo.0 {
                            lo = f;
                        }
                        if f.0 > hi.0 {
                            hi = f;
                        }
                    }
                    let z = self.lay.float_bend_z;
                    let bend = self.lay.float_bend;
                    let pre = Vec3::new(x, lo.0 - bend, -lo.1 * z);
                    let post = Vec3::new(x, hi.0 + bend, -hi.1 * z);
                    stations.push((pre.y, self.store.free(pre)));
                    stations.push((post.y, self.store.free(post)));
                }
            }
        }
        for e in &events {
            stations.push((e.y, self.store.at(e.contact, e.role)));
        }
        stations.sort_by(|p, q| p.0.total_cmp(&q.0));
        stations.into_iter().map(|s| s.1).collect()
    }

    /// z of a loop's legs: by kind, and a tuck one `tuck_depth` behind the
    /// legs of the loop it sits on.
    fn leg_z(&self, id: LoopId) -> f64 {
        let l = &self.g.loops[id];
        match l.tucked_on {
            Some(held) => self.leg_z(held) - self.lay.slot_depth(l.slot),
            None => leg_sign(l.kind) * self.lay.leg_z,
        }
    }

    /// One loop, left sinker to right sinker excluded, drawn left to right.
    /// A child passes through its parents' heads deepest (tucks) first.
    pub(super) fn loop_points(&mut self, id: LoopId) -> Vec<PathPoint> {
        let g = self.g;
        let l = &g.loops[id];
        let role = child_role(l.kind);
        let mut pts = Vec::new();
        let parents = self.interlocks[id].clone();
        for ids in parents.iter().rev() {
            pts.push(self.store.at(ids[0], role));
            pts.push(self.store.at(ids[1], role));
        }
        if let Some(t) = self.tucks[id] {
            pts.push(self.store.at(t[0], Role::Back));
        }
        pts.extend(self.leg(id, LEFT));

        let x = self.lay.x_center(l.col);
        let a = self.lay.leg_offset();
        let top = self.lay.y_interlock(l.top_row);
        let head_sign = l.child.map_or(leg_sign(l.kind), |c| leg_sign(g.loops[c].kind));
        let depth = self.lay.slot_depth(l.slot);
        let apex_z = -head_sign * self.lay.leg_z - depth;
        let apex = Vec3::new(x, top + self.lay.apex_rise, apex_z);
        match l.child {
            Some(c) => {
                let j = g.loops[c].parents.iter().position(|&p| p == id).unwrap_or(0);
                let ids = self.interlocks[c][j];
                let pr = other(child_role(g.loops[c].kind));
                pts.push(self.store.at(ids[0], pr).on_head());
                pts.push(self.store.at(ids[1], pr).on_head());
                pts.push(self.store.free(apex).on_head());
                pts.push(self.store.at(ids[2], pr).on_head());
                pts.push(self.store.at(ids[3], pr).on_head());
            }
            None => {
                pts.push(self.store.free(Vec3::new(x - a, top, -depth)).on_head());
                pts.push(self.store.free(apex).on_head());
                pts.push(self.store.free(Vec3::new(x + a, top, -depth)).on_head());
            }
        }

        let mut right = self.leg(id, RIGHT);
        right.reverse();
        pts.extend(right);
        if let Some(t) = self.tucks[id] {
            pts.push(self.store.at(t[1], Role::Back));
        }
        for ids in &parents {
            pts.push(self.store.at(ids[2], role));
            pts.push(self.store.at(ids[3], role));
        }
        pts
    }
}
