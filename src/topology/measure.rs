//! Measured gauge: stitches and rows per 10 cm of a fabric state, counted
//! the way a knitter counts a swatch, in its middle and away from the edges.
//!
//! Each knitted stitch is held by one interlock: the two stitch contacts
//! where a child loop's legs pass through its parent's head, four
//! [`ContactKind::Stitch`] nodes in two partner pairs (docs/MODEL.md,
//! "Stitch contact layout"). The compiled (flat) layout puts every pair's
//! midpoint on a regular grid: one `y` per interlock row, two `x` per
//! column (left and right leg). [`StitchGrid::of`] reads that grid off the
//! *compiled* fabric once; [`StitchGrid::measure`] then takes any later
//! state of the same fabric (node numbers are stable through relaxation)
//! and averages the distances between the centres of neighbouring
//! interlocks over the middle half of the swatch:
//!
//! - wale spacing: centre of `(row, col)` to centre of `(row, col + 1)`;
//! - course spacing: centre of `(row, col)` to centre of `(row + 1, col)`.
//!
//! A slipped or tucked stitch leaves its cell empty (its loop is carried
//! up, unworked), so the linen stitch's grid is a checkerboard. Where the
//! neighbour is missing, the next present cell up to [`MAX_GAP`] cells
//! away is used and the distance divided by the cells crossed, as a
//! knitter counts a slip-stitch fabric over several stitches.
//!
//! Distances are straight-line in 3D, so a curled swatch still measures
//! the length of fabric per stitch, as a knitter's tape laid along it
//! does. Patterns knitted in the round, or whose interlocks do not fill a
//! grid, have no grid: measuring them returns `None`.

use super::fabric::{ContactKind, Fabric, Vec3};
use serde::Serialize;
use std::collections::BTreeMap;

/// How many cells a neighbour may lie away along a row or a column
/// (slipped and tucked stitches leave empty cells between).
pub const MAX_GAP: usize = 3;

/// What a swatch measures.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MeasuredGauge {
    pub stitches_per_10cm: f64,
    pub rows_per_10cm: f64,
    /// Wale and course spacings averaged (m).
    pub wale_spacing: f64,
    pub course_spacing: f64,
    /// How many neighbour pairs each average took.
    pub wale_samples: usize,
    pub course_samples: usize,
}

/// The interlocks of a compiled fabric by grid cell: node numbers of the
/// four stitch-contact nodes of each `(row, col)`.
#[derive(Clone, Debug, Default)]
pub struct StitchGrid {
    cells: BTreeMap<(usize, usize), Vec<usize>>,
    rows: usize,
    cols: usize,
}

/// Ranks of `values` after merging values closer than `tol`.
fn cluster_ranks(values: &[f64], tol: f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut rank = vec![0; values.len()];
    let mut current = 0;
    for w in 0..order.len() {
        if w > 0 && values[order[w]] - values[order[w - 1]] > tol {
            current += 1;
        }
        rank[order[w]] = current;
    }
    rank
}

impl StitchGrid {
    /// Reads the interlock grid off a compiled, flat fabric.
    pub fn of(compiled: &Fabric) -> Self {
        let x = |n: usize| compiled.nodes[n].x;
        // One entry per partner pair of stitch contacts: (its two nodes, midpoint).
        let mut pairs: Vec<([usize; 2], Vec3)> = Vec::new();
        for c in compiled.contacts.iter().filter(|c| c.kind == ContactKind::Stitch) {
            if let Some(p) = c.partner.filter(|&p| c.node < p) {
                pairs.push(([c.node, p], 0.5 * (x(c.node) + x(p))));
            }
        }
        if pairs.is_empty() {
            return Self::default();
        }
        // Grid pitches are millimetres; compiled positions repeat exactly.
        let tol = 1e-6;
        let rows = cluster_ranks(&pairs.iter().map(|p| p.1.y).collect::<Vec<_>>(), tol);
        let legs = cluster_ranks(&pairs.iter().map(|p| p.1.x).collect::<Vec<_>>(), tol);
        let n_legs = legs.iter().max().map_or(0, |m| m + 1);
        if n_legs % 2 != 0 {
            return Self::default();
        }
        let mut cells: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
        for (k, (nodes, _)) in pairs.iter().enumerate() {
            cells.entry((rows[k], legs[k] / 2)).or_default().extend(nodes);
        }
        let rows = rows.iter().max().map_or(0, |m| m + 1);
        StitchGrid {
            cells,
            rows,
            cols: n_legs / 2,
        }
    }

    /// Interlock rows and columns found.
    pub fn size(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// The stitch-contact nodes of interlock `(row, col)` (0-based, row 0
    /// at the bottom, column 0 at the left); empty outside the grid.
    pub fn cell(&self, row: usize, col: usize) -> &[usize] {
        self.cells.get(&(row, col)).map_or(&[], Vec::as_slice)
    }

    fn centre(&self, f: &Fabric, cell: (usize, usize)) -> Option<Vec3> {
        let nodes = self.cells.get(&cell)?;
        if nodes.len() != 4 {
            return None;
        }
        let sum = nodes.iter().fold(Vec3::zeros(), |s, &n| s + f.nodes[n].x);
        Some(sum / 4.0)
    }

    /// The gauge of `state` (a later state of the compiled fabric), over
    /// the middle half of the grid in each direction; `None` without a grid
    /// of at least 2 x 2 interlocks or with a non-finite position.
    pub fn measure(&self, state: &Fabric) -> Option<MeasuredGauge> {
        if self.rows < 2 || self.cols < 2 || self.cells.values().flatten().any(|&n| n >= state.nodes.len()) {
            return None;
        }
        let middle = |n: usize| {
            let cut = n / 4;
            cut..(n - cut).max(cut + 2).min(n)
        };
        let (rows, cols) = (middle(self.rows), middle(self.cols));
        let (mut wale, mut course) = ((0.0, 0usize), (0.0, 0usize));
        for r in rows.clone() {
            for c in cols.clone() {
                let Some(here) = self.centre(state, (r, c)) else {
                    continue;
                };
                let right = (1..=MAX_GAP)
                    .find_map(|k| (c + k < cols.end).then(|| self.centre(state, (r, c + k)).map(|x| (x, k)))?);
                if let Some((right, k)) = right {
                    wale = (wale.0 + (right - here).norm() / k as f64, wale.1 + 1);
                }
                let up = (1..=MAX_GAP)
                    .find_map(|k| (r + k < rows.end).then(|| self.centre(state, (r + k, c)).map(|x| (x, k)))?);
                if let Some((up, k)) = up {
                    course = (course.0 + (up - here).norm() / k as f64, course.1 + 1);
                }
            }
        }
        if wale.1 == 0 || course.1 == 0 {
            return None;
        }
        let (w, h) = (wale.0 / wale.1 as f64, course.0 / course.1 as f64);
        (w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0).then_some(MeasuredGauge {
            stitches_per_10cm: 0.1 / w,
            rows_per_10cm: 0.1 / h,
            wale_spacing: w,
            course_spacing: h,
            wale_samples: wale.1,
            course_samples: course.1,
        })
    }
}

impl StitchGrid {
    /// The swatch's own frame in `state`: the course direction (summed
    /// interlock-to-right-neighbour vectors), the wale direction
    /// (interlock-to-upper-neighbour, made orthogonal to the course) and
    /// the fabric normal. `None` without a grid, or where the sums vanish.
    pub fn frame(&self, state: &Fabric) -> Option<[Vec3; 3]> {
        if self.rows < 2 || self.cols < 2 || self.cells.values().flatten().any(|&n| n >= state.nodes.len()) {
            return None;
        }
        let (mut course, mut wale) = (Vec3::zeros(), Vec3::zeros());
        for &(r, c) in self.cells.keys() {
            let Some(here) = self.centre(state, (r, c)) else {
                continue;
            };
            if let Some(right) = self.centre(state, (r, c + 1)) {
                course += right - here;
            }
            if let Some(up) = self.centre(state, (r + 1, c)) {
                wale += up - here;
            }
        }
        let e1 = course.try_normalize(1e-300)?;
        let e2 = (wale - wale.dot(&e1) * e1).try_normalize(1e-300)?;
        let frame = [e1, e2, e1.cross(&e2)];
        frame.iter().all(|e| e.iter().all(|v| v.is_finite())).then_some(frame)
    }

    /// The finished size of `state` (m): the extents of every node along
    /// the swatch's own frame ([`StitchGrid::frame`]), i.e. width along the
    /// courses, height along the wales and depth across the fabric, as the
    /// swatch measures laid square on a table whichever way it has turned
    /// in space. `None` where there is no frame.
    pub fn extents(&self, state: &Fabric) -> Option<[f64; 3]> {
        let frame = self.frame(state)?;
        Some(frame.map(|axis| {
            let (lo, hi) = state
                .nodes
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), n| {
                    let t = n.x.dot(&axis);
                    (lo.min(t), hi.max(t))
                });
            (hi - lo).max(0.0)
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pattern::parse_str;
    use crate::topology::{compile, CompileOptions};

    fn lab_extents(f: &Fabric) -> [f64; 3] {
        [0, 1, 2].map(|k| {
            let (lo, hi) = f.nodes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), n| {
                (lo.min(n.x[k]), hi.max(n.x[k]))
            });
            hi - lo
        })
    }

    fn stockinette(w: usize, h: usize) -> Fabric {
        let text = format!(
            "name: s\ngauge: 20 sts x 25 rows / 10 cm\nyarn MC: #ffffff, radius 0.5 mm\nwidth: {w}\nheight: {h}\n\nlegend:\n  . = knit\n\nchart:\n  .\n"
        );
        let p = parse_str(&text, "s.knit").expect("pattern");
        compile(&p.pattern, &CompileOptions::default()).expect("compile")
    }

    #[test]
    fn the_compiled_grid_has_one_cell_per_stitch() {
        let f = stockinette(6, 5);
        let g = StitchGrid::of(&f);
        // Rows 1..=5 interlock with their parents; 6 columns.
        assert_eq!(g.size(), (5, 6));
        assert!(g.cells.values().all(|n| n.len() == 4));
    }

    #[test]
    fn the_finished_size_does_not_turn_with_the_swatch() {
        let f = stockinette(8, 6);
        let g = StitchGrid::of(&f);
        let flat = g.extents(&f).expect("frame");
        let lab = lab_extents(&f);
        for k in 0..3 {
            assert!((flat[k] - lab[k]).abs() < 1e-12, "axis {k}: {flat:?} vs {lab:?}");
        }
        // Turned 30 degrees about z and 50 about x: the lab box changes,
        // the size along courses, wales and normal does not.
        let rot = nalgebra::Rotation3::from_euler_angles(50f64.to_radians(), 0.0, 30f64.to_radians());
        let mut turned = f.clone();
        for n in &mut turned.nodes {
            n.x = rot * n.x + Vec3::new(0.3, -0.2, 0.1);
        }
        let size = g.extents(&turned).expect("frame");
        for k in 0..3 {
            assert!((size[k] - flat[k]).abs() < 1e-12, "axis {k}: {size:?} vs {flat:?}");
        }
        assert!((lab_extents(&turned)[0] - flat[0]).abs() > 1e-3);
    }

    #[test]
    fn a_slip_stitch_checkerboard_is_measured_across_its_gaps() {
        let text = "name: l\ngauge: 20 sts x 25 rows / 10 cm\nyarn MC: #ffffff, radius 0.5 mm\nwidth: 10\nheight: 10\n\nlegend:\n  . = knit\n  v = slip wyif\n\nchart:\n  . [v .] .\n  . [. v] .\n";
        let p = parse_str(text, "l.knit").expect("pattern");
        let linen = compile(&p.pattern, &CompileOptions::default()).expect("compile");
        let g = StitchGrid::of(&linen);
        let (rows, cols) = g.size();
        let empty = (0..rows)
            .flat_map(|r| (0..cols).map(move |c| (r, c)))
            .filter(|&(r, c)| g.cell(r, c).is_empty());
        assert!(empty.count() > rows * cols / 4, "slips leave empty cells");
        let linen_gauge = g.measure(&linen).expect("a checkerboard is measurable");
        let plain = stockinette(10, 10);
        let plain_gauge = StitchGrid::of(&plain).measure(&plain).expect("gauge");
        // Both are compiled on the pitch of the same gauge line.
        assert!((linen_gauge.wale_spacing - plain_gauge.wale_spacing).abs() < 1e-3 * plain_gauge.wale_spacing);
        assert!((linen_gauge.course_spacing - plain_gauge.course_spacing).abs() < 1e-3 * plain_gauge.course_spacing);
    }

    #[test]
    fn a_uniform_stretch_scales_the_measured_gauge() {
        let f = stockinette(8, 8);
        let g = StitchGrid::of(&f);
        let before = g.measure(&f).expect("gauge");
        let mut stretched = f.clone();
        for n in &mut stretched.nodes {
            n.x.x *= 2.0;
            n.x.y *= 0.5;
        }
        let after = g.measure(&stretched).expect("gauge");
        assert!((after.stitches_per_10cm - 0.5 * before.stitches_per_10cm).abs() < 1e-9);
        assert!((after.rows_per_10cm - 2.0 * before.rows_per_10cm).abs() < 1e-9);
    }

    #[test]
    fn rolling_the_swatch_into_a_tube_keeps_the_course_spacing() {
        // Wrap x onto a cylinder: the wale spacing becomes a chord, the
        // course spacing (along the axis) is unchanged.
        let f = stockinette(8, 8);
        let g = StitchGrid::of(&f);
        let flat = g.measure(&f).expect("gauge");
        let radius = 0.02;
        let mut rolled = f.clone();
        for n in &mut rolled.nodes {
            let phi = n.x.x / radius;
            n.x = Vec3::new(radius * phi.sin(), n.x.y, radius * (1.0 - phi.cos()));
        }
        let tube = g.measure(&rolled).expect("gauge");
        assert!((tube.course_spacing - flat.course_spacing).abs() < 1e-6 * flat.course_spacing);
        let chord = 2.0 * radius * (flat.wale_spacing / (2.0 * radius)).sin();
        assert!(
            (tube.wale_spacing - chord).abs() < 1e-2 * chord,
            "{} vs {chord}",
            tube.wale_spacing
        );
    }

    #[test]
    fn a_state_with_nan_has_no_gauge() {
        let f = stockinette(6, 6);
        let g = StitchGrid::of(&f);
        let mut bad = f.clone();
        for n in &mut bad.nodes {
            n.x.x = f64::NAN;
        }
        assert!(g.measure(&bad).is_none());
    }
}
