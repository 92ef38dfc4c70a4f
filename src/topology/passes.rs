//! Stringing loops and floats into a pass (one yarn's trip along a row).
//!
//! - Sinkers sit between two loops of the pass and at a piece's ends.
//! - Where a float meets a loop of its own pass, the yarn first *drops*
//!   below the float level at the float's depth, a little towards the loop,
//!   then goes to the loop's foot. So two colours changing places at a
//!   column boundary cross there a full drop apart in height and a float
//!   layer apart in depth, instead of sharing a sinker spot.
//! - In the round the seam joins a row's left end to the next row's right
//!   end; it is treated like any column boundary between the two passes of
//!   the same piece. A piece that starts or ends on the seam does so at its
//!   own float depth, the ending one a little higher and the starting one a
//!   little lower, so a colour change there keeps the ends apart.

use super::fabric::Vec3;
use super::geometry::{sinker_sign, Geometry};
use super::knit_graph::Cell;
use super::path::{Owner, Path, PathPoint};

impl Geometry<'_> {
    fn sinker_z(&self, pass: usize, col: usize, neighbour: Option<usize>) -> f64 {
        let cells = &self.g.passes[pass].cells;
        let sign_at = |c: usize| match cells.get(c) {
            Some(Cell::Loop(l)) => Some(sinker_sign(self.g.loops[*l].kind)),
            _ => None,
        };
        let own = sign_at(col).unwrap_or(-1.0);
        let other = neighbour.and_then(sign_at).unwrap_or(own);
        0.5 * (own + other) * self.lay.leg_z
    }

    /// Where a float meets a loop of its own pass, the yarn first drops
    /// below the float level at the float's depth, a little towards the loop
    /// (`towards` = +1 right, -1 left), then goes to the loop's foot. So the
    /// yarn leaving a float is a full drop away from another colour's float
    /// before it rises through that float's layer.
    fn drop_point(&mut self, float_end: Vec3, towards: f64) -> PathPoint {
        let x = float_end.x + towards * self.lay.float_drop_shift;
        let y = float_end.y - self.lay.float_drop;
        self.store.free(Vec3::new(x, y, float_end.z))
    }

    /// A piece starts and ends on a tube's seam at its own float depth, so
    /// one colour's end and the next colour's start (which meet there) are
    /// apart.
    fn edge_sinker_z(&self, pass: usize, col: usize, next: Option<usize>, nb: Neighbour) -> f64 {
        if self.lay.round && nb == Neighbour::Edge {
            let layer = self.spec_layer[self.g.passes[pass].spec];
            return self.lay.z_float(layer, -1.0);
        }
        self.sinker_z(pass, col, next)
    }

    /// On a tube's seam a piece that ends (at the row's left end) finishes a
    /// little higher and one that starts (at the right end) begins a little
    /// lower, so a colour change there has the two ends a diameter apart in
    /// height as well as a layer apart in depth.
    fn seam_end_rise(&self, nb: Neighbour) -> f64 {
        if self.lay.round && nb == Neighbour::Edge {
            0.6 * self.lay.d
        } else {
            0.0
        }
    }

    /// What lies beside column `col` of a pass, `side` -1 left or +1 right.
    /// In the round the seam joins a row's left end to the next row's right
    /// end (and its right end to the previous row's left end) when the same
    /// yarn piece works both rows.
    fn neighbour(&self, pass: usize, col: usize, side: isize) -> Neighbour {
        let p = &self.g.passes[pass];
        let width = p.cells.len();
        let (other_pass, other_col) = match (side, col) {
            (-1, 0) => (self.seam_pass(pass, 1), width.saturating_sub(1)),
            (1, c) if c + 1 == width => (self.seam_pass(pass, -1), 0),
            (-1, c) => (Some(pass), c - 1),
            (_, c) => (Some(pass), c + 1),
        };
        let on_seam = other_pass != Some(pass);
        match other_pass.and_then(|q| self.g.passes[q].cells.get(other_col)) {
            None => Neighbour::Edge,
            Some(Cell::Loop(_)) => Neighbour::Loop { on_seam },
            Some(Cell::Float { .. }) => Neighbour::Float { on_seam },
        }
    }

    /// The same piece's pass one row up (`step` 1) or down (-1), in the round.
    fn seam_pass(&self, pass: usize, step: isize) -> Option<usize> {
        if !self.lay.round {
            return None;
        }
        let p = &self.g.passes[pass];
        let row = p.row.checked_add_signed(step)?;
        self.g.pieces[p.piece]
            .passes
            .iter()
            .copied()
            .find(|&q| self.g.passes[q].row == row)
    }

    /// A whole pass, drawn left to right (flat layout). Sinkers sit between
    /// two loops of the pass (and at the edges). Where a float meets a loop
    /// of its own pass the float end drops first (see `drop_point`),
    /// so two colours changing places at a column boundary cross there at
    /// their different float depths instead of sharing a sinker spot.
    pub fn pass_path(&mut self, pass: usize) -> Path {
        let g = self.g;
        let p = &g.passes[pass];
        let sinker_y = self.lay.y_interlock(p.row) - self.lay.sinker_drop;
        let mut path = Path::default();
        for (col, cell) in p.cells.iter().enumerate() {
            let x_left = self.lay.x_boundary(col);
            let x_right = self.lay.x_boundary(col + 1);
            let left = self.neighbour(pass, col, -1);
            let right = self.neighbour(pass, col, 1);
            match cell {
                Cell::Loop(id) => {
                    let owner = Owner::Loop(*id);
                    let first = matches!(left, Neighbour::Edge | Neighbour::Loop { on_seam: true });
                    if first {
                        let z = self.edge_sinker_z(pass, col, None, left);
                        let y = sinker_y + self.seam_end_rise(left);
                        let s = self.store.free(Vec3::new(x_left, y, z));
                        path.push(s, owner);
                    }
                    for pt in self.loop_points(*id) {
                        path.push(pt, owner);
                    }
                    if matches!(right, Neighbour::Edge | Neighbour::Loop { .. }) {
                        let z = self.edge_sinker_z(pass, col, Some(col + 1), right);
                        let y = sinker_y - self.seam_end_rise(right);
                        let s = self.store.free(Vec3::new(x_right, y, z));
                        path.push(s, owner);
                    }
                }
                Cell::Float { .. } => {
                    let Some(f) = self.floats[pass][col].clone() else {
                        continue;
                    };
                    let owner = Owner::Float(f.id);
                    let entry = Vec3::new(x_left, f.y, f.z);
                    if matches!(left, Neighbour::Loop { .. }) {
                        let d = self.drop_point(entry, -1.0);
                        path.push(d, owner);
                    }
                    if !matches!(left, Neighbour::Float { on_seam: false }) {
                        let e = self.store.free(entry);
                        path.push(e, owner);
                    }
                    let mut last_x = None;
                    for &(x, c, role) in &f.crossings {
                        if let Some(lx) = last_x {
                            let mid = self.store.free(Vec3::new(0.5 * (lx + x), f.y, f.z));
                            path.push(mid, owner);
                        }
                        path.push(self.store.at(c, role), owner);
                        last_x = Some(x);
                    }
                    if !matches!(right, Neighbour::Float { on_seam: false }) {
                        let exit = Vec3::new(x_right, f.y, f.z);
                        let e = self.store.free(exit);
                        path.push(e, owner);
                        if matches!(right, Neighbour::Loop { .. }) {
                            let d = self.drop_point(exit, 1.0);
                            path.push(d, owner);
                        }
                    }
                }
            }
        }
        path
    }
}

/// What lies beside a cell of a pass.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Neighbour {
    /// Nothing: a fabric edge, or a piece's start or end.
    Edge,
    Loop {
        on_seam: bool,
    },
    Float {
        on_seam: bool,
    },
}
