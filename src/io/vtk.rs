//! Legacy ASCII VTK: yarn centre lines with per-point kind and `u`.
//!
//! Dataset choice, checked against meshio 5.3.5 (the project's read-back
//! reference): meshio's legacy reader rejects `DATASET POLYDATA` outright
//! and rejects `VTK_POLY_LINE` (type 4) cells, while ParaView reads all of
//! them. So the default is an `UNSTRUCTURED_GRID` of `VTK_LINE` (type 3)
//! cells, one per centre-line segment, which both read; meshio sees them as
//! `line` cells. [`VtkCells::Polylines`] writes one `VTK_POLY_LINE` per yarn
//! instead, for ParaView's Tube filter, which then draws continuous tubes
//! without joints; meshio cannot read that variant.
//!
//! Contact nodes are written once per yarn point (two coincident points),
//! so that every point belongs to exactly one yarn and `yarn_id`/`u` are
//! well defined per point.
//!
//! Fields: POINT_DATA `yarn_id` (int), `node_kind` (int: 0 Lagrangian,
//! 1 EoL, 2 EIL, the values of [`NodeKind`]), `u` (double); CELL_DATA
//! `yarn_id` (int) and `yarn_color` (3 floats in `[0, 1]`, sRGB; as
//! a 3-component SCALARS array because meshio skips COLOR_SCALARS).

use super::validate::check_structure;
use super::{write_atomic, IoError};
use crate::topology::{Fabric, NodeKind, YarnCurve};
use std::io::{self, Write};
use std::path::Path;

/// VTK cell type ids (VTK file formats document, "cell types").
const VTK_LINE: u8 = 3;
const VTK_POLY_LINE: u8 = 4;

/// How centre lines become cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VtkCells {
    /// One 2-point line cell per segment: ParaView and meshio.
    #[default]
    Segments,
    /// One polyline cell per yarn (yarns with at least 2 points): ParaView only.
    Polylines,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VtkOptions {
    pub cells: VtkCells,
}

/// Writes the fabric's centre lines to `path` (atomically).
pub fn write_vtk(fabric: &Fabric, path: &Path, options: &VtkOptions) -> Result<(), IoError> {
    check_structure(fabric).map_err(|source| IoError::Export {
        path: path.to_path_buf(),
        source,
    })?;
    let curves = fabric.curves();
    write_atomic(path, |w| write_vtk_to(w, fabric, &curves, options))
}

/// A cell: the yarn it belongs to and its point indices.
struct Cell {
    yarn: usize,
    points: Vec<usize>,
}

fn cells(curves: &[YarnCurve], style: VtkCells) -> Vec<Cell> {
    let mut out = Vec::new();
    let mut first = 0;
    for c in curves {
        let n = c.points.len();
        match style {
            VtkCells::Segments => out.extend((1..n).map(|i| Cell {
                yarn: c.yarn,
                points: vec![first + i - 1, first + i],
            })),
            VtkCells::Polylines if n >= 2 => out.push(Cell {
                yarn: c.yarn,
                points: (first..first + n).collect(),
            }),
            VtkCells::Polylines => {}
        }
        first += n;
    }
    out
}

fn write_vtk_to(w: &mut dyn Write, fabric: &Fabric, curves: &[YarnCurve], options: &VtkOptions) -> io::Result<()> {
    // The title line must be one line of at most 256 characters.
    let title: String = format!("knitsim fabric: {}", fabric.meta.name)
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .take(255)
        .collect();
    writeln!(
        w,
        "# vtk DataFile Version 3.0\n{title}\nASCII\nDATASET UNSTRUCTURED_GRID"
    )?;

    let points: Vec<_> = curves.iter().flat_map(|c| c.points.iter()).collect();
    writeln!(w, "POINTS {} double", points.len())?;
    for p in &points {
        writeln!(w, "{:e} {:e} {:e}", p.x.x, p.x.y, p.x.z)?;
    }

    let cells = cells(curves, options.cells);
    let cell_type = match options.cells {
        VtkCells::Segments => VTK_LINE,
        VtkCells::Polylines => VTK_POLY_LINE,
    };
    let list_size: usize = cells.iter().map(|c| c.points.len() + 1).sum();
    writeln!(w, "CELLS {} {list_size}", cells.len())?;
    for c in &cells {
        write!(w, "{}", c.points.len())?;
        for i in &c.points {
            write!(w, " {i}")?;
        }
        writeln!(w)?;
    }
    writeln!(w, "CELL_TYPES {}", cells.len())?;
    for _ in &cells {
        writeln!(w, "{cell_type}")?;
    }

    if !points.is_empty() {
        writeln!(w, "POINT_DATA {}", points.len())?;
        let yarn_of_point = curves.iter().flat_map(|c| c.points.iter().map(move |_| c.yarn));
        write_scalars(w, "yarn_id", "int", yarn_of_point)?;
        write_scalars(w, "node_kind", "int", points.iter().map(|p| kind_code(p.kind)))?;
        write_scalars(w, "u", "double", points.iter().map(|p| p.u))?;
    }
    if !cells.is_empty() {
        writeln!(w, "CELL_DATA {}", cells.len())?;
        write_scalars(w, "yarn_id", "int", cells.iter().map(|c| c.yarn))?;
        writeln!(w, "SCALARS yarn_color float 3\nLOOKUP_TABLE default")?;
        for c in &cells {
            let spec = fabric.yarns[c.yarn].spec;
            let [r, g, b] = fabric.meta.yarns[spec].color.map(|v| f32::from(v) / 255.0);
            writeln!(w, "{r} {g} {b}")?;
        }
    }
    Ok(())
}

fn kind_code(kind: NodeKind) -> u8 {
    kind as u8
}

fn write_scalars<T: std::fmt::Display>(
    w: &mut dyn Write,
    name: &str,
    vtk_type: &str,
    values: impl Iterator<Item = T>,
) -> io::Result<()> {
    writeln!(w, "SCALARS {name} {vtk_type} 1\nLOOKUP_TABLE default")?;
    for v in values {
        writeln!(w, "{v}")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::fixtures::crossing;

    fn write_to_string(fabric: &Fabric, options: VtkOptions) -> String {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.vtk");
        write_vtk(fabric, &path, &options).unwrap();
        std::fs::read_to_string(&path).unwrap()
    }

    /// Lines after the header line `header` (exactly `count` of them).
    fn section<'a>(text: &'a str, header: &str, count: usize) -> Vec<&'a str> {
        let lines: Vec<&str> = text.lines().collect();
        let start = lines
            .iter()
            .position(|l| *l == header)
            .unwrap_or_else(|| panic!("missing {header:?}"));
        lines[start + 1..start + 1 + count].to_vec()
    }

    #[test]
    fn header_and_sections_are_well_formed() {
        // crossing(): 4 + 3 yarn points, 3 + 2 segments.
        let text = write_to_string(&crossing(), VtkOptions::default());
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "# vtk DataFile Version 3.0");
        assert!(lines[1].contains("fixture"));
        assert_eq!(lines[2], "ASCII");
        assert_eq!(lines[3], "DATASET UNSTRUCTURED_GRID");

        let pts = section(&text, "POINTS 7 double", 7);
        assert!(pts.iter().all(|l| l.split_whitespace().count() == 3));
        // The contact is written once per yarn: point 2 (yarn 0) and point 5 (yarn 1).
        assert_eq!(pts[2], pts[5]);

        let cells = section(&text, "CELLS 5 15", 5);
        assert_eq!(cells, vec!["2 0 1", "2 1 2", "2 2 3", "2 4 5", "2 5 6"]);
        assert_eq!(section(&text, "CELL_TYPES 5", 5), vec!["3"; 5]);

        assert!(text.contains("POINT_DATA 7\n"));
        let kinds = section(&text, "SCALARS node_kind int 1", 8);
        // LOOKUP_TABLE line, then: end, EIL, contact, end | end, contact, end.
        assert_eq!(kinds[1..], ["0", "2", "1", "0", "0", "1", "0"]);
        let yarn_ids = section(&text, "SCALARS yarn_id int 1", 8);
        assert_eq!(yarn_ids[1..], ["0", "0", "0", "0", "1", "1", "1"]);

        assert!(text.contains("CELL_DATA 5\n"));
        let colors = section(&text, "SCALARS yarn_color float 3", 6);
        let red: Vec<f32> = colors[1].split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert_eq!(red, vec![200.0 / 255.0, 30.0 / 255.0, 30.0 / 255.0]);
        assert_eq!(colors[4], colors[5], "both segments of yarn 1");
    }

    #[test]
    fn polylines_are_one_cell_per_yarn() {
        let options = VtkOptions {
            cells: VtkCells::Polylines,
        };
        let text = write_to_string(&crossing(), options);
        assert_eq!(section(&text, "CELLS 2 9", 2), vec!["4 0 1 2 3", "3 4 5 6"]);
        assert_eq!(section(&text, "CELL_TYPES 2", 2), vec!["4", "4"]);
    }

    #[test]
    fn points_and_u_are_written_exactly() {
        let fabric = crossing();
        let text = write_to_string(&fabric, VtkOptions::default());
        let pts = section(&text, "POINTS 7 double", 7);
        let first: Vec<f64> = pts[1].split_whitespace().map(|v| v.parse().unwrap()).collect();
        // The EIL point is interpolated between its neighbours: (1 mm, 0, 0).
        assert_eq!(first, vec![1e-3, 0.0, 0.0]);
        let u = section(&text, "SCALARS u double 1", 8);
        let u3: f64 = u[4].parse().unwrap();
        assert_eq!(u3, fabric.yarns[0].points[3].u);
    }

    #[test]
    fn dangling_spec_is_an_error_and_writes_nothing() {
        let mut fabric = crossing();
        fabric.yarns[1].spec = 9;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.vtk");
        let err = write_vtk(&fabric, &path, &VtkOptions::default()).unwrap_err();
        assert!(err.to_string().contains("yarn spec 9"), "{err}");
        assert!(!path.exists());
    }
}
