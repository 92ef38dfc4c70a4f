//! From passes to yarns: join each piece's passes with edge turns (flat) or
//! the spiral seam (round), map the layout to its place, hand out `u`, and
//! pair every contact node with its two yarn points.
//!
//! Flat edges: the yarn in float layer `k` owns a strand lane outside each
//! edge, `edge_gap + k carry_spacing` beyond it, at its float depth. A pass ends by stepping out to its lane, the yarn climbs the
//! lane (turning, or carried up the side over rows it skips) and steps back
//! in. Lanes differ in x *and* z so one yarn's step-in never touches
//! another's carried strand. In the round the next row starts where the last
//! ended. A piece begins and ends in a lane behind the fabric beside the
//! seam: entering pieces left of it, leaving ones right of it, one lane per
//! yarn spec, so two colours swapping at the seam stay apart.

use super::error::TopologyError;
use super::fabric::{Fabric, PointRef, Vec3, Yarn, YarnPoint};
use super::geometry::Geometry;
use super::knit_graph::{Direction, KnitGraph};
use super::layout::Layout;
use super::options::CompileOptions;
use super::path::{Owner, Path, PathPoint};
use super::rest_length::{assign_u, float_length, stitch_length};
use crate::pattern::Meta;

#[derive(Clone, Copy, PartialEq)]
enum Edge {
    Left,
    Right,
}

struct Joiner<'a> {
    lay: &'a Layout,
}

impl Joiner<'_> {
    fn lane_x(&self, edge: Edge, layer: usize, lane: bool) -> f64 {
        let out = self.lay.edge_gap
            + if lane {
                layer as f64 * self.lay.carry_spacing
            } else {
                0.0
            };
        match edge {
            Edge::Left => -out,
            Edge::Right => self.lay.x_boundary(self.lay.columns) + out,
        }
    }

    /// Points from the fabric edge out to the lane at height `y` (outwards
    /// order). A lane lies at its yarn's float depth, so a yarn stepping
    /// out from a float stays in its layer.
    fn step_out(&self, geo: &mut Geometry, edge: Edge, layer: usize, y: f64) -> Vec<PathPoint> {
        let z = self.lay.z_float(layer, -1.0);
        let mut pts = Vec::new();
        if layer > 0 {
            pts.push(geo.store.free(Vec3::new(self.lane_x(edge, layer, false), y, z)));
        }
        pts.push(geo.store.free(Vec3::new(self.lane_x(edge, layer, true), y, z)));
        pts
    }

    /// A piece's end point in the round: a lane behind the fabric, beside
    /// the seam on the side of the row's own stitches (`x = 0` side when it
    /// leaves a row, `x = W` side when it enters), one lane per layer.
    fn seam_lane(&self, geo: &mut Geometry, layer: usize, y: f64, seam_side: Edge) -> PathPoint {
        let shift = (layer as f64 + 0.5) * self.lay.carry_spacing;
        let x = match seam_side {
            Edge::Left => shift,
            Edge::Right => self.lay.x_boundary(self.lay.columns) - shift,
        };
        geo.store.free(Vec3::new(x, y, self.lay.z_min))
    }
}

fn edge_of(p: &Path, geo: &Geometry, lay: &Layout) -> (Edge, f64) {
    let x = p.points.first().map_or(Vec3::zeros(), |q| geo.store.position(q));
    let edge = if x.x < 0.5 * lay.x_boundary(lay.columns) {
        Edge::Left
    } else {
        Edge::Right
    };
    (edge, x.y)
}

/// Builds the fabric from the graph's pieces.
pub fn assemble(
    g: &KnitGraph,
    lay: &Layout,
    mut geo: Geometry,
    meta: &Meta,
    opts: &CompileOptions,
) -> Result<Fabric, TopologyError> {
    let join = Joiner { lay };
    let mut paths: Vec<(usize, Path)> = Vec::with_capacity(g.pieces.len());
    for piece in &g.pieces {
        let spec = piece.spec;
        let layer = geo.spec_layer.get(spec).copied().unwrap_or(0);
        let mut path = Path::default();
        let mut prev_row: Option<usize> = None;
        for &pi in &piece.passes {
            let mut pass = geo.pass_path(pi);
            if g.passes[pi].dir == Direction::RightToLeft {
                pass.reverse();
            }
            let (edge, _) = edge_of(&pass, &geo, lay);
            // Lanes are entered at sinker height, a full row apart per turn.
            let y = lay.y_interlock(g.passes[pi].row) - lay.sinker_drop;
            match (lay.round, prev_row) {
                (false, None) => {
                    for p in join.step_out(&mut geo, edge, layer, y).into_iter().rev() {
                        path.push(p, Owner::Connector);
                    }
                }
                (false, Some(r)) => {
                    let y_end = lay.y_interlock(r) - lay.sinker_drop;
                    for p in join.step_out(&mut geo, edge, layer, y_end) {
                        path.push(p, Owner::Connector);
                    }
                    for p in join.step_out(&mut geo, edge, layer, y).into_iter().rev() {
                        path.push(p, Owner::Connector);
                    }
                }
                (true, _) => {}
            }
            if lay.round && prev_row.is_none() {
                if let Some(first) = pass.points.first() {
                    let y = geo.store.position(first).y;
                    path.push(join.seam_lane(&mut geo, layer, y, Edge::Right), Owner::Connector);
                }
            }
            // In the round the previous pass may end exactly where this starts.
            if let (true, Some(last), Some(first)) = (lay.round, path.last(), pass.points.first()) {
                let a = lay.place(geo.store.position(last));
                let b = lay.place(geo.store.position(first));
                if (a - b).norm() < 1e-9 * lay.w {
                    pass.points.remove(0);
                    if !pass.owners.is_empty() {
                        let o = pass.owners.remove(0);
                        path.append(pass, o);
                        prev_row = Some(g.passes[pi].row);
                        continue;
                    }
                }
            }
            path.append(pass, Owner::Connector);
            prev_row = Some(g.passes[pi].row);
        }
        if let (true, Some(last)) = (lay.round, path.last()) {
            let y = geo.store.position(last).y;
            path.push(join.seam_lane(&mut geo, layer, y, Edge::Left), Owner::Connector);
        }
        if let (false, Some(last), Some(r)) = (lay.round, path.last(), prev_row) {
            {
                let mut pos = geo.store.position(last);
                pos.y = lay.y_interlock(r) - lay.sinker_drop;
                let edge = if pos.x < 0.5 * lay.x_boundary(lay.columns) {
                    Edge::Left
                } else {
                    Edge::Right
                };
                for p in join.step_out(&mut geo, edge, layer, pos.y) {
                    path.push(p, Owner::Connector);
                }
            }
        }
        if let Some(first) = path.points.first_mut() {
            first.fixed_u = true;
        }
        if let Some(last) = path.points.last_mut() {
            last.fixed_u = true;
        }
        paths.push((spec, path));
    }

    // Place the nodes, dropping any a path no longer uses (seam merges).
    let mut used = vec![false; geo.store.nodes.len()];
    for (_, p) in &paths {
        for q in &p.points {
            used[q.node] = true;
        }
    }
    let mut remap = vec![usize::MAX; used.len()];
    let mut nodes = Vec::with_capacity(used.len());
    for (i, node) in geo.store.nodes.iter().enumerate() {
        if used[i] {
            remap[i] = nodes.len();
            let mut n = node.clone();
            n.x = lay.place(n.x);
            nodes.push(n);
        }
    }

    let mut yarns = Vec::with_capacity(paths.len());
    for (yi, (spec, path)) in paths.iter().enumerate() {
        let lengths: Vec<f64> = path
            .points
            .windows(2)
            .map(|s| (nodes[remap[s[1].node]].x - nodes[remap[s[0].node]].x).norm())
            .collect();
        let d = 2.0 * meta.yarns.get(*spec).map_or(0.0, |y| y.radius);
        let u = assign_u(&lengths, &path.owners, |owner, total| match owner {
            Owner::Loop(_) => stitch_length(lay.gauge_w, lay.gauge_h, d, meta.looseness, opts),
            Owner::Float(f) => float_length(lay.gauge_w, geo.float_kinds[f], opts),
            Owner::Connector => total * lay.connector_scale(),
        });
        let mut points = Vec::with_capacity(path.points.len());
        for (pi, (q, &uq)) in path.points.iter().zip(&u).enumerate() {
            if let Some((c, role)) = q.contact {
                geo.store.visit(c, role, PointRef { yarn: yi, point: pi })?;
            }
            points.push(YarnPoint {
                node: remap[q.node],
                u: uq,
                fixed_u: q.fixed_u,
                eil: false,
            });
        }
        if points.windows(2).any(|s| s[1].u <= s[0].u) {
            return Err(TopologyError::Internal(format!(
                "yarn {yi}: u is not strictly increasing (two points coincide)"
            )));
        }
        yarns.push(Yarn {
            spec: *spec,
            rest_length: u.last().copied().unwrap_or(0.0),
            points,
        });
    }
    let mut contacts = geo.store.finish_contacts()?;
    for c in &mut contacts {
        c.node = remap[c.node];
        c.partner = c.partner.map(|n| remap[n]);
    }
    Ok(Fabric {
        meta: meta.clone(),
        nodes,
        yarns,
        contacts,
        sim: None,
    })
}
