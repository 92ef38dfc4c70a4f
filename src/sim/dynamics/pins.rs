//! Pin selectors resolved to node sets on a fabric's starting state
//! (`sim::dynamics_settings::PinSelector`).
//!
//! Geometric selectors (corners, edges) use the bounding box of the nodes
//! in the `x`-`y` plane, the plane the compiler lays a swatch out in; the
//! stitch selector uses the interlock grid of the compiled fabric
//! (`topology::StitchGrid`), so it needs the fabric as compiled.

use crate::sim::dynamics_settings::{Edge, PinSelector, YarnEnd};
use crate::topology::{Fabric, StitchGrid};

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PinError {
    #[error("pins[{index}]: {message}")]
    Bad { index: usize, message: String },
}

/// Every node used by a yarn, with its position.
fn yarn_nodes(f: &Fabric) -> Vec<usize> {
    let mut used = vec![false; f.nodes.len()];
    for y in &f.yarns {
        for p in &y.points {
            used[p.node] = true;
        }
    }
    (0..f.nodes.len()).filter(|&n| used[n]).collect()
}

/// The node sets of `selectors` on `state`; `compiled` (the flat layout,
/// same topology) serves the stitch selector and the geometric ones.
pub fn resolve_pins(compiled: &Fabric, selectors: &[PinSelector]) -> Result<Vec<Vec<usize>>, PinError> {
    let nodes = yarn_nodes(compiled);
    let x = |n: usize| compiled.nodes[n].x;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &n in &nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(x(n)[k]);
            hi[k] = hi[k].max(x(n)[k]);
        }
    }
    let mut grid: Option<StitchGrid> = None;
    let mut out = Vec::with_capacity(selectors.len());
    for (index, sel) in selectors.iter().enumerate() {
        let bad = |message: String| PinError::Bad { index, message };
        let set: Vec<usize> = match sel {
            PinSelector::Corners { edge } => {
                let corners: Vec<[f64; 2]> = [[lo[0], lo[1]], [hi[0], lo[1]], [lo[0], hi[1]], [hi[0], hi[1]]]
                    .into_iter()
                    .filter(|c| match edge {
                        None => true,
                        Some(Edge::Top) => c[1] == hi[1],
                        Some(Edge::Bottom) => c[1] == lo[1],
                        Some(Edge::Left) => c[0] == lo[0],
                        Some(Edge::Right) => c[0] == hi[0],
                    })
                    .collect();
                let mut set: Vec<usize> = corners
                    .iter()
                    .filter_map(|c| {
                        nodes.iter().copied().min_by(|&a, &b| {
                            let d = |n: usize| (x(n)[0] - c[0]).powi(2) + (x(n)[1] - c[1]).powi(2);
                            d(a).total_cmp(&d(b))
                        })
                    })
                    .collect();
                set.dedup();
                set
            }
            PinSelector::Edge { edge, depth } => nodes
                .iter()
                .copied()
                .filter(|&n| match edge {
                    Edge::Top => x(n)[1] >= hi[1] - depth,
                    Edge::Bottom => x(n)[1] <= lo[1] + depth,
                    Edge::Left => x(n)[0] <= lo[0] + depth,
                    Edge::Right => x(n)[0] >= hi[0] - depth,
                })
                .collect(),
            PinSelector::Stitches { rows, columns } => {
                let g = grid.get_or_insert_with(|| StitchGrid::of(compiled));
                let (nr, nc) = g.size();
                if rows[0] < 1
                    || rows[0] > rows[1]
                    || rows[1] > nr
                    || columns[0] < 1
                    || columns[0] > columns[1]
                    || columns[1] > nc
                {
                    return Err(bad(format!(
                        "rows {rows:?} and columns {columns:?} must be ranges within the {nr} x {nc} interlock grid (1-based)"
                    )));
                }
                let mut set = Vec::new();
                for r in rows[0] - 1..rows[1] {
                    for c in columns[0] - 1..columns[1] {
                        set.extend_from_slice(g.cell(r, c));
                    }
                }
                set.sort_unstable();
                set.dedup();
                set
            }
            PinSelector::YarnEnd { yarn, end } => {
                let y = compiled
                    .yarns
                    .get(*yarn)
                    .ok_or_else(|| bad(format!("there is no yarn {yarn} ({} yarns)", compiled.yarns.len())))?;
                let p = match end {
                    YarnEnd::Start => y.points.first(),
                    YarnEnd::End => y.points.last(),
                };
                p.map(|p| vec![p.node]).unwrap_or_default()
            }
            PinSelector::Nodes { nodes: list } => {
                if let Some(n) = list.iter().find(|&&n| n >= compiled.nodes.len()) {
                    return Err(bad(format!("node {n} does not exist ({} nodes)", compiled.nodes.len())));
                }
                list.clone()
            }
        };
        if set.is_empty() {
            return Err(bad("selects no node".to_string()));
        }
        out.push(set);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology::{compile, CompileOptions};

    fn swatch() -> Fabric {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/patterns/stockinette.knit")).unwrap();
        let text = crate::app::study::resize_text(&text, 4);
        let parsed = crate::pattern::parse_str(&text, "stockinette").unwrap();
        compile(&parsed.pattern, &CompileOptions::default()).unwrap()
    }

    #[test]
    fn selectors_pick_the_nodes_they_name() {
        let f = swatch();
        let sets = resolve_pins(
            &f,
            &[
                PinSelector::Corners { edge: None },
                PinSelector::Corners { edge: Some(Edge::Top) },
                PinSelector::Edge {
                    edge: Edge::Top,
                    depth: 1e-3,
                },
                PinSelector::Stitches {
                    rows: [1, 1],
                    columns: [1, 2],
                },
            ],
        )
        .unwrap();
        assert_eq!(sets[0].len(), 4);
        assert_eq!(sets[1].len(), 2);
        let top = f.nodes.iter().map(|n| n.x.y).fold(f64::NEG_INFINITY, f64::max);
        assert!(sets[2].iter().all(|&n| f.nodes[n].x.y >= top - 1e-3));
        // Two stitches of four stitch-contact nodes each.
        assert_eq!(sets[3].len(), 8);
        let e = resolve_pins(
            &f,
            &[PinSelector::Stitches {
                rows: [1, 9],
                columns: [1, 1],
            }],
        )
        .unwrap_err();
        assert!(e.to_string().starts_with("pins[0]:"), "{e}");
    }
}
