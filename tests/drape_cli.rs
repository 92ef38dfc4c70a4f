//! `knitsim drape` end to end: the files it writes (frames, the `.pvd`
//! collection, the final state, obstacles, `energy.csv`, `summary.json`),
//! the shipped example scenes, the scene errors of the `dynamics` section,
//! and the default scene on a shipped pattern (small in CI, full size
//! ignored: see its doc).

mod contact_support;
mod drape_support;

use drape_support::woven_patch;
use std::path::Path;
use std::process::Command;

fn knitsim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_knitsim"))
}

/// Runs tests/python/check_mesh.py on a frame; skips when
/// KNITSIM_SKIP_PYTHON=1 and python or meshio is missing.
fn meshio_reads(path: &Path, points: usize, cells: usize) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python/check_mesh.py");
    let skip = std::env::var("KNITSIM_SKIP_PYTHON").is_ok_and(|v| v == "1");
    let out = match Command::new("python3")
        .arg(&script)
        .arg(path)
        .arg(points.to_string())
        .arg(cells.to_string())
        .args(["--cell-type", "line", "--point-data", "u"])
        .output()
    {
        Ok(o) => o,
        Err(_) if skip => return,
        Err(e) => panic!("python3 is required for the meshio read-back ({e}); set KNITSIM_SKIP_PYTHON=1 to skip"),
    };
    let stdout = String::from_utf8_lossy(&out.stdout);
    if out.status.code() == Some(2) && stdout.contains("not installed") && skip {
        return;
    }
    assert!(out.status.success(), "meshio cannot read {}: {stdout}", path.display());
}

/// The frames listed in a `.pvd`: (time, file).
fn pvd_frames(path: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| l.contains("<DataSet "))
        .map(|l| {
            let attr = |name: &str| {
                let from = l.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                l[from..from + l[from..].find('"').unwrap()].to_string()
            };
            (attr("timestep").parse().unwrap(), attr("file"))
        })
        .collect()
}

#[test]
fn drape_writes_frames_a_collection_and_the_final_state() {
    let dir = tempfile::tempdir().unwrap();
    let state = dir.path().join("patch.json");
    knitsim::io::save_json(&woven_patch(), &state).unwrap();
    let scene = dir.path().join("scene.json");
    std::fs::write(
        &scene,
        r#"{"obstacles": [{"type": "plane", "point": [0, 0, -0.002], "normal": [0, 0, 1]}],
            "contact": {"mode": "none"},
            "terms": {"wrapping": false},
            "dynamics": {"obstacle_mu": 0.3, "dt": 0.001, "max_dt": 0.004, "duration": 0.12, "frame_rate": 100, "rest_time": 0}}"#,
    )
    .unwrap();
    let out = dir.path().join("out");
    let run = knitsim()
        .arg("drape")
        .arg(&state)
        .arg("-o")
        .arg(&out)
        .arg("--scene")
        .arg(&scene)
        .arg("--no-relax")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        matches!(run.status.code(), Some(0) | Some(3)),
        "{:?}\n{stdout}\n{stderr}",
        run.status
    );
    let frames = pvd_frames(&out.join("drape.pvd"));
    assert!(frames.len() >= 10, "{} frames", frames.len());
    // Times grow; every file exists.
    assert!(frames.windows(2).all(|w| w[1].0 > w[0].0));
    for (_, f) in &frames {
        assert!(out.join(f).is_file(), "{f}");
    }
    for f in [
        "state.json",
        "draped.vtk",
        "draped.obj",
        "draped.mtl",
        "draped.png",
        "obstacles.vtu",
        "obstacles.obj",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("energy.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("time_s,step,h_s,kinetic_j,potential_j,newton_iterations"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() >= 30, "{} steps", rows.len());
    // The patch falls: kinetic energy rises from zero in the first steps.
    assert!(rows[5][3] > 0.0);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["frames"].as_u64().unwrap() as usize, frames.len());
    assert!(summary["min_obstacle_clearance"].as_f64().unwrap() > 0.5);
    // meshio reads the last frame: one point per yarn point, a line per segment.
    let f = woven_patch();
    let points: usize = f.yarns.iter().map(|y| y.points.len()).sum();
    meshio_reads(&out.join(&frames.last().unwrap().1), points, points - f.yarns.len());
}

#[test]
fn every_example_scene_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "json") {
            knitsim::scene::load_params(&path).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 5, "{n} scenes");
}

/// `knitsim drape INPUT --no-relax --scene SCENE -o OUT`.
fn drape_as_is(input: &Path, scene: &Path, out: &Path) -> std::process::Output {
    knitsim()
        .arg("drape")
        .arg(input)
        .arg("--no-relax")
        .arg("--scene")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap()
}

/// The shipped layered scenes on an 8 x 8 weave (`topology::weave`), cut
/// to 30 ms: the summary reports the layers, their contacts and seams, and
/// what was removed; a seam onto a missing patch is an error.
#[test]
fn layered_scenes_join_sew_and_report_their_layers() {
    use knitsim::topology::weave::{plain_weave, WeaveOptions};
    let dir = tempfile::tempdir().unwrap();
    let cloth = dir.path().join("cloth.json");
    let o = WeaveOptions {
        warps: 8,
        wefts: 8,
        ..WeaveOptions::default()
    };
    knitsim::io::save_json(&plain_weave(&o).unwrap(), &cloth).unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    for (name, patches, seams) in [("tablecloth", 3, false), ("sewn-patch", 2, true)] {
        let mut scene: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(scenes.join(format!("{name}.json"))).unwrap()).unwrap();
        scene["dynamics"]["duration"] = serde_json::json!(0.03);
        let path = dir.path().join(format!("{name}.json"));
        std::fs::write(&path, scene.to_string()).unwrap();
        let out = dir.path().join(name);
        let run = drape_as_is(&cloth, &path, &out);
        let summary: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out.join("summary.json"))
                .unwrap_or_else(|e| panic!("{name}: no summary ({e}): {}", String::from_utf8_lossy(&run.stderr))),
        )
        .unwrap();
        let layers = &summary["layers"];
        eprintln!("{name}: {layers}");
        assert_eq!(layers["patches"], patches, "{name}");
        assert!(layers["layer_contacts"].as_u64().unwrap() > 0, "{name}: {layers}");
        assert_eq!(layers["seam_contacts"].as_u64().unwrap() > 0, seams, "{name}: {layers}");
        assert_eq!(summary["checks"]["non_finite"], 0, "{name}");
    }
    let bad = dir.path().join("bad.json");
    std::fs::write(
        &bad,
        r#"{"layers": {"patches": [{}], "seams": [{"top": 1, "bottom": 0, "edges": ["left"]}]}}"#,
    )
    .unwrap();
    let run = drape_as_is(&cloth, &bad, &dir.path().join("bad"));
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success() && err.contains("seams[0]"), "{err}");
}

#[test]
fn dynamics_errors_name_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    for (text, at, words) in [
        ("{\"dynamics\": {\n  \"dt\": 0}\n}", "2:10", "above 0"),
        (
            "{\"dynamics\": {\n  \"gravty\": [0, 0, 1]\n}}",
            "2:10",
            "unknown field `gravty`",
        ),
        ("{\"dynamics\": {\"obstacle_mu\": -1}}", "1:32", "0 or above"),
        (
            "{\"obstacles\": [{\"type\": \"mesh\", \"path\": \"missing.obj\"}]}",
            "1:",
            "cannot read mesh",
        ),
    ] {
        let path = dir.path().join("s.json");
        std::fs::write(&path, text).unwrap();
        let e = knitsim::scene::load_params(&path).unwrap_err().to_string();
        assert!(e.contains(&format!("s.json:{at}")) && e.contains(words), "{text}: {e}");
    }
    // A pin set that selects nothing, and a motion of a missing pin set, are
    // bad input (exit 2) from the command.
    let state = dir.path().join("patch.json");
    knitsim::io::save_json(&woven_patch(), &state).unwrap();
    let scene = dir.path().join("pins.json");
    std::fs::write(&scene, r#"{"dynamics": {"pins": [{"select": "nodes", "nodes": []}]}}"#).unwrap();
    let run = knitsim()
        .args(["drape", "--no-relax", "-o"])
        .arg(dir.path().join("o"))
        .arg(&state)
        .arg("--scene")
        .arg(&scene)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(2), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(String::from_utf8_lossy(&run.stderr).contains("pins[0]: selects no node"));
}

/// What the default scene must do: `knitsim drape PATTERN -o OUT` writes
/// `drape.pvd` with at least 10 frames, meshio reads the last one, the
/// swatch comes to rest within the scene's duration (one that slides off
/// the sphere falls on at the air drag's terminal speed and never does),
/// it hangs (vertical extent at least 25% of its flat width) and no
/// node comes closer to the sphere's centre than its radius plus 0.9 yarn
/// radii in any frame, read back from the frames themselves. `size`
/// resizes the pattern to `size x size` stitches first.
fn drapes_over_the_default_sphere(stem: &str, size: Option<usize>) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("patterns/{stem}.knit"));
    let pattern = match size {
        Some(n) => {
            let text = std::fs::read_to_string(&shipped).unwrap();
            let path = dir.path().join(format!("{stem}.knit"));
            std::fs::write(&path, knitsim::app::study::resize_text(&text, n)).unwrap();
            path
        }
        None => shipped,
    };
    let run = knitsim()
        .arg("drape")
        .arg(&pattern)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let frames = pvd_frames(&out.join("drape.pvd"));
    assert!(frames.len() >= 10, "{} frames", frames.len());
    let (fabric, _) =
        knitsim::app::study::load_resized(&pattern, None, &knitsim::topology::CompileOptions::default()).unwrap();
    let points: usize = fabric.yarns.iter().map(|y| y.points.len()).sum();
    meshio_reads(
        &out.join(&frames.last().unwrap().1),
        points,
        points - fabric.yarns.len(),
    );
    let yarn = knitsim::scene::params_for(&fabric, None)
        .unwrap()
        .yarn_radii(&fabric)
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let flat = summary["flat_size_mm"][0]
        .as_f64()
        .unwrap()
        .max(summary["flat_size_mm"][1].as_f64().unwrap());
    let hang = summary["final_size_mm"][2].as_f64().unwrap();
    println!(
        "{} frames; hangs {hang:.1} mm of a {flat:.1} mm flat width",
        frames.len()
    );
    assert_eq!(summary["at_rest"].as_bool(), Some(true), "not at rest: {summary}");
    assert!(hang >= 0.25 * flat, "hangs {hang} mm of {flat} mm");
    let checks = &summary["checks"];
    assert_eq!(checks["non_finite"].as_u64(), Some(0), "{checks}");
    assert_eq!(checks["overlaps"].as_u64(), Some(0), "the draped yarns cross: {checks}");
    let sphere = &summary["obstacles"][0];
    let c: Vec<f64> = sphere["center"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let radius = sphere["radius"].as_f64().unwrap();
    let mut closest = f64::INFINITY;
    for (_, f) in &frames {
        let text = std::fs::read_to_string(out.join(f)).unwrap();
        let block = text
            .split("<Points>")
            .nth(1)
            .unwrap()
            .split("</DataArray>")
            .next()
            .unwrap();
        for line in block.lines().skip(2) {
            let p: Vec<f64> = line.split_whitespace().map(|v| v.parse().unwrap()).collect();
            if p.len() == 3 {
                let d = ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt();
                closest = closest.min((d - radius) / yarn);
            }
        }
    }
    println!("closest approach to the sphere: {closest:.3} yarn radii");
    assert!(closest >= 0.9, "a node {closest} yarn radii from the sphere");
}

/// The default scene on a 10 x 10 linen stitch, small enough for CI. At 8
/// x 8 and 6 x 6 the curled swatch slides off the sphere.
#[test]
fn default_scene_drapes_a_small_linen_stitch_over_the_sphere() {
    drapes_over_the_default_sphere("linen-stitch", Some(10));
}

/// The default scene on the shipped linen stitch (20 x 16). Run it with
/// `--ignored`.
#[test]
#[ignore = "relaxing and draping the 20 x 16 linen stitch takes about 20 minutes on two cores"]
fn default_scene_drapes_the_linen_stitch_over_the_sphere() {
    drapes_over_the_default_sphere("linen-stitch", None);
}
