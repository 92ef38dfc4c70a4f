//! Wavefront OBJ tube meshes, one object per yarn, with an MTL file of yarn
//! colours.
//!
//! Each yarn's centre line is smoothed ([`smooth`](super::smooth)), then
//! wrapped in a capped tube of the yarn radius ([`tube`](super::tube)). Each
//! yarn becomes `o yarn_<i>` plus `g yarn_<i>` (Blender splits objects on
//! `o`, meshio and most other readers split groups on `g`) and selects the
//! material of its yarn spec with `usemtl`. Faces are `f v//vn` with equal
//! indices, since the tube has exactly one normal per vertex.
//!
//! The MTL file sits next to the OBJ (`<stem>.mtl`) and is written first,
//! each atomically: an OBJ on disk therefore never references a missing
//! material library. MTL `Kd` takes the sRGB colour divided by 255, which is
//! how viewers interpret it in practice.

use super::smooth::{smooth_centre_line, SmoothOptions};
use super::tube::{tube_around, TubeOptions};
use super::validate::check_drawable;
use super::{write_atomic, IoError};
use crate::pattern::YarnSpec;
use crate::topology::{Fabric, Vec3};
use std::io::{self, Write};
use std::path::Path;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ObjOptions {
    pub tube: TubeOptions,
    pub smooth: SmoothOptions,
}

/// Writes `path` (the OBJ) and `path` with extension `mtl`, both atomically.
pub fn write_obj(fabric: &Fabric, path: &Path, options: &ObjOptions) -> Result<(), IoError> {
    let invalid = |source| IoError::Export {
        path: path.to_path_buf(),
        source,
    };
    check_drawable(fabric).map_err(invalid)?;
    let mtl_path = path.with_extension("mtl");
    // OBJ refers to the library by bare file name, relative to itself.
    let mtl_name = mtl_path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "yarns.mtl".into());
    write_atomic(&mtl_path, |w| write_mtl(w, &fabric.meta.yarns))?;
    write_atomic(path, |w| write_obj_to(w, fabric, &mtl_name, options))
}

/// Material name of yarn spec `index`: unique by the index, readable by the
/// spec name with everything but `[A-Za-z0-9_-]` replaced (MTL names end at
/// whitespace).
pub fn material_name(index: usize, spec: &YarnSpec) -> String {
    let clean: String = spec
        .name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' { c } else { '_' })
        .collect();
    format!("yarn{index}_{clean}")
}

fn write_mtl(w: &mut dyn Write, specs: &[YarnSpec]) -> io::Result<()> {
    writeln!(w, "# knitsim yarn materials")?;
    for (i, spec) in specs.iter().enumerate() {
        let [r, g, b] = spec.color.map(|c| f64::from(c) / 255.0);
        writeln!(w, "\nnewmtl {}", material_name(i, spec))?;
        writeln!(
            w,
            "Ka 0 0 0\nKd {r:.6} {g:.6} {b:.6}\nKs 0.04 0.04 0.04\nNs 16\nd 1\nillum 2"
        )?;
    }
    Ok(())
}

fn write_obj_to(w: &mut dyn Write, fabric: &Fabric, mtl_name: &str, options: &ObjOptions) -> io::Result<()> {
    writeln!(w, "# knitsim fabric: {}", fabric.meta.name.replace(['\n', '\r'], " "))?;
    writeln!(w, "mtllib {mtl_name}")?;
    // OBJ indices are global and 1-based.
    let mut first_vertex = 1;
    for curve in fabric.curves() {
        let spec = &fabric.meta.yarns[curve.spec];
        let points: Vec<Vec3> = curve.points.iter().map(|p| p.x).collect();
        let centre = smooth_centre_line(&points, spec.radius, &options.smooth);
        let mesh = tube_around(&centre, spec.radius, &options.tube);
        if mesh.triangles.is_empty() {
            continue;
        }
        writeln!(w, "o yarn_{0}\ng yarn_{0}", curve.yarn)?;
        writeln!(w, "usemtl {}", material_name(curve.spec, spec))?;
        for p in &mesh.positions {
            writeln!(w, "v {:e} {:e} {:e}", p.x, p.y, p.z)?;
        }
        for n in &mesh.normals {
            writeln!(w, "vn {:.6} {:.6} {:.6}", n.x, n.y, n.z)?;
        }
        for tri in &mesh.triangles {
            let [a, b, c] = tri.map(|i| i + first_vertex);
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
        }
        first_vertex += mesh.positions.len();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::fixtures::{crossing, meta, push_yarn};

    struct ParsedObj {
        vertices: Vec<Vec3>,
        normals: usize,
        faces: Vec<[usize; 3]>,
        groups: Vec<String>,
        materials: Vec<String>,
    }

    fn parse_obj(text: &str) -> ParsedObj {
        let mut p = ParsedObj {
            vertices: vec![],
            normals: 0,
            faces: vec![],
            groups: vec![],
            materials: vec![],
        };
        for line in text.lines() {
            let mut it = line.split_whitespace();
            match it.next() {
                Some("v") => {
                    let c: Vec<f64> = it.map(|s| s.parse().unwrap()).collect();
                    p.vertices.push(Vec3::new(c[0], c[1], c[2]));
                }
                Some("vn") => p.normals += 1,
                Some("f") => {
                    let idx: Vec<usize> = it.map(|s| s.split('/').next().unwrap().parse().unwrap()).collect();
                    p.faces.push([idx[0], idx[1], idx[2]]);
                }
                Some("g") => p.groups.push(it.next().unwrap().to_string()),
                Some("usemtl") => p.materials.push(it.next().unwrap().to_string()),
                _ => {}
            }
        }
        p
    }

    fn distance_to_segment(p: &Vec3, a: &Vec3, b: &Vec3) -> f64 {
        let ab = b - a;
        let s = ((p - a).dot(&ab) / ab.dot(&ab)).clamp(0.0, 1.0);
        (p - (a + ab * s)).norm()
    }

    #[test]
    fn writes_groups_materials_and_mtl() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.obj");
        write_obj(&crossing(), &path, &ObjOptions::default()).unwrap();
        let obj = parse_obj(&std::fs::read_to_string(&path).unwrap());
        assert_eq!(obj.groups, vec!["yarn_0", "yarn_1"]);
        assert_eq!(obj.materials, vec!["yarn0_yarn_0", "yarn1_yarn_1"]);
        assert_eq!(obj.normals, obj.vertices.len());
        assert!(obj.faces.iter().flatten().all(|&i| i >= 1 && i <= obj.vertices.len()));

        let mtl = std::fs::read_to_string(dir.path().join("f.mtl")).unwrap();
        assert!(mtl.contains("newmtl yarn0_yarn_0\n"));
        // Yarn 1 is (30, 60, 200).
        assert!(mtl.contains(&format!(
            "Kd {:.6} {:.6} {:.6}",
            30.0 / 255.0,
            60.0 / 255.0,
            200.0 / 255.0
        )));
    }

    #[test]
    fn tube_vertices_are_at_yarn_radius_from_a_straight_centre_line() {
        // Unevenly spaced collinear points: the smoothed line stays on the
        // line, so every side vertex is exactly `radius` from it, and cap
        // centres lie on it.
        let radius = 0.7e-3;
        let mut fabric = crossing();
        fabric.meta = meta(&[([10, 200, 10], radius)]);
        fabric.yarns.clear();
        fabric.contacts.clear();
        fabric.nodes.clear();
        let dir = Vec3::new(1.0, -2.0, 0.5).normalize() * 1e-3;
        let (a, b) = (dir * 0.0, dir * 9.0);
        push_yarn(&mut fabric, 0, &[a, dir * 0.5, dir * 4.0, dir * 4.2, b]);
        let dirpath = tempfile::tempdir().unwrap();
        let path = dirpath.path().join("line.obj");
        let options = ObjOptions::default();
        write_obj(&fabric, &path, &options).unwrap();
        let obj = parse_obj(&std::fs::read_to_string(&path).unwrap());

        let k = options.tube.sides;
        let samples = 4 * options.smooth.samples_per_segment + 1;
        assert_eq!(obj.vertices.len(), samples * k + 2 * (k + 1));
        let side = &obj.vertices[..samples * k];
        for v in side {
            let d = distance_to_segment(v, &a, &b);
            assert!(
                (d - radius).abs() < 1e-9 * radius.max(1.0),
                "distance {d} vs radius {radius}"
            );
        }
        let cap_centres = [obj.vertices[samples * k], obj.vertices[samples * k + k + 1]];
        assert!((cap_centres[0] - a).norm() < 1e-15 && (cap_centres[1] - b).norm() < 1e-15);
    }

    #[test]
    fn tube_follows_a_curved_yarn_at_yarn_radius() {
        // Points on a circle of radius R: the tube surface is a torus piece,
        // every side vertex near distance r from the circle. The two end spans
        // are left out: their mirrored phantom points straighten them by design.
        let (big_r, r) = (10e-3, 0.5e-3);
        let mut fabric = crossing();
        fabric.meta = meta(&[([10, 200, 10], r)]);
        fabric.yarns.clear();
        fabric.contacts.clear();
        fabric.nodes.clear();
        let pts: Vec<Vec3> = (0..=16)
            .map(|i| {
                let a = i as f64 / 16.0 * std::f64::consts::PI;
                Vec3::new(big_r * a.cos(), big_r * a.sin(), 0.0)
            })
            .collect();
        push_yarn(&mut fabric, 0, &pts);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("arc.obj");
        write_obj(&fabric, &path, &ObjOptions::default()).unwrap();
        let obj = parse_obj(&std::fs::read_to_string(&path).unwrap());
        let options = ObjOptions::default();
        let (k, per_span) = (options.tube.sides, options.smooth.samples_per_segment);
        let side_count = obj.vertices.len() - 2 * (k + 1);
        assert_eq!(side_count, (16 * per_span + 1) * k);
        for v in &obj.vertices[per_span * k..side_count - per_span * k] {
            let in_plane = (v.x * v.x + v.y * v.y).sqrt();
            let to_circle = ((in_plane - big_r).powi(2) + v.z * v.z).sqrt();
            assert!((to_circle - r).abs() < 1e-3 * r, "distance {to_circle} vs {r}");
        }
    }

    #[test]
    fn zero_radius_is_rejected_before_writing() {
        let mut fabric = crossing();
        fabric.meta.yarns[0].radius = 0.0;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.obj");
        let err = write_obj(&fabric, &path, &ObjOptions::default()).unwrap_err();
        assert!(err.to_string().contains("radius"), "{err}");
        assert!(!path.exists() && !dir.path().join("f.mtl").exists());
    }
}
