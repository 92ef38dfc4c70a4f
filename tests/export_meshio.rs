//! Read-back of the VTK and OBJ writers with an independent reader, meshio
//! (tests/python/check_mesh.py), on small synthetic fabrics and on every
//! shipped pattern file, with point and cell counts worked out here from
//! the formats' definitions.
//!
//! python3 with meshio is a test requirement (tests/python-requirements.txt):
//! without it these tests fail, unless KNITSIM_SKIP_PYTHON=1 says to skip.

use knitsim::io::{write_obj, write_vtk, ObjOptions, SmoothOptions, TubeOptions, VtkOptions};
use knitsim::pattern::{Construction, Gauge, Meta, YarnSpec};
use knitsim::topology::{Contact, ContactKind, Fabric, Node, PointRef, Vec3, Yarn, YarnPoint};
use std::path::Path;

mod common;
use std::process::Command;

const MM: f64 = 1e-3;

fn meta(yarns: usize) -> Meta {
    let colors = [[200, 30, 30], [30, 60, 200], [240, 200, 60]];
    Meta {
        name: "meshio read-back".into(),
        gauge: Gauge {
            stitches_per_10cm: 22.0,
            rows_per_10cm: 30.0,
        },
        yarns: (0..yarns)
            .map(|i| YarnSpec {
                name: format!("colour {i}"),
                color: colors[i % colors.len()],
                radius: (0.3 + 0.1 * i as f64) * MM,
                material: None,
            })
            .collect(),
        construction: Construction::Flat,
        width: 2,
        height: 2,
        looseness: 1.0,
    }
}

/// Adds a yarn of Lagrangian points through `xs` (in mm); returns its index.
fn add_yarn(f: &mut Fabric, spec: usize, xs: &[[f64; 3]]) -> usize {
    let mut u = 0.0;
    let mut points = Vec::new();
    for (i, x) in xs.iter().enumerate() {
        let x = Vec3::from(*x) * MM;
        if let Some(prev) = points.last().map(|p: &YarnPoint| f.nodes[p.node].x) {
            u += (x - prev).norm();
        }
        f.nodes.push(Node { x, pinned: false });
        points.push(YarnPoint {
            node: f.nodes.len() - 1,
            u,
            fixed_u: i == 0 || i + 1 == xs.len(),
            eil: false,
        });
    }
    f.yarns.push(Yarn {
        layer: 0,
        spec,
        rest_length: u,
        points,
    });
    f.yarns.len() - 1
}

/// Makes yarn point `b` share yarn point `a`'s node: an EoL contact.
fn join(f: &mut Fabric, a: PointRef, b: PointRef) {
    let node = f.yarns[a.yarn].points[a.point].node;
    f.yarns[b.yarn].points[b.point].node = node;
    f.contacts.push(Contact {
        node,
        front: a,
        back: b,
        kind: ContactKind::Stitch,
        partner: None,
    });
}

fn empty(specs: usize) -> Fabric {
    Fabric {
        meta: meta(specs),
        nodes: vec![],
        yarns: vec![],
        contacts: vec![],
        sim: None,
    }
}

/// Three yarns: a wavy course crossed by two legs, each leg sharing one
/// contact node with the course. Lagrangian and EoL points only.
fn three_yarns() -> Fabric {
    let mut f = empty(3);
    let course = add_yarn(
        &mut f,
        0,
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.5, 0.3],
            [2.0, 0.0, 0.0],
            [3.0, -0.5, -0.3],
            [4.0, 0.0, 0.0],
        ],
    );
    let leg_a = add_yarn(&mut f, 1, &[[1.0, -2.0, -0.5], [1.0, 0.5, 0.3], [1.2, 2.0, 0.5]]);
    let leg_b = add_yarn(&mut f, 2, &[[3.0, -2.0, 0.5], [3.0, -0.5, -0.3], [2.8, 2.0, -0.5]]);
    join(
        &mut f,
        PointRef { yarn: course, point: 1 },
        PointRef { yarn: leg_a, point: 1 },
    );
    join(
        &mut f,
        PointRef { yarn: course, point: 3 },
        PointRef { yarn: leg_b, point: 1 },
    );
    f
}

/// Two yarns with one contact, and an EIL point on the first yarn.
fn with_eil() -> Fabric {
    let mut f = empty(2);
    let a = add_yarn(
        &mut f,
        0,
        &[[0.0, 0.0, 0.0], [0.7, 0.1, 0.0], [1.5, 0.0, 0.2], [3.0, 0.0, 0.0]],
    );
    let b = add_yarn(&mut f, 1, &[[1.5, -1.5, 0.0], [1.5, 0.0, 0.2], [1.5, 1.5, 0.0]]);
    join(&mut f, PointRef { yarn: a, point: 2 }, PointRef { yarn: b, point: 1 });
    f.yarns[a].points[1].eil = true;
    f
}

fn point_counts(f: &Fabric) -> Vec<usize> {
    f.yarns.iter().map(|y| y.points.len()).collect()
}

/// Runs check_mesh.py; `None` when skipping is allowed and python/meshio is
/// missing. Returns the JSON summary it prints.
fn check_mesh(path: &Path, points: usize, cells: usize, cell_type: &str, extra: &[&str]) -> Option<serde_json::Value> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python/check_mesh.py");
    let output = Command::new("python3")
        .arg(&script)
        .arg(path)
        .arg(points.to_string())
        .arg(cells.to_string())
        .args(["--cell-type", cell_type])
        .args(extra)
        .output();
    let skip = std::env::var("KNITSIM_SKIP_PYTHON").is_ok_and(|v| v == "1");
    let output = match output {
        Ok(o) => o,
        Err(e) if skip => {
            eprintln!("KNITSIM_SKIP_PYTHON=1: skipping meshio read-back (python3 not runnable: {e})");
            return None;
        }
        Err(e) => panic!("python3 is required for the meshio read-back ({e}); set KNITSIM_SKIP_PYTHON=1 to skip"),
    };
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    match output.status.code() {
        Some(0) => Some(serde_json::from_str(&stdout).expect("check_mesh.py prints JSON")),
        Some(2) if stdout.contains("not installed") && skip => {
            eprintln!("KNITSIM_SKIP_PYTHON=1: skipping meshio read-back: {stdout}");
            None
        }
        Some(2) if stdout.contains("not installed") => {
            panic!("{stdout}\nmeshio is required for this test; set KNITSIM_SKIP_PYTHON=1 to skip")
        }
        _ => panic!("meshio read-back of {} failed:\n{stdout}{stderr}", path.display()),
    }
}

fn check_vtk(fabric: &Fabric, name: &str) -> Option<serde_json::Value> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    write_vtk(fabric, &path, &VtkOptions::default()).unwrap();
    let counts = point_counts(fabric);
    // One point per yarn point; one 2-point line per consecutive pair.
    let points: usize = counts.iter().sum();
    let cells: usize = counts.iter().map(|n| n - 1).sum();
    let fields = [
        "--point-data",
        "yarn_id",
        "--point-data",
        "node_kind",
        "--point-data",
        "u",
        "--cell-data",
        "yarn_id",
        "--cell-data",
        "yarn_color",
    ];
    check_mesh(&path, points, cells, "line", &fields)
}

fn check_obj(fabric: &Fabric, sides: usize, samples_per_segment: usize) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tubes.obj");
    let options = ObjOptions {
        tube: TubeOptions { sides, caps: true },
        smooth: SmoothOptions {
            samples_per_segment,
            ..SmoothOptions::default()
        },
    };
    write_obj(fabric, &path, &options).unwrap();
    assert!(dir.path().join("tubes.mtl").is_file());
    // Per yarn of n points: s (n - 1) + 1 rings of `sides` vertices, and two
    // caps of one centre plus a ring copy; triangles: two per ring-to-ring
    // quad, `sides` per cap.
    let (mut vertices, mut triangles) = (0, 0);
    for n in point_counts(fabric) {
        let rings = samples_per_segment * (n - 1) + 1;
        vertices += rings * sides + 2 * (1 + sides);
        triangles += 2 * (rings - 1) * sides + 2 * sides;
    }
    check_mesh(&path, vertices, triangles, "triangle", &["--point-data", "obj:vn"]);
}

#[test]
fn vtk_of_three_yarns_with_contacts_reads_back() {
    let Some(summary) = check_vtk(&three_yarns(), "three.vtk") else {
        return;
    };
    // 5 + 3 + 3 points; the two contacts appear once per yarn: 4 EoL points.
    let kinds = &summary["point_data_histograms"]["node_kind"];
    assert_eq!(kinds["0"], 7, "{summary}");
    assert_eq!(kinds["1"], 4, "{summary}");
    assert_eq!(summary["cell_data_shapes"]["yarn_color"][0][1], 3);
}

#[test]
fn vtk_with_an_eil_point_reads_back() {
    let Some(summary) = check_vtk(&with_eil(), "eil.vtk") else {
        return;
    };
    let kinds = &summary["point_data_histograms"]["node_kind"];
    assert_eq!(
        (&kinds["0"], &kinds["1"], &kinds["2"]),
        (&4.into(), &2.into(), &1.into()),
        "{summary}"
    );
    assert_eq!(summary["point_data_histograms"]["yarn_id"]["1"], 3);
}

#[test]
fn every_shipped_pattern_reads_back() {
    // Both files of each compiled pattern (the starting geometry that
    // `knitsim export PATTERN --vtk --obj` writes); coarse tubes keep the
    // OBJ files small, the counting is the same at any resolution.
    for (name, p) in common::shipped_patterns() {
        let f = knitsim::topology::compile(&p, &knitsim::topology::CompileOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let Some(summary) = check_vtk(&f, &format!("{name}.vtk")) else {
            return;
        };
        // Every contact node is listed once per yarn through it: twice.
        let eol_points = summary["point_data_histograms"]["node_kind"]["1"].as_u64().unwrap_or(0);
        assert_eq!(eol_points as usize, 2 * f.contacts.len(), "{name}: {summary}");
        check_obj(&f, 6, 2);
        println!("{name}: VTK and OBJ read back");
    }
}

#[test]
fn obj_tubes_read_back_with_expected_counts() {
    check_obj(&three_yarns(), 8, 4);
    check_obj(&with_eil(), 5, 1);
    check_obj(&with_eil(), 12, 3);
}

/// A frame of a dynamic run (`.vtu`, the files `drape.pvd` lists) reads
/// back with the points, line cells and fields of the legacy file.
#[test]
fn vtu_frames_read_back() {
    for (fabric, name) in [(three_yarns(), "three.vtu"), (with_eil(), "eil.vtu")] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        knitsim::io::write_vtu(&fabric, &path).unwrap();
        let counts = point_counts(&fabric);
        let points: usize = counts.iter().sum();
        let cells: usize = counts.iter().map(|n| n - 1).sum();
        let fields = [
            "--point-data",
            "yarn_id",
            "--point-data",
            "node_kind",
            "--point-data",
            "u",
            "--cell-data",
            "yarn_id",
        ];
        check_mesh(&path, points, cells, "line", &fields);
    }
}

/// Obstacles drawn as triangles (`obstacles.vtu`) read back.
#[test]
fn obstacle_triangles_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("obstacles.vtu");
    let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    knitsim::io::write_triangles_vtu(&points, &[[0, 1, 2], [0, 2, 3]], &[0, 1], &path).unwrap();
    check_mesh(&path, 4, 2, "triangle", &["--cell-data", "obstacle_id"]);
}
