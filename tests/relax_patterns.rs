//! Every shipped pattern, loose and tight, relaxes.
//!
//! Each pattern is shrunk to the smallest width and height of at least 8
//! that its repeats allow (full-size runs are the benchmark's job), then
//! relaxed with the default options. Checked against the compiled start:
//! the static residual ends below the default tolerance, every coordinate
//! is finite, the potential energy went down, and every stitch contact is
//! still a contact: its two yarn points share one node whose position is
//! finite and whose `u` stays strictly inside both yarns (no unravelling).

use knitsim::app::{check_state, Limits};
use knitsim::rod::bending::BendingHessian;
use knitsim::rod::params::RodParams;
use knitsim::scene::params_for;
use knitsim::sim::{relax, RelaxOptions, SimParams, Simulation, YarnRadii};
use knitsim::solver::linear::LinearSolver;
use knitsim::solver::newton::Problem;
use knitsim::topology::{thin_shape_points, Fabric};
use std::path::Path;

mod common;
use common::small_fabric;

/// The default relaxation at a tolerance of one force scale: these tests
/// check that every pattern relaxes without breaking, not how deep
/// (`tests/relax_converged.rs` checks that the default tolerance is a
/// converged answer), and at 0.01 the float patterns take minutes each.
fn options() -> RelaxOptions {
    RelaxOptions {
        tol: 1.0,
        ..RelaxOptions::default()
    }
}

/// The settings of a simulation's own schedule that relaxation must not change.
fn schedule_of(sim: &Simulation) -> (usize, f64, f64, f64) {
    let s = sim.schedule();
    (s.newton.max_iterations, s.newton.max_force_tol, s.h, s.h_max)
}

fn potential(sim: &Simulation) -> f64 {
    sim.problem(None).unwrap().energy(sim.q())
}

fn check_contacts(f: &Fabric, name: &str) {
    for (k, c) in f.contacts.iter().enumerate() {
        for p in [c.front, c.back] {
            let y = &f.yarns[p.yarn];
            let pt = &y.points[p.point];
            assert_eq!(pt.node, c.node, "{name}: contact {k} lost its node");
            let (u_min, u_max) = (y.points[0].u, y.points[y.points.len() - 1].u);
            assert!(
                pt.u > u_min && pt.u < u_max,
                "{name}: contact {k} slid off yarn {} (u {} not in ({u_min}, {u_max}))",
                p.yarn,
                pt.u
            );
        }
        assert!(
            f.nodes[c.node].x.iter().all(|v| v.is_finite()),
            "{name}: contact {k} not finite"
        );
    }
}

/// Relaxes the small variant of `path` and returns one line of figures and
/// the most unknowns Newton held at a bound in one iteration, or what
/// failed. Panics only on NaN or a lost contact (hard errors).
fn relax_pattern(path: &Path, looseness: &str, params: SimParams) -> Result<(String, usize), String> {
    relax_fabric(path, looseness, 0.0, params)
}

/// [`relax_pattern`] with the compiled fabric's shape points thinned at
/// `shape_gap` yarn diameters (`topology::thin`) first.
fn relax_fabric(path: &Path, looseness: &str, shape_gap: f64, params: SimParams) -> Result<(String, usize), String> {
    let opts = options();
    let stem = path.file_stem().unwrap().to_string_lossy();
    let name = match shape_gap > 0.0 {
        true => format!("{stem} ({looseness}, shape gap {shape_gap})"),
        false => format!("{stem} ({looseness})"),
    };
    let mut fabric = small_fabric(path, looseness);
    if shape_gap > 0.0 && thin_shape_points(&mut fabric, shape_gap) == 0 {
        // The same fabric as the default run: nothing new to test.
        return Ok((format!("{name}: nothing thinned"), 0));
    }
    // The pattern's own yarn radii, as `knitsim relax` uses them.
    let own = params_for(&fabric, None).unwrap();
    let params = SimParams {
        rod: RodParams {
            radius: own.rod.radius,
            ..params.rod
        },
        radii: own.radii,
        ..params
    };
    let n_contacts = fabric.contacts.len();
    let mut sim = Simulation::new(fabric, params, LinearSolver::direct(), opts.h_initial);
    let e0 = potential(&sim);
    let before = schedule_of(&sim);
    let mut held = 0;
    let rep = relax(
        &mut sim,
        opts,
        None,
        &mut |s, _| held = held.max(s.held),
        &mut |_, _| {},
    )
    .unwrap();
    // Relaxation's Newton settings and pseudo time step do not leak out.
    let after = schedule_of(&sim);
    assert_eq!(before, after, "{name}: relax left its settings on the simulation");
    let e1 = potential(&sim);
    let max_gap = sim.eil_gaps().into_iter().fold(0.0f64, f64::max);
    let radius = sim.params().rod.radius;
    let line = format!(
        "{name:32} {:6} dofs {:3} steps {:4} its residual {:.2e} energy {e0:.3e} -> {e1:.3e} max EIL gap {:.2}% of r",
        sim.q().len(),
        rep.steps,
        rep.newton_iterations,
        rep.residual,
        100.0 * max_gap / radius
    );
    println!("{line}");
    assert!(sim.q().iter().all(|v| v.is_finite()), "{name}: NaN in the state");
    let out = sim.snapshot();
    assert_eq!(out.contacts.len(), n_contacts, "{name}: contacts removed");
    check_contacts(&out, &name);
    if e1.is_nan() || e1 >= e0 {
        return Err(format!("{name}: energy rose from {e0} to {e1}"));
    }
    // The soft EIL constraint (kc = kc_factor ks / du) holds contacts to
    // within a fraction of the yarn radius at equilibrium.
    if max_gap > 0.01 * radius {
        return Err(format!("{line}: an EIL contact is open by more than 1% of the radius"));
    }
    if !(rep.converged && rep.residual <= opts.tol) {
        return Err(format!("{line}: not below tol {:.0e}", opts.tol));
    }
    Ok((line, held))
}

fn shipped() -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "knit"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 14, "the shipped patterns are missing");
    paths
}

/// The float patterns: the ones whose layout has shape points near its
/// contacts (the leg bends around its floats).
const FLOATS: [&str; 5] = ["linen-stitch", "honeycomb", "mosaic", "jacquard", "fig3-"];

fn is_float(path: &Path) -> bool {
    let stem = path.file_stem().unwrap().to_string_lossy();
    FLOATS.iter().any(|f| stem.starts_with(f))
}

fn relax_all(looseness: &str, shape_gap: f64) {
    // Thinning changes only the float patterns (checked below).
    let which = |p: &Path| shape_gap == 0.0 || is_float(p);
    relax_all_with(looseness, shape_gap, SimParams::default(), &which);
}

fn relax_all_with(looseness: &str, shape_gap: f64, params: SimParams, which: &dyn Fn(&Path) -> bool) {
    let (mut failures, mut unchanged) = (Vec::new(), Vec::new());
    for path in shipped().into_iter().filter(|p| which(p)) {
        match relax_fabric(&path, looseness, shape_gap, params.clone()) {
            Ok((line, _)) if line.ends_with("nothing thinned") => {
                unchanged.push(path.file_stem().unwrap().to_string_lossy().into_owned())
            }
            Ok(_) => {}
            Err(e) => failures.push(e),
        }
    }
    assert!(failures.is_empty(), "not relaxed:\n{}", failures.join("\n"));
    // Every float pattern has shape points near its contacts, so thinning
    // must have changed it.
    let missed: Vec<_> = unchanged
        .iter()
        .filter(|n| FLOATS.iter().any(|f| n.starts_with(f)))
        .collect();
    assert!(
        missed.is_empty(),
        "thinning changed nothing in {missed:?} ({looseness})"
    );
}

// Every shipped pattern (knit-purl, slip, tuck and
// colourwork), loose and tight. Two tests so the two run in parallel.

#[test]
fn every_shipped_pattern_relaxes_loose() {
    relax_all("loose", 0.0);
}

#[test]
fn every_shipped_pattern_relaxes_tight() {
    relax_all("tight", 0.0);
}

/// The same checks with the layout's shape points thinned at one yarn
/// diameter (`CompileOptions::shape_gap`, opt-in; docs/RELAX.md, "Shape gap"),
/// on the float patterns, which thinning changes: fewer, longer segments
/// must not cost any pattern its equilibrium or a contact.
#[test]
fn every_shipped_pattern_relaxes_loose_with_shape_points_thinned() {
    relax_all("loose", 1.0);
}

#[test]
fn every_shipped_pattern_relaxes_tight_with_shape_points_thinned() {
    relax_all("tight", 1.0);
}

/// The closed-form bending Hessian (`--bending-hessian split`, opt-in;
/// docs/RELAX.md, "Bending Hessian") changes only Newton's model, not the
/// energy: a knit-purl, a slip and a tuck pattern still reach the tolerance
/// with every check above. (With the exact Hessian the model is used only
/// in the iterations that fall back to a projection.)
#[test]
fn patterns_relax_with_the_split_bending_hessian() {
    let params = SimParams {
        bending_hessian: BendingHessian::Split,
        ..SimParams::default()
    };
    let which = |p: &Path| {
        ["rib-1x1", "linen-stitch", "tuck"]
            .iter()
            .any(|n| p.ends_with(format!("{n}.knit")))
    };
    relax_all_with("loose", 0.0, params, &which);
}

/// The opt-in sliding stops (`AssignParams::stop_fraction`, docs/RELAX.md,
/// "Slide stops") on the float patterns, where contacts slide furthest: the
/// stops engage (Newton holds points at them) and every check above holds.
#[test]
fn float_patterns_relax_with_sliding_stops() {
    let mut params = SimParams::default();
    params.assign.stop_fraction = 0.05;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns");
    for name in ["linen-stitch", "fig3-long-slip", "tuck"] {
        let (line, held) =
            relax_pattern(&dir.join(format!("{name}.knit")), "loose", params.clone()).unwrap_or_else(|e| panic!("{e}"));
        assert!(held > 0, "{line}: no point ever reached its stop");
    }
    // Off by default: Newton never holds anything.
    let (line, held) = relax_pattern(&dir.join("linen-stitch.knit"), "loose", SimParams::default()).unwrap();
    assert_eq!(held, 0, "{line}");
}

/// A colourwork pattern whose two yarns differ in thickness: each yarn is
/// simulated at its own radius (`YarnRadii::Pattern`, what `knitsim relax`
/// uses), and every check above holds.
#[test]
fn a_jacquard_with_a_thicker_contrast_yarn_relaxes() {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/jacquard.knit")).unwrap();
    let cc = text
        .lines()
        .find(|l| l.starts_with("yarn CC:"))
        .expect("jacquard has a CC yarn");
    let thick = cc.replace("radius 0.7 mm", "radius 1.0 mm");
    assert_ne!(cc, thick, "the CC line names its radius");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("jacquard-thick-cc.knit");
    std::fs::write(&path, text.replace(cc, &thick)).unwrap();
    let fabric = common::small_fabric(&path, "loose");
    let params = params_for(&fabric, None).unwrap();
    assert_eq!(params.radii, YarnRadii::Pattern);
    let mut radii = params.yarn_radii(&fabric);
    radii.sort_by(f64::total_cmp);
    radii.dedup();
    // Model radii: 0.6 of the stated ones (`CompileOptions::yarn_compression`).
    let c = knitsim::topology::CompileOptions::default().yarn_compression;
    assert_eq!(
        radii,
        vec![0.7e-3 * c, 1.0e-3 * c],
        "both yarn radii reach the simulator"
    );
    relax_pattern(&path, "loose", SimParams::default()).unwrap_or_else(|e| panic!("{e}"));
}

/// With `RelaxOptions::keep_eil` an EIL point of a sliding relaxation is
/// never turned real again while relaxing (docs/RELAX.md, "Keeping EIL points"), new EIL points still appear,
/// and `relax` hands the simulation back with the scene's release rule, so
/// dynamics afterwards releases as before. Without it a point is released.
#[test]
fn relaxation_keeps_its_eil_points_and_restores_the_release_rule() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/linen-stitch.knit");
    let fabric = small_fabric(&path, "loose");
    let params = params_for(&fabric, None).unwrap();
    let release = params.assign.release_fraction;
    // Steps of a relaxation: (points ever EIL, points released).
    let run = |opts: &RelaxOptions| {
        let mut sim = Simulation::new(fabric.clone(), params.clone(), LinearSolver::direct(), opts.h_initial);
        let mut schedule = knitsim::sim::relax_schedule(&sim, opts);
        let (mut seen, mut released) = (vec![false; sim.assignment().eil.len()], 0);
        for _ in 0..8 {
            sim.step_with(&mut schedule, false, None, &mut |_, _| {}).unwrap();
            for (s, &e) in seen.iter_mut().zip(&sim.assignment().eil) {
                released += usize::from(*s && !e);
                *s |= e;
            }
        }
        (seen.iter().filter(|&&s| s).count(), released)
    };
    // EIL points come from contacts sliding onto each other.
    // The schedule this test was calibrated with: short steps.
    let sliding = RelaxOptions {
        sliding: true,
        newton_per_step: 20,
        h_initial: 1e-3,
        ..RelaxOptions::default()
    };
    let opts = RelaxOptions {
        keep_eil: true,
        ..sliding
    };
    let (ever, released) = run(&opts);
    assert!(
        ever > 0 && released == 0,
        "{ever} points turned EIL, {released} released"
    );
    assert!(run(&sliding).1 > 0, "without keep_eil points are released");
    let mut sim = Simulation::new(fabric, params, LinearSolver::direct(), opts.h_initial);
    let short = RelaxOptions { max_steps: 3, ..opts };
    relax(&mut sim, short, None, &mut |_, _| {}, &mut |_, _| {}).unwrap();
    assert_eq!(sim.params().assign.release_fraction, release);
    assert!(!sim.schedule().keep_eil);
}

/// The tuck pattern as `knitsim relax` runs it (its own parameters, so
/// thickness contact on; the default tolerance) converges with no two
/// yarns inside each other. A tuck's head and the head of the loop it sits
/// on are pulled through by one child: laid too close together, the contact
/// filter takes them for neighbours and lets them sink into each other
/// (docs/MODEL.md, "Stitch contact layout", "Tuck").
#[test]
fn the_tuck_pattern_relaxes_with_contact_and_no_overlaps() {
    // The shipped pattern as it is, at 9 x 8 stitches (two repeats wide).
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("patterns/tuck.knit");
    let text = std::fs::read_to_string(&path).unwrap();
    let resized: String = text
        .lines()
        .map(|l| match l {
            l if l.starts_with("width:") => "width: 9".to_string(),
            l if l.starts_with("height:") => "height: 8".to_string(),
            l => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    let parsed = knitsim::pattern::parse_str(&resized, "tuck.knit").unwrap();
    let fabric = knitsim::topology::compile(&parsed.pattern, &knitsim::topology::CompileOptions::default()).unwrap();
    let params = params_for(&fabric, None).unwrap();
    assert!(params.contact.is_some(), "knitsim relax has thickness contact on");
    let opts = RelaxOptions::default();
    let mut sim = Simulation::new(fabric, params, LinearSolver::direct(), opts.h_initial);
    let rep = relax(&mut sim, opts, None, &mut |_, _| {}, &mut |_, _| {}).unwrap();
    let checks = check_state(&sim.snapshot(), sim.params(), &Limits::default());
    println!(
        "tuck: {} steps, {} its, residual {:.2e}, {} overlaps, smallest gap {:.2} of the radii's sum",
        rep.steps, rep.newton_iterations, rep.residual, checks.overlaps, checks.min_gap_ratio
    );
    assert!(rep.converged, "not converged: residual {:.2e}", rep.residual);
    assert_eq!(
        checks.overlaps, 0,
        "deepest overlap at {:?} m",
        checks.deepest_overlap_at
    );
}
