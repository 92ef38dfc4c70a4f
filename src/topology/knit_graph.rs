//! The knit graph: which loop is pulled through which, and how each yarn
//! travels along the rows. No geometry yet.
//!
//! Built by simulating the needles column by column, row by row:
//! - every needle holds a stack of loops (bottom = the loop that was pulled
//!   through, above it any tucks laid on it);
//! - knit or purl pulls a new loop through *every* loop on the needle (so a
//!   child passes through a tuck and the loop it sits on), then the needle
//!   holds only the new loop;
//! - a slip leaves the needle alone: the held loop keeps growing upwards and
//!   is finally knitted in a later row, so one loop spans two or more rows;
//! - a tuck pushes a loop onto the needle without pulling it through anything.
//!
//! A cast-on row of plain loops (row 0) is implied below row 1 so that row 1
//! has parents. Loops still on the needles after the last row stay open.
//!
//! Yarn passes: each row has one pass per yarn used in it (as a loop or as
//! the working yarn of a slip), in order of first appearance in work order.
//! A pass spans the whole row: where its yarn makes no loop it floats past
//! the column (a slip float on the side given by the stitch, or a stranded
//! float behind the other colour's loop). In flat knitting a pass starts at
//! the edge where the row is begun (RS rows at the right). A yarn continues
//! its current piece when it waits at that edge (carried up the side if it
//! skipped rows); otherwise a knitter would cut it and rejoin at the other
//! edge, so a new yarn piece starts. In the round every pass runs right to
//! left and a yarn used in consecutive rows continues: the tube is a spiral.
//! A yarn that skips rows in the round is cut and rejoined (a new piece):
//! a strand carried up the seam would have to cross the other colours'
//! ends there, which the starting layout cannot keep clear.

use super::error::TopologyError;
use super::options::CompileOptions;
use crate::pattern::{Construction, Pattern, Side, StitchKind};

pub type LoopId = usize;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LoopKind {
    CastOn,
    Knit,
    Purl,
    Tuck,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Loop {
    /// 0 for the cast-on, chart row number otherwise.
    pub row: usize,
    pub col: usize,
    /// Yarn spec (index into `meta.yarns`).
    pub spec: usize,
    pub kind: LoopKind,
    /// Position on the needle while held: 0 for a pulled-through loop, 1 for
    /// a tuck laid on it.
    pub slot: usize,
    /// Heads this loop is pulled through, bottom of the needle first.
    pub parents: Vec<LoopId>,
    /// The loop pulled through this loop's head, if any.
    pub child: Option<LoopId>,
    /// Row of the child (`rows + 1` when the loop stays open): the loop's
    /// legs span rows `row..top_row`.
    pub top_row: usize,
    /// For a tuck: the loop below it on the needle, whose legs it crosses.
    pub tucked_on: Option<LoopId>,
    /// The pass that made it.
    pub pass: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    LeftToRight,
    RightToLeft,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FloatSide {
    /// On the RS of the legs it crosses.
    Front,
    /// On the WS.
    Back,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FloatKind {
    /// The working yarn passing a slipped stitch.
    Slip,
    /// A colour not used at this column, stranded behind.
    Strand,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    Loop(LoopId),
    Float {
        col: usize,
        side: FloatSide,
        kind: FloatKind,
        /// Loops whose legs the float crosses (all loops spanning this row
        /// at this column), bottom of the needle first.
        crosses: Vec<LoopId>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Pass {
    pub row: usize,
    pub spec: usize,
    pub piece: usize,
    /// This pass's index among the row's passes, and how many there are.
    pub index_in_row: usize,
    pub passes_in_row: usize,
    pub dir: Direction,
    /// One cell per column, left to right as drawn (not work order).
    pub cells: Vec<Cell>,
}

/// A continuous yarn piece: its passes in work order.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    pub spec: usize,
    pub passes: Vec<usize>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct KnitGraph {
    pub width: usize,
    /// Chart rows (the cast-on is row 0 on top of these).
    pub rows: usize,
    pub construction: Construction,
    pub loops: Vec<Loop>,
    pub passes: Vec<Pass>,
    pub pieces: Vec<Piece>,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Edge {
    Left,
    Right,
}

fn direction(construction: Construction, side: Side) -> Direction {
    match (construction, side) {
        (Construction::Flat, Side::Ws) => Direction::LeftToRight,
        _ => Direction::RightToLeft,
    }
}

fn edges(dir: Direction) -> (Edge, Edge) {
    match dir {
        Direction::LeftToRight => (Edge::Left, Edge::Right),
        Direction::RightToLeft => (Edge::Right, Edge::Left),
    }
}

/// Checks what the graph relies on; the gauge and radii are checked by the
/// layout, which is where they matter.
fn validate(p: &Pattern) -> Result<(), TopologyError> {
    let width = p.meta.width;
    if width == 0 || p.rows.is_empty() {
        return Err(TopologyError::Empty {
            width,
            rows: p.rows.len(),
        });
    }
    for (i, row) in p.rows.iter().enumerate() {
        if row.stitches.len() != width {
            return Err(TopologyError::RowWidth {
                row: i + 1,
                expected: width,
                found: row.stitches.len(),
            });
        }
        if p.meta.construction == Construction::Round && row.side == Side::Ws {
            return Err(TopologyError::WsRowInRound { row: i + 1 });
        }
        for (col, st) in row.stitches.iter().enumerate() {
            if st.yarn >= p.meta.yarns.len() {
                return Err(TopologyError::UnknownYarn {
                    row: i + 1,
                    col,
                    yarn: st.yarn,
                    declared: p.meta.yarns.len(),
                });
            }
        }
    }
    Ok(())
}

/// Yarns used in a row, in order of first appearance in work order.
fn row_yarns(p: &Pattern, row_index: usize) -> Vec<usize> {
    let row = &p.rows[row_index];
    let mut out = Vec::new();
    for c in row.work_order() {
        let y = row.stitches[c].yarn;
        if !out.contains(&y) {
            out.push(y);
        }
    }
    out
}

struct Builder {
    g: KnitGraph,
    /// Per spec: the piece it is on and the edge where it waits.
    yarn_at: Vec<Option<(usize, Edge)>>,
    /// Per spec: the last row it was used in.
    used_in_row: Vec<usize>,
}

impl Builder {
    fn add_pass(&mut self, row: usize, spec: usize, index: usize, count: usize, dir: Direction) {
        let (start, end) = edges(dir);
        let piece = match (self.g.construction, self.yarn_at[spec]) {
            (Construction::Round, Some((piece, _))) if self.used_in_row[spec] + 1 == row => piece,
            (Construction::Flat, Some((piece, edge))) if edge == start => piece,
            _ => {
                self.g.pieces.push(Piece {
                    spec,
                    passes: Vec::new(),
                });
                self.g.pieces.len() - 1
            }
        };
        self.yarn_at[spec] = Some((piece, end));
        self.used_in_row[spec] = row;
        self.g.pieces[piece].passes.push(self.g.passes.len());
        self.g.passes.push(Pass {
            row,
            spec,
            piece,
            index_in_row: index,
            passes_in_row: count,
            dir,
            cells: Vec::with_capacity(self.g.width),
        });
    }

    fn new_loop(&mut self, row: usize, col: usize, spec: usize, kind: LoopKind, pass: usize) -> LoopId {
        self.g.loops.push(Loop {
            row,
            col,
            spec,
            kind,
            slot: 0,
            parents: Vec::new(),
            child: None,
            top_row: 0,
            tucked_on: None,
            pass,
        });
        self.g.loops.len() - 1
    }
}

/// Builds the knit graph of a pattern.
pub fn build(p: &Pattern, opts: &CompileOptions) -> Result<KnitGraph, TopologyError> {
    validate(p)?;
    let width = p.meta.width;
    let rows = p.rows.len();
    let construction = p.meta.construction;
    let mut b = Builder {
        g: KnitGraph {
            width,
            rows,
            construction,
            loops: Vec::with_capacity(width * (rows + 1)),
            passes: Vec::new(),
            pieces: Vec::new(),
        },
        yarn_at: vec![None; p.meta.yarns.len()],
        used_in_row: vec![0; p.meta.yarns.len()],
    };

    // Cast-on: one pass with the yarn that starts row 1, ending where row 1 begins.
    let first = &p.rows[0];
    let first_dir = direction(construction, first.side);
    let cast_on_spec = first.work_order().next().map_or(0, |c| first.stitches[c].yarn);
    let cast_on_dir = match (construction, first_dir) {
        (Construction::Flat, Direction::RightToLeft) => Direction::LeftToRight,
        (Construction::Flat, Direction::LeftToRight) => Direction::RightToLeft,
        (Construction::Round, _) => Direction::RightToLeft,
    };
    b.add_pass(0, cast_on_spec, 0, 1, cast_on_dir);
    let mut needles: Vec<Vec<LoopId>> = Vec::with_capacity(width);
    for col in 0..width {
        let id = b.new_loop(0, col, cast_on_spec, LoopKind::CastOn, 0);
        b.g.passes[0].cells.push(Cell::Loop(id));
        needles.push(vec![id]);
    }

    for (i, row) in p.rows.iter().enumerate() {
        let r = i + 1;
        let dir = direction(construction, row.side);
        let yarns = row_yarns(p, i);
        let first_pass = b.g.passes.len();
        for (k, &spec) in yarns.iter().enumerate() {
            b.add_pass(r, spec, k, yarns.len(), dir);
        }
        for (col, st) in row.stitches.iter().enumerate() {
            let worker = first_pass + yarns.iter().position(|&y| y == st.yarn).unwrap_or(0);
            let held = needles[col].clone();
            let bottom_row = held.first().map_or(r, |&h| b.g.loops[h].row);
            let made = match st.kind {
                StitchKind::Knit | StitchKind::Purl => {
                    let kind = if st.kind == StitchKind::Knit {
                        LoopKind::Knit
                    } else {
                        LoopKind::Purl
                    };
                    let id = b.new_loop(r, col, st.yarn, kind, worker);
                    for &h in &held {
                        b.g.loops[h].child = Some(id);
                        b.g.loops[h].top_row = r;
                    }
                    b.g.loops[id].parents = held;
                    needles[col] = vec![id];
                    Some(id)
                }
                StitchKind::SlipFront | StitchKind::SlipBack | StitchKind::Tuck => {
                    let span = r + 1 - bottom_row;
                    if span > opts.max_rows_per_loop {
                        return Err(TopologyError::HeldTooLong {
                            row: r,
                            col,
                            rows: span,
                            max: opts.max_rows_per_loop,
                        });
                    }
                    if st.kind == StitchKind::Tuck {
                        if held.len() + 1 > opts.max_loops_on_needle {
                            return Err(TopologyError::NeedleOverfull {
                                row: r,
                                col,
                                loops: held.len() + 1,
                                max: opts.max_loops_on_needle,
                            });
                        }
                        let id = b.new_loop(r, col, st.yarn, LoopKind::Tuck, worker);
                        b.g.loops[id].slot = held.len();
                        b.g.loops[id].tucked_on = held.last().copied();
                        needles[col].push(id);
                        Some(id)
                    } else {
                        None
                    }
                }
            };
            let spanning = needles[col].clone();
            for (k, &spec) in yarns.iter().enumerate() {
                let cell = match made {
                    Some(id) if st.yarn == spec => Cell::Loop(id),
                    _ if st.yarn == spec => Cell::Float {
                        col,
                        side: if st.kind == StitchKind::SlipFront {
                            FloatSide::Front
                        } else {
                            FloatSide::Back
                        },
                        kind: FloatKind::Slip,
                        crosses: spanning.clone(),
                    },
                    _ => Cell::Float {
                        col,
                        side: FloatSide::Back,
                        kind: FloatKind::Strand,
                        crosses: spanning.clone(),
                    },
                };
                b.g.passes[first_pass + k].cells.push(cell);
            }
        }
    }
    for stack in &needles {
        for &id in stack {
            b.g.loops[id].top_row = rows + 1;
        }
    }
    Ok(b.g)
}

impl KnitGraph {
    /// Number of loops the chart makes (cast-on excluded).
    pub fn pattern_loops(&self) -> usize {
        self.loops.iter().filter(|l| l.kind != LoopKind::CastOn).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology::sample::chart_pattern;

    fn graph(chart: &[&str]) -> KnitGraph {
        let p = chart_pattern(chart, None, Construction::Flat).unwrap();
        build(&p, &CompileOptions::default()).unwrap()
    }

    #[test]
    fn slipped_loop_is_knitted_two_rows_up() {
        // Column 1 slipped in row 1 (bottom row "kvk"), knitted in row 2.
        let g = graph(&["kkk", "kvk"]);
        let cast_on_1 = g.loops.iter().position(|l| l.row == 0 && l.col == 1).unwrap();
        let child = g.loops.iter().position(|l| l.row == 2 && l.col == 1).unwrap();
        assert_eq!(g.loops[child].parents, vec![cast_on_1]);
        assert_eq!(g.loops[cast_on_1].top_row, 2);
        assert_eq!(g.loops[cast_on_1].child, Some(child));
        // Row 1's pass floats over column 1, crossing the held cast-on loop.
        let pass = g.passes.iter().find(|p| p.row == 1).unwrap();
        assert!(
            matches!(&pass.cells[1], Cell::Float { crosses, side: FloatSide::Front, .. }
            if crosses == &vec![cast_on_1])
        );
    }

    #[test]
    fn tuck_child_has_two_parents_and_last_row_stays_open() {
        let g = graph(&["kkk", "ktk"]);
        let held = g.loops.iter().position(|l| l.row == 0 && l.col == 1).unwrap();
        let tuck = g.loops.iter().position(|l| l.kind == LoopKind::Tuck).unwrap();
        assert_eq!(g.loops[tuck].tucked_on, Some(held));
        assert_eq!(g.loops[tuck].slot, 1);
        let child = g.loops.iter().position(|l| l.row == 2 && l.col == 1).unwrap();
        assert_eq!(g.loops[child].parents, vec![held, tuck]);
        assert!(g
            .loops
            .iter()
            .filter(|l| l.row == 2)
            .all(|l| l.top_row == 3 && l.child.is_none()));
    }

    #[test]
    fn passes_follow_work_order_and_turn() {
        // Cast-on left to right, RS row 1 right to left, WS row 2 left to
        // right: one piece of three passes.
        let g = graph(&["kk", "kk"]);
        let dirs: Vec<Direction> = g.passes.iter().map(|p| p.dir).collect();
        assert_eq!(
            dirs,
            vec![Direction::LeftToRight, Direction::RightToLeft, Direction::LeftToRight]
        );
        assert_eq!(g.pieces.len(), 1);
        assert_eq!(g.pieces[0].passes, vec![0, 1, 2]);
    }
}
