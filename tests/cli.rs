//! The `knitsim` binary end to end: what the README's main job promises
//! (outputs, `convergence.csv`, the last line), bad input (file, line and
//! column, exit status, no output written), and a scene key reaching the
//! simulation (`separation`).

use knitsim::io::save_json;
use knitsim::pattern::{Construction, Gauge, Meta, YarnSpec};
use knitsim::topology::{Contact, ContactKind, Fabric, Node, PointRef, Vec3, Yarn, YarnPoint};
use std::path::Path;
use std::process::{Command, Output};

const OUTPUTS: [&str; 7] = [
    "state.json",
    "relaxed.vtk",
    "relaxed.obj",
    "relaxed.mtl",
    "relaxed.png",
    "convergence.csv",
    "summary.json",
];

fn knitsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_knitsim"))
        .args(args)
        .output()
        .expect("the knitsim binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The shipped stockinette, 4 x 4 stitches.
fn small_stockinette(dir: &Path) -> String {
    let shipped = std::fs::read_to_string("patterns/stockinette.knit").unwrap();
    let small = shipped
        .replace("width: 16", "width: 4")
        .replace("height: 16", "height: 4");
    assert_ne!(small, shipped, "the shipped pattern's size lines changed");
    let path = dir.join("small.knit");
    std::fs::write(&path, small).unwrap();
    path.display().to_string()
}

#[test]
fn relax_writes_every_output_and_ends_with_the_residual_and_wall_time() {
    let dir = tempfile::tempdir().unwrap();
    let pattern = small_stockinette(dir.path());
    let out = dir.path().join("out");
    let run = knitsim(&["relax", &pattern, "-o", out.to_str().unwrap()]);
    let stdout = text(&run.stdout);
    assert!(run.status.success(), "{stdout}\n{}", text(&run.stderr));
    for name in OUTPUTS {
        let len = std::fs::metadata(out.join(name)).map(|m| m.len()).unwrap_or(0);
        assert!(len > 0, "{name} missing or empty");
    }
    // No temporary file is left behind.
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), OUTPUTS.len());

    let last = stdout.lines().last().unwrap_or_default();
    let residual: f64 = last
        .strip_prefix("largest free force ")
        .and_then(|r| r.split_whitespace().next())
        .and_then(|r| r.parse().ok())
        .unwrap_or_else(|| panic!("last line: {last}"));
    assert!(
        last.contains("(converged, tol 1.0e-2)") && last.contains("wall time"),
        "{last}"
    );
    assert!(residual < 0.01, "{last}");
    // The line before gives the measured gauge; summary.json holds the same.
    let gauge_line = stdout.lines().rev().nth(1).unwrap_or_default();
    assert!(
        gauge_line.starts_with("gauge ") && gauge_line.contains("(pattern: 24.0 x 32.0)"),
        "{gauge_line}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["converged"], serde_json::Value::Bool(true));
    assert!((summary["stopping_quantity"].as_f64().unwrap() - residual).abs() <= 1e-3 * residual);

    // One CSV row per Newton iteration, as many as the summary reports.
    let iterations: usize = stdout
        .lines()
        .find_map(|l| l.split(" steps, ").nth(1)?.split(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("no summary line in {stdout}"));
    let csv = std::fs::read_to_string(out.join("convergence.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("iteration,step,elapsed_s,energy,max_force_over_scale,gradient_norm,step_length,eil_count")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("numeric cell")).collect())
        .collect();
    assert_eq!(rows.len(), iterations);
    assert!(rows.iter().all(|r| r.len() == 8 && r.iter().all(|v| v.is_finite())));
    assert!(rows.windows(2).all(|w| w[1][2] >= w[0][2]), "elapsed time goes back");
}

#[test]
fn a_malformed_pattern_is_an_error_at_its_line_and_column_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let pattern = "tests/malformed/unknown-symbol.knit";
    let run = knitsim(&["relax", pattern, "-o", out.to_str().unwrap()]);
    let stderr = text(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "bad input: {stderr}");
    let at = format!("{pattern}:");
    let location = stderr
        .split(&at)
        .nth(1)
        .unwrap_or_else(|| panic!("no file name in: {stderr}"));
    let digits = |s: &str| s.chars().take_while(char::is_ascii_digit).collect::<String>();
    let line = digits(location);
    let column = digits(location.get(line.len() + 1..).unwrap_or(""));
    assert_eq!((line.as_str(), column.as_str()), ("8", "7"), "{stderr}");
    // Said once, with one heading.
    assert_eq!(stderr.matches("unknown symbol").count(), 1, "{stderr}");
    assert!(stderr.starts_with("error: unknown symbol"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!out.exists() || std::fs::read_dir(&out).unwrap().count() == 0);
}

#[test]
fn a_broken_scene_file_is_an_error_at_its_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let pattern = small_stockinette(dir.path());
    let scene = dir.path().join("scene.json");
    std::fs::write(&scene, "{\n  \"rod\": {\"ks\": 1.0,}\n}\n").unwrap();
    let out = dir.path().join("out");
    let run = knitsim(&[
        "relax",
        &pattern,
        "-o",
        out.to_str().unwrap(),
        "--scene",
        scene.to_str().unwrap(),
    ]);
    let stderr = text(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "bad input: {stderr}");
    assert!(stderr.contains(&format!("{}:2:21:", scene.display())), "{stderr}");
    assert!(!out.exists() || std::fs::read_dir(&out).unwrap().count() == 0);
    let run = knitsim(&["relax", &pattern, "-o", out.to_str().unwrap(), "--tol", "NaN"]);
    assert_eq!(run.status.code(), Some(2));
    assert!(text(&run.stderr).contains("--tol must be a positive number"));
}

#[test]
fn bad_values_in_a_pattern_or_scene_exit_with_2_at_their_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    let latin1 = "tests/malformed/latin1-gauge.knit";
    let run = knitsim(&["compile", latin1, "-o", out_s]);
    let stderr = text(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(&format!("{latin1}:2:15")) && stderr.contains("not UTF-8"),
        "{stderr}"
    );

    let pattern = small_stockinette(dir.path());
    let scene = dir.path().join("sphere.json");
    let sphere = "{\"obstacles\": [\n  {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": -0.01}\n]}\n";
    std::fs::write(&scene, sphere).unwrap();
    let run = knitsim(&["relax", &pattern, "-o", out_s, "--scene", scene.to_str().unwrap()]);
    let stderr = text(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(&format!("{}:2:58: ", scene.display())), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!out.exists() || std::fs::read_dir(&out).unwrap().count() == 0);

    // A file that cannot be opened is bad input too: exit status 2.
    let missing = dir.path().join("missing.knit");
    let run = knitsim(&["compile", missing.to_str().unwrap(), "-o", out_s]);
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stderr));
}

/// Two yarns 40 mm long crossing at their middles on one `Layer` contact,
/// the front one (along x) with its pinned ends 1 mm above the back one's.
fn lifted_layer() -> Fabric {
    let meta = Meta {
        name: "two layers".into(),
        gauge: Gauge {
            stitches_per_10cm: 20.0,
            rows_per_10cm: 28.0,
        },
        yarns: vec![YarnSpec {
            name: "MC".into(),
            color: [200, 120, 40],
            radius: 0.75e-3,
            material: None,
        }],
        construction: Construction::Flat,
        width: 1,
        height: 1,
        looseness: 1.0,
    };
    let mut f = Fabric {
        meta,
        nodes: vec![Node {
            x: Vec3::zeros(),
            pinned: false,
        }],
        yarns: vec![],
        contacts: vec![],
        sim: None,
    };
    for along_x in [true, false] {
        let mut points = Vec::new();
        for i in 0..5 {
            let s = 0.01 * i as f64 - 0.02;
            let end = i == 0 || i == 4;
            let node = if i == 2 {
                0
            } else {
                let z = if along_x && end { 1e-3 } else { 0.0 };
                let x = if along_x {
                    Vec3::new(s, 0.0, z)
                } else {
                    Vec3::new(0.0, s, z)
                };
                f.nodes.push(Node { x, pinned: end });
                f.nodes.len() - 1
            };
            points.push(YarnPoint {
                node,
                u: 0.01 * i as f64,
                fixed_u: i != 2,
                eil: false,
            });
        }
        f.yarns.push(Yarn {
            layer: 0,
            spec: 0,
            rest_length: 0.04,
            points,
        });
    }
    f.contacts.push(Contact {
        node: 0,
        front: PointRef { yarn: 0, point: 2 },
        back: PointRef { yarn: 1, point: 2 },
        kind: ContactKind::Layer,
        partner: None,
    });
    f
}

#[test]
fn the_separation_scene_key_splits_a_layer_contact_that_pulls() {
    let dir = tempfile::tempdir().unwrap();
    let topology = dir.path().join("layers.json");
    save_json(&lifted_layer(), &topology).unwrap();
    let scene = dir.path().join("scene.json");
    // The layers start touching: thickness contact (on by default) would
    // refuse the start, so both runs turn it off.
    std::fs::write(&scene, r#"{"separation": {}, "contact": {"mode": "none"}}"#).unwrap();
    let plain = dir.path().join("plain.json");
    std::fs::write(&plain, r#"{"contact": {"mode": "none"}}"#).unwrap();
    let contacts_after = |scene: Option<&Path>| {
        let out = dir.path().join(if scene.is_some() { "with" } else { "without" });
        let scene = scene.unwrap_or(&plain);
        let args = vec![
            "relax",
            topology.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--scene",
            scene.to_str().unwrap(),
        ];
        let run = knitsim(&args);
        let stdout = text(&run.stdout);
        assert!(run.status.success(), "{stdout}\n{}", text(&run.stderr));
        let state = knitsim::io::load_json(&out.join("state.json")).unwrap();
        (state.contacts.len(), stdout)
    };
    let (kept, stdout) = contacts_after(None);
    assert_eq!(kept, 1, "{stdout}");
    assert!(!stdout.contains("pulled apart"), "{stdout}");
    let (kept, stdout) = contacts_after(Some(&scene));
    assert_eq!(kept, 0, "{stdout}");
    assert!(
        stdout.contains("1 contact(s) removed: their yarns pulled apart (scene key separation)"),
        "{stdout}"
    );
}

/// `--shape-gap` reaches the compiler: the thinned topology of the shipped
/// linen stitch keeps every contact with fewer nodes, and a negative gap is
/// an error naming the file that writes nothing.
#[test]
fn shape_gap_thins_the_compiled_topology_and_a_negative_gap_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let compiled = |gap: &str| {
        let out = dir.path().join(format!("linen-{gap}.json"));
        let run = knitsim(&[
            "compile",
            "patterns/linen-stitch.knit",
            &format!("--shape-gap={gap}"),
            "-o",
            out.to_str().unwrap(),
        ]);
        (run, out)
    };
    let load = |p: &Path| -> Fabric { serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap() };
    let (run, full) = compiled("0");
    assert!(run.status.success(), "{}", text(&run.stderr));
    let (run, thin) = compiled("1");
    assert!(run.status.success(), "{}", text(&run.stderr));
    let (full, thin) = (load(&full), load(&thin));
    assert_eq!(full.contacts.len(), thin.contacts.len());
    assert!(
        thin.nodes.len() < full.nodes.len(),
        "{} vs {}",
        thin.nodes.len(),
        full.nodes.len()
    );

    let (run, out) = compiled("-1");
    assert_eq!(run.status.code(), Some(2), "a refused option is bad input");
    let stderr = text(&run.stderr);
    assert!(
        stderr.contains("linen-stitch.knit") && stderr.contains("shape_gap"),
        "{stderr}"
    );
    assert!(!out.exists(), "a refused run wrote {}", out.display());
}

/// `--bending-hessian split` and the scene key `bending_hessian` pick the
/// closed-form bending model; the run converges either way, and an
/// unknown model or scene value is refused before anything is written.
#[test]
fn the_bending_hessian_flag_and_scene_key_are_read_and_checked() {
    let dir = tempfile::tempdir().unwrap();
    let pattern = small_stockinette(dir.path());
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    let run = knitsim(&["relax", &pattern, "-o", out_s, "--bending-hessian", "split"]);
    let stdout = text(&run.stdout);
    assert!(run.status.success(), "{stdout}\n{}", text(&run.stderr));
    assert!(
        stdout.lines().last().unwrap_or_default().contains("(converged"),
        "{stdout}"
    );

    let scene = dir.path().join("scene.json");
    std::fs::write(&scene, "{\"bending_hessian\": \"split\"}").unwrap();
    let run = knitsim(&["relax", &pattern, "-o", out_s, "--scene", scene.to_str().unwrap()]);
    assert!(run.status.success(), "{}", text(&run.stderr));

    let refused = dir.path().join("refused");
    let run = knitsim(&[
        "relax",
        &pattern,
        "-o",
        refused.to_str().unwrap(),
        "--bending-hessian",
        "exact",
    ]);
    assert_eq!(run.status.code(), Some(2), "clap's usage error");
    assert!(text(&run.stderr).contains("eigen, split"), "{}", text(&run.stderr));
    std::fs::write(&scene, "{\"bending_hessian\": \"exact\"}").unwrap();
    let run = knitsim(&[
        "relax",
        &pattern,
        "-o",
        refused.to_str().unwrap(),
        "--scene",
        scene.to_str().unwrap(),
    ]);
    assert_eq!(run.status.code(), Some(2), "bad input: {}", text(&run.stderr));
    assert!(
        text(&run.stderr).contains(&format!("{}:1:", scene.display())),
        "{}",
        text(&run.stderr)
    );
    assert!(!refused.exists() || std::fs::read_dir(&refused).unwrap().count() == 0);
}

/// Exit status 0 for a converged run, 2 for an input that cannot be read,
/// 3 for a run stopped by the step cap (whose state is still written), and
/// the codes are documented in `--help`.
#[test]
fn exit_status_tells_converged_bad_input_and_not_converged_apart() {
    let dir = tempfile::tempdir().unwrap();
    let pattern = small_stockinette(dir.path());
    let out = dir.path().join("converged");
    let run = knitsim(&["relax", &pattern, "-o", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));

    let missing = dir.path().join("no-such.knit");
    let out = dir.path().join("missing");
    let run = knitsim(&["relax", missing.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stderr));
    assert!(!out.join("state.json").exists());

    let out = dir.path().join("capped");
    // A tolerance no single step reaches, so the cap always comes first.
    let run = knitsim(&[
        "relax",
        &pattern,
        "-o",
        out.to_str().unwrap(),
        "--max-steps",
        "1",
        "--tol",
        "1e-9",
    ]);
    let stdout = text(&run.stdout);
    assert_eq!(run.status.code(), Some(3), "{stdout}\n{}", text(&run.stderr));
    assert!(stdout.contains("not converged: residual"), "{stdout}");
    assert!(
        stdout.lines().last().unwrap_or_default().contains("(NOT converged"),
        "{stdout}"
    );
    let state = std::fs::metadata(out.join("state.json")).map(|m| m.len()).unwrap_or(0);
    assert!(state > 0, "the capped run's state.json is missing");

    let help = text(&knitsim(&["--help"]).stdout);
    for code in ["0 ", "1 ", "2 ", "3 ", "130 "] {
        assert!(
            help.contains(&format!("\n  {code}")),
            "exit status {code}missing from --help:\n{help}"
        );
    }
}
