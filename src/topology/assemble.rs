//! From passes to yarns: join each piece's passes with edge turns (flat) or
//! the spiral seam (round), map the layout to its place, hand out `u`, and
//! pair every contact node with its two yarn points.
//!
//! Flat edges: the yarn in float layer `k` owns a strand lane outside each
//! edge, `edge_gap + k carry_spacing` beyond it, at its float depth. A pass
//! ends by stepping straight out to its lane at its own height and depth,
//! the yarn climbs the lane (turning, or carried up the side over rows it
//! skips) and steps back in. Lanes differ in x *and* z so one yarn's step
//! never touches another's lane. In the round the next row starts where the
//! last ended; a piece begins and ends on the seam at its own float depth
//! (see `Geometry::pass_path`), so two colours swapping there stay apart.

use super::error::TopologyError;
use super::fabric::{Fabric, PointRef, Vec3, Yarn, YarnPoint};
use super::geometry::Geometry;
use super::knit_graph::{Direction, KnitGraph};
use super::layout::Layout;
use super::options::CompileOptions;
use super::path::{Owner, Path, PathPoint};
use super::rest_length::{assign_u, float_length, ordinary_loop_lengths, segment_weights, stitch_length};
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
    fn lane_x(&self, edge: Edge, layer: usize) -> f64 {
        let out = self.lay.edge_gap + layer as f64 * self.lay.carry_spacing;
        match edge {
            Edge::Left => -out,
            Edge::Right => self.lay.x_boundary(self.lay.columns) + out,
        }
    }

    /// Points from a pass's end `from` out to its lane, outwards order. The
    /// yarn first runs straight out at its own height and depth to its lane
    /// (crossing the inner lanes a layer in front of or behind them), then
    /// turns to the lane's depth, its float depth.
    fn step_out(&self, geo: &mut Geometry, edge: Edge, layer: usize, from: Vec3) -> Vec<PathPoint> {
        let x = self.lane_x(edge, layer);
        let z = self.lay.z_float(layer, -1.0);
        let mut pts = Vec::new();
        if (from.z - z).abs() > 1e-9 * self.lay.d && layer > 0 {
            pts.push(geo.store.free(Vec3::new(x, from.y, from.z)));
        }
        pts.push(geo.store.free(Vec3::new(x, from.y, z)));
        pts
    }
}

/// The edge a pass starts at, and its first point.
fn edge_of(p: &Path, geo: &Geometry, lay: &Layout) -> (Edge, Vec3) {
    let x = p.points.first().map_or(Vec3::zeros(), |q| geo.store.position(q));
    let edge = if x.x < 0.5 * lay.x_boundary(lay.columns) {
        Edge::Left
    } else {
        Edge::Right
    };
    (edge, x)
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
        for &pi in &piece.passes {
            let mut pass = geo.pass_path(pi);
            if g.passes[pi].dir == Direction::RightToLeft {
                pass.reverse();
            }
            let (edge, start) = edge_of(&pass, &geo, lay);
            if !lay.round {
                if let Some(last) = path.last() {
                    let end = geo.store.position(last);
                    for p in join.step_out(&mut geo, edge, layer, end) {
                        path.push(p, Owner::Connector);
                    }
                }
                for p in join.step_out(&mut geo, edge, layer, start).into_iter().rev() {
                    path.push(p, Owner::Connector);
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
                        continue;
                    }
                }
            }
            path.append(pass, Owner::Connector);
        }
        if let (false, Some(last)) = (lay.round, path.last()) {
            let end = geo.store.position(last);
            let edge = if end.x < 0.5 * lay.x_boundary(lay.columns) {
                Edge::Left
            } else {
                Edge::Right
            };
            for p in join.step_out(&mut geo, edge, layer, end) {
                path.push(p, Owner::Connector);
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

    let all_lengths: Vec<Vec<f64>> = paths
        .iter()
        .map(|(_, path)| {
            path.points
                .windows(2)
                .map(|s| (nodes[remap[s[1].node]].x - nodes[remap[s[0].node]].x).norm())
                .collect()
        })
        .collect();
    // Loops laid out longer than an ordinary one: a slipped or held loop is
    // drawn over more than one row, a tuck loop's legs run back to the layer
    // behind the loop it sits on, and a child pulled through a tuck and its
    // loop runs its foot through both layers. Each head is given an
    // ordinary loop's share of the yarn (`rest_length` docs).
    let elongated = |id: usize| {
        let l = &g.loops[id];
        l.top_row > l.row + 1 || l.tucked_on.is_some() || l.parents.len() > 1
    };
    let mut ordinary = ordinary_loop_lengths(
        all_lengths
            .iter()
            .zip(&paths)
            .map(|(l, (_, p))| (&l[..], &p.owners[..])),
        |id| !elongated(id),
    );
    ordinary.sort_by(f64::total_cmp);
    let reference = ordinary.get(ordinary.len() / 2).copied().unwrap_or(0.0);

    let mut yarns = Vec::with_capacity(paths.len());
    for (yi, ((spec, path), lengths)) in paths.iter().zip(&all_lengths).enumerate() {
        let d = 2.0 * meta.yarns.get(*spec).map_or(0.0, |y| y.radius);
        let head: Vec<bool> = path.points.windows(2).map(|s| s[0].head && s[1].head).collect();
        let weights = segment_weights(lengths, &path.owners, &head, elongated, reference);
        let u = assign_u(lengths, &weights, &path.owners, |owner, total| match owner {
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
            layer: 0,
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
