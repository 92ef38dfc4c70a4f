//! The default relaxation is a converged answer, and a reproducible one.
//!
//! - **Tightening does not move it.** A swatch relaxed at the default
//!   tolerance and again at a tolerance a hundred times tighter ends within
//!   1% in width and height and within one yarn diameter out of plane.
//!   Measured on the bounding box, the quantities a designer reads off
//!   the result. This fails when the default stops while the soft modes
//!   (the edge roll of stockinette) are still moving.
//! - **A nudge does not move it.** Starts jittered by at most 1 nm per
//!   coordinate end within 1% of each other in width, height and energy,
//!   and within half a yarn diameter out of plane. This fails when the
//!   path to the answer is chaotic at rounding level.
//!
//! - **The linear solver does not move it.** cpu-direct and cpu-cg end
//!   within 1e-3 yarn radii RMS of each other.
//!
//! A free swatch has rigid motions that cost no energy, and a jittered
//! start may turn it by a fraction of a degree. Sizes are therefore the
//! finished size along the swatch's own courses, wales and normal
//! (`StitchGrid::extents`, as `summary.json` reports it), and shapes are
//! compared after the best rigid fit (`topology::align`), never in the
//! lab frame.
//!
//! Sizes are the smallest that still have an interior and edges that
//! roll, so the tests run in CI.

use knitsim::app::study::load_resized;
use knitsim::scene::params_for;
use knitsim::sim::{relax, RelaxOptions, Simulation};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::align::aligned_rms;
use knitsim::topology::jitter::jitter;
use knitsim::topology::{CompileOptions, Fabric, StitchGrid, Vec3};
use std::path::Path;

struct Relaxed {
    extent: [f64; 3],
    energy: f64,
    radius: f64,
    iterations: usize,
    x: Vec<Vec3>,
}

fn fabric(stem: &str, n: usize) -> Fabric {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("patterns/{stem}.knit"));
    load_resized(&path, Some(n), &CompileOptions::default()).unwrap().0
}

fn relaxed_with(fabric: Fabric, opts: RelaxOptions, solver: LinearSolver) -> Relaxed {
    let grid = StitchGrid::of(&fabric);
    let params = params_for(&fabric, None).unwrap();
    assert!(params.terms.friction, "the swatch has friction");
    let radius = params.yarn_radii(&fabric).into_iter().fold(0.0, f64::max);
    let mut sim = Simulation::new(fabric, params, solver, opts.h_initial);
    let rep = relax(&mut sim, opts, None, &mut |_, _| {}, &mut |_, _| {}).unwrap();
    assert!(rep.converged, "not converged: {rep:?}");
    let state = sim.snapshot();
    Relaxed {
        extent: grid.extents(&state).expect("a stitch grid"),
        energy: sim.potential_energy().unwrap(),
        radius,
        iterations: rep.newton_iterations,
        x: state.nodes.iter().map(|n| n.x).collect(),
    }
}

fn relaxed(fabric: Fabric, opts: RelaxOptions) -> Relaxed {
    relaxed_with(fabric, opts, LinearSolver::direct())
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn a_hundred_times_tighter_tolerance_leaves_the_default_stockinette_where_it_is() {
    let default = RelaxOptions::default();
    let tight = RelaxOptions {
        tol: default.tol / 100.0,
        ..default
    };
    let a = relaxed(fabric("stockinette", 8), default);
    let b = relaxed(fabric("stockinette", 8), tight);
    let (w, h) = (rel(a.extent[0], b.extent[0]), rel(a.extent[1], b.extent[1]));
    let depth = (a.extent[2] - b.extent[2]).abs();
    println!(
        "default {:?} mm, tight {:?} mm, depth difference {:.3} mm",
        a.extent.map(|e| e * 1e3),
        b.extent.map(|e| e * 1e3),
        depth * 1e3
    );
    assert!(w <= 0.01 && h <= 0.01, "width {w:.4}, height {h:.4} apart");
    assert!(depth <= 2.0 * a.radius, "out of plane {depth:.2e} m apart");
    // The stockinette's edges roll: the answer is not the flat start.
    assert!(b.extent[2] > 4.0 * a.radius, "depth {:.2e} m", b.extent[2]);
}

#[test]
fn ten_jittered_starts_of_the_linen_stitch_end_in_one_swatch() {
    let runs: Vec<Relaxed> = (1..=10)
        .map(|seed| {
            let mut f = fabric("linen-stitch", 4);
            jitter(&mut f, seed);
            relaxed(f, RelaxOptions::default())
        })
        .collect();
    let spread = |get: &dyn Fn(&Relaxed) -> f64| {
        let v: Vec<f64> = runs.iter().map(get).collect();
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
        (lo, hi)
    };
    let (w, h, d, e) = (
        spread(&|r| r.extent[0]),
        spread(&|r| r.extent[1]),
        spread(&|r| r.extent[2]),
        spread(&|r| r.energy),
    );
    let its: Vec<usize> = runs.iter().map(|r| r.iterations).collect();
    println!("width {w:?}, height {h:?}, depth {d:?}, energy {e:?}, Newton iterations {its:?}");
    assert!(rel(w.1, w.0) <= 0.01, "width spread {w:?}");
    assert!(rel(h.1, h.0) <= 0.01, "height spread {h:?}");
    assert!(rel(e.1, e.0) <= 0.01, "energy spread {e:?}");
    assert!(d.1 - d.0 <= runs[0].radius, "depth spread {d:?}");
}

/// With sticking friction the answer does not depend on the linear
/// solver: cpu-direct and cpu-cg, both at their defaults, end within 1e-3
/// yarn radii RMS of each other, rigid motion aside. CG is slow on these
/// stiff systems, hence a small swatch; 4 x 4 is the smallest whose only
/// zero-energy motions are rigid ones (a 3 x 3 stockinette has a seventh
/// null mode of the Hessian at equilibrium, a mechanism along which any
/// two solvers may stop apart; docs/RELAX.md, "Solver independence").
#[test]
fn cpu_direct_and_cpu_cg_relax_a_frictional_swatch_to_the_same_state() {
    let opts = RelaxOptions::default();
    let a = relaxed_with(fabric("stockinette", 4), opts, LinearSolver::direct());
    let b = relaxed_with(fabric("stockinette", 4), opts, LinearSolver::cg());
    let rms = aligned_rms(&b.x, &a.x).unwrap() / a.radius;
    println!("RMS distance {rms:.2e} radii over {} nodes", a.x.len());
    assert!(rms <= 1e-3, "{rms:.2e} radii apart");
    assert!(rel(b.energy, a.energy) < 1e-6, "energies {} and {}", a.energy, b.energy);
}
