//! Shared test fixtures: the structures every stage must handle.
#![allow(dead_code)]

use knitsim::pattern::parse_str;
use knitsim::pattern::{Construction, Gauge, Meta, Pattern, YarnSpec};
use knitsim::topology::sample::{chart_pattern, tile};
use knitsim::topology::{compile, CompileOptions, Fabric, Node, Vec3, Yarn, YarnPoint};
use std::path::Path;

/// A named structure: stitch tile and optional colour tile, top row first.
pub type Structure = (&'static str, Vec<&'static str>, Option<Vec<&'static str>>);

/// The structures the project ships.
pub fn structures() -> Vec<Structure> {
    vec![
        ("stockinette", vec!["k"], None),
        ("garter", vec!["p", "k"], None),
        ("rib 1x1", vec!["kp"], None),
        ("rib 2x2", vec!["kkpp"], None),
        ("seed", vec!["pk", "kp"], None),
        ("linen", vec!["vk", "kv"], None),
        ("honeycomb", vec!["kkkk", "kwkw", "kkkk", "wkwk"], None),
        (
            "mosaic",
            vec!["kkkk", "kwkw", "kkkk", "wkwk"],
            Some(vec!["1111", "1111", "0000", "0000"]),
        ),
        ("tuck", vec!["kkkk", "ktkt", "kkkk", "tktk"], None),
        ("jacquard", vec!["k"], Some(vec!["0110", "1001", "0011", "1100"])),
    ]
}

pub fn pattern(t: &[&str], c: Option<&[&str]>, cons: Construction, w: usize, h: usize) -> Pattern {
    let st = tile(t, w, h);
    let st: Vec<&str> = st.iter().map(String::as_str).collect();
    let cl = c.map(|c| tile(c, w, h));
    let cl: Option<Vec<&str>> = cl.as_ref().map(|c| c.iter().map(String::as_str).collect());
    chart_pattern(&st, cl.as_deref(), cons).expect("chart")
}

/// Every `patterns/*.knit` file the project ships, sorted by name, with its
/// parsed pattern. Read from the directory, so a new pattern is covered by
/// every "each shipped pattern" test without editing the tests.
pub fn shipped_patterns() -> Vec<(String, Pattern)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(&dir)
        .expect("patterns/ is readable")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "knit"))
        .collect();
    files.sort();
    assert!(files.len() >= 14, "expected the shipped patterns in {}", dir.display());
    files
        .into_iter()
        .map(|path| {
            let name = path
                .file_stem()
                .and_then(|s| s.to_str())
                .expect("utf-8 name")
                .to_string();
            let parsed = knitsim::pattern::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
            (name, parsed.pattern)
        })
        .collect()
}

/// One shipped pattern by file stem (`"rib-1x1"` for `patterns/rib-1x1.knit`).
pub fn shipped(stem: &str) -> Pattern {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("patterns/{stem}.knit"));
    knitsim::pattern::load(&path)
        .unwrap_or_else(|e| panic!("{stem}: {e}"))
        .pattern
}

// Hand-made fabrics for the physics tests.

pub fn meta(radius: f64) -> Meta {
    Meta {
        name: "test".into(),
        gauge: Gauge {
            stitches_per_10cm: 20.0,
            rows_per_10cm: 28.0,
        },
        yarns: vec![YarnSpec {
            name: "a".into(),
            color: [180, 40, 40],
            radius,
            material: None,
        }],
        construction: Construction::Flat,
        width: 1,
        height: 1,
        looseness: 1.0,
    }
}

/// A yarn of rest length `len` with `n` segments, points at `pos(s)` for
/// `s` in [0, 1]; all `u` fixed (a plain Lagrangian rod).
pub fn yarn_fabric(len: f64, n: usize, pos: impl Fn(f64) -> Vec3) -> Fabric {
    let nodes: Vec<Node> = (0..=n)
        .map(|i| Node {
            x: pos(i as f64 / n as f64),
            pinned: false,
        })
        .collect();
    let points = (0..=n)
        .map(|i| YarnPoint {
            node: i,
            u: len * i as f64 / n as f64,
            fixed_u: true,
            eil: false,
        })
        .collect();
    Fabric {
        meta: meta(5e-4),
        nodes,
        yarns: vec![Yarn {
            layer: 0,
            spec: 0,
            rest_length: len,
            points,
        }],
        contacts: vec![],
        sim: None,
    }
}

/// Adds a straight yarn through `pts` to `f`; `contact_at[k] = Some(node)`
/// makes point k share an existing node (an EoL contact, free `u`). Ends are
/// fixed-u. Returns the yarn index.
pub fn add_yarn(f: &mut Fabric, pts: &[Vec3], contact_at: &[Option<usize>]) -> usize {
    let mut u = 0.0;
    let mut points = Vec::new();
    for (k, p) in pts.iter().enumerate() {
        if k > 0 {
            u += (p - pts[k - 1]).norm();
        }
        let node = match contact_at[k] {
            Some(n) => n,
            None => {
                f.nodes.push(Node { x: *p, pinned: false });
                f.nodes.len() - 1
            }
        };
        let fixed_u = k == 0 || k + 1 == pts.len();
        points.push(YarnPoint {
            node,
            u,
            fixed_u,
            eil: false,
        });
    }
    f.yarns.push(Yarn {
        layer: 0,
        spec: 0,
        rest_length: u,
        points,
    });
    f.yarns.len() - 1
}

pub fn empty_fabric(radius: f64) -> Fabric {
    Fabric {
        meta: meta(radius),
        nodes: vec![],
        yarns: vec![],
        contacts: vec![],
        sim: None,
    }
}

/// The pattern text with width, height and looseness replaced.
pub fn variant(text: &str, w: usize, h: usize, looseness: &str) -> String {
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with("looseness:") {
            continue;
        }
        if line.starts_with("width:") {
            out.push(format!("width: {w}"));
            out.push(format!("looseness: {looseness}"));
        } else if line.starts_with("height:") {
            out.push(format!("height: {h}"));
        } else {
            out.push(line.to_string());
        }
    }
    out.join("\n") + "\n"
}

/// The smallest variant with width and height >= 8 that compiles.
pub fn small_fabric(path: &Path, looseness: &str) -> Fabric {
    sized_fabric(path, looseness, 8)
}

/// The smallest variant with width and height >= `min` that compiles.
pub fn sized_fabric(path: &Path, looseness: &str, min: usize) -> Fabric {
    let text = std::fs::read_to_string(path).unwrap();
    for w in min..=40 {
        for h in min..=40 {
            let Ok(parsed) = parse_str(&variant(&text, w, h, looseness), &path.display().to_string()) else {
                continue;
            };
            if let Ok(f) = compile(&parsed.pattern, &CompileOptions::default()) {
                return f;
            }
        }
    }
    panic!("{}: no size between {min} and 40 compiles", path.display());
}

/// Writes a 12 x 12 swatch to `dir/swatch.knit`: `gauge` as in a `gauge`
/// line without its `/ 10 cm`, `yarn` appended to the yarn line (e.g.
/// `", radius 1.5 mm"`, or empty for the default yarn), and the chart's
/// lines (`.` knit, `-` purl), each indented.
pub fn swatch_file(dir: &Path, gauge: &str, yarn: &str, chart: &str) -> std::path::PathBuf {
    let purl = if chart.contains('-') { "  - = purl\n" } else { "" };
    let text = format!(
        "name: swatch\ngauge: {gauge} / 10 cm\nyarn MC: #ffffff{yarn}\nwidth: 12\nheight: 12\n\n\
         legend:\n  . = knit\n{purl}\nchart:\n{chart}"
    );
    let path = dir.join("swatch.knit");
    std::fs::write(&path, text).unwrap();
    path
}

/// Relaxes the pattern at `path` with the default settings, asserting that
/// it compiles without warnings and converges, and returns the final state
/// with the compiled stitch grid. The tolerance is 0.1 force scales: a
/// swatch is measured in its middle, which has settled long before the
/// edge roll that the last decades of the default tolerance finish
/// (docs/RELAX.md, "What the default tolerance means").
pub fn relaxed_swatch(path: &Path) -> (Fabric, knitsim::topology::StitchGrid) {
    use knitsim::sim::{relax, RelaxOptions, Simulation};
    let loaded = knitsim::app::load_fabric(path, &CompileOptions::default()).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let grid = knitsim::topology::StitchGrid::of(&loaded.fabric);
    let params = knitsim::scene::params_for(&loaded.fabric, None).unwrap();
    let mut sim = Simulation::new(
        loaded.fabric,
        params,
        knitsim::solver::linear::LinearSolver::direct(),
        RelaxOptions::default().h_initial,
    );
    let opts = RelaxOptions {
        tol: 0.1,
        ..RelaxOptions::default()
    };
    let report = relax(&mut sim, opts, None, &mut |_, _| {}, &mut |_, _| {}).unwrap();
    assert!(report.converged, "{report:?}");
    (sim.snapshot(), grid)
}
