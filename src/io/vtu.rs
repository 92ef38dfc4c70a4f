//! VTK XML unstructured grids (`.vtu`, ASCII) and ParaView collections
//! (`.pvd`): the frames of a dynamic run and the obstacles around it.
//!
//! A fabric is written as [`vtk`](super::vtk) writes it (one `VTK_LINE`
//! cell per centre-line segment, contact nodes once per yarn, point data
//! `yarn_id`, `node_kind`, `u`, cell data `yarn_id`), because ParaView's
//! `.pvd` reader opens only XML files: a `.pvd` lists one `.vtu` per frame
//! with its time, and ParaView plays them as an animation. meshio reads
//! the same files. Triangle meshes (obstacles) use `VTK_TRIANGLE` cells.

use super::validate::check_structure;
use super::{write_atomic, IoError};
use crate::topology::Fabric;
use std::io::{self, Write};
use std::path::Path;

const VTK_LINE: u8 = 3;
const VTK_TRIANGLE: u8 = 5;

/// Writes the fabric's centre lines to `path` as `.vtu` (atomically).
pub fn write_vtu(fabric: &Fabric, path: &Path) -> Result<(), IoError> {
    check_structure(fabric).map_err(|source| IoError::Export {
        path: path.to_path_buf(),
        source,
    })?;
    let curves = fabric.curves();
    let mut points = Vec::new();
    let mut yarn_of_point = Vec::new();
    let mut kinds = Vec::new();
    let mut us = Vec::new();
    let mut cells: Vec<Vec<usize>> = Vec::new();
    let mut cell_yarn = Vec::new();
    for c in &curves {
        let first = points.len();
        for (i, p) in c.points.iter().enumerate() {
            points.push([p.x.x, p.x.y, p.x.z]);
            yarn_of_point.push(c.yarn);
            kinds.push(p.kind as u8);
            us.push(p.u);
            if i > 0 {
                cells.push(vec![first + i - 1, first + i]);
                cell_yarn.push(c.yarn);
            }
        }
    }
    write_atomic(path, |w| {
        let grid = Grid {
            points: &points,
            cells: &cells,
            cell_type: VTK_LINE,
        };
        grid.write(
            w,
            |w| {
                int_array(w, "yarn_id", yarn_of_point.iter().map(|v| *v as i64))?;
                int_array(w, "node_kind", kinds.iter().map(|v| *v as i64))?;
                float_array(w, "u", us.iter().copied())
            },
            |w| int_array(w, "yarn_id", cell_yarn.iter().map(|v| *v as i64)),
        )
    })
}

/// Writes a triangle mesh to `path` as `.vtu` (atomically), with cell data
/// `obstacle_id`.
pub fn write_triangles_vtu(
    points: &[[f64; 3]],
    triangles: &[[usize; 3]],
    ids: &[usize],
    path: &Path,
) -> Result<(), IoError> {
    let cells: Vec<Vec<usize>> = triangles.iter().map(|t| t.to_vec()).collect();
    write_atomic(path, |w| {
        Grid {
            points,
            cells: &cells,
            cell_type: VTK_TRIANGLE,
        }
        .write(
            w,
            |_| Ok(()),
            |w| int_array(w, "obstacle_id", ids.iter().map(|v| *v as i64)),
        )
    })
}

/// One `.pvd` entry: a time and a file name relative to the `.pvd`.
#[derive(Clone, Debug, PartialEq)]
pub struct PvdEntry {
    pub time: f64,
    pub file: String,
}

/// Writes a ParaView collection of `entries` to `path` (atomically).
pub fn write_pvd(entries: &[PvdEntry], path: &Path) -> Result<(), IoError> {
    write_atomic(path, |w| {
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">"
        )?;
        writeln!(w, "  <Collection>")?;
        for e in entries {
            writeln!(
                w,
                "    <DataSet timestep=\"{:e}\" group=\"\" part=\"0\" file=\"{}\"/>",
                e.time,
                xml_escape(&e.file)
            )?;
        }
        writeln!(w, "  </Collection>\n</VTKFile>")
    })
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

struct Grid<'a> {
    points: &'a [[f64; 3]],
    cells: &'a [Vec<usize>],
    cell_type: u8,
}

type Arrays<'a> = &'a dyn Fn(&mut dyn Write) -> io::Result<()>;

impl Grid<'_> {
    fn write(
        &self,
        w: &mut dyn Write,
        point_data: impl Fn(&mut dyn Write) -> io::Result<()>,
        cell_data: impl Fn(&mut dyn Write) -> io::Result<()>,
    ) -> io::Result<()> {
        let (point_data, cell_data): (Arrays, Arrays) = (&point_data, &cell_data);
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">"
        )?;
        writeln!(w, "<UnstructuredGrid>")?;
        writeln!(
            w,
            "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
            self.points.len(),
            self.cells.len()
        )?;
        writeln!(w, "<PointData>")?;
        point_data(w)?;
        writeln!(w, "</PointData>\n<CellData>")?;
        cell_data(w)?;
        writeln!(w, "</CellData>\n<Points>")?;
        writeln!(
            w,
            "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
        )?;
        for p in self.points {
            writeln!(w, "{:e} {:e} {:e}", p[0], p[1], p[2])?;
        }
        writeln!(w, "</DataArray>\n</Points>\n<Cells>")?;
        writeln!(w, "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">")?;
        for c in self.cells {
            let s: Vec<String> = c.iter().map(|i| i.to_string()).collect();
            writeln!(w, "{}", s.join(" "))?;
        }
        writeln!(
            w,
            "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
        )?;
        let mut off = 0;
        for c in self.cells {
            off += c.len();
            writeln!(w, "{off}")?;
        }
        writeln!(
            w,
            "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
        )?;
        for _ in self.cells {
            writeln!(w, "{}", self.cell_type)?;
        }
        writeln!(w, "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>")
    }
}

fn int_array(w: &mut dyn Write, name: &str, values: impl Iterator<Item = i64>) -> io::Result<()> {
    writeln!(w, "<DataArray type=\"Int32\" Name=\"{name}\" format=\"ascii\">")?;
    for v in values {
        writeln!(w, "{v}")?;
    }
    writeln!(w, "</DataArray>")
}

fn float_array(w: &mut dyn Write, name: &str, values: impl Iterator<Item = f64>) -> io::Result<()> {
    writeln!(w, "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">")?;
    for v in values {
        writeln!(w, "{v:e}")?;
    }
    writeln!(w, "</DataArray>")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::fixtures::crossing;

    #[test]
    fn a_fabric_frame_has_its_points_cells_and_fields() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.vtu");
        write_vtu(&crossing(), &path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        // crossing(): 4 + 3 yarn points, 3 + 2 segments.
        assert!(text.contains("NumberOfPoints=\"7\" NumberOfCells=\"5\""), "{text}");
        assert!(text.contains("Name=\"node_kind\"") && text.contains("Name=\"u\""));
        let offsets = text.split("Name=\"offsets\" format=\"ascii\">\n").nth(1).unwrap();
        let offsets: Vec<&str> = offsets.lines().take(5).collect();
        assert_eq!(offsets, ["2", "4", "6", "8", "10"]);
    }

    #[test]
    fn a_collection_lists_files_with_times() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.pvd");
        let entries = [
            PvdEntry {
                time: 0.0,
                file: "frames/frame_0000.vtu".into(),
            },
            PvdEntry {
                time: 0.02,
                file: "frames/frame_0001.vtu".into(),
            },
        ];
        write_pvd(&entries, &path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.matches("<DataSet ").count(), 2);
        assert!(
            text.contains("timestep=\"2e-2\"") && text.contains("file=\"frames/frame_0001.vtu\""),
            "{text}"
        );
    }
}
