//! A yarn hanging between two pins relaxes to the analytic catenary, and
//! the error falls as the discretization is refined.

mod common;

use knitsim::sim::{relax, RelaxOptions, SimParams, Simulation, Terms};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::Vec3;

/// Catenary parameter `a` for a chain of length `len` between supports `span` apart:
/// `len = 2 a sinh(span / 2a)`, solved by bisection.
fn catenary_a(len: f64, span: f64) -> f64 {
    let (mut lo, mut hi) = (1e-6, 1e3);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if 2.0 * mid * (span / (2.0 * mid)).sinh() > len {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Mid-span sag error of a relaxed hanging yarn with `n` segments.
fn sag_error(n: usize) -> f64 {
    let (len, span) = (0.12, 0.1);
    let mut f = common::yarn_fabric(len, n, |s| {
        Vec3::new(span * (s - 0.5), 0.0, -0.01 * (std::f64::consts::PI * s).sin())
    });
    f.nodes[0].pinned = true;
    f.nodes[n].pinned = true;
    let terms = Terms {
        bending: false,
        gravity: true,
        friction: false,
        ..Terms::default()
    };
    let mut p = SimParams {
        terms,
        ..SimParams::default()
    };
    // Nearly inextensible compared with the yarn's weight, as the analytic chain.
    p.rod.ks = 1e3;
    let mut sim = Simulation::new(f, p, LinearSolver::direct(), 1.0);
    let rep = relax(
        &mut sim,
        RelaxOptions {
            // 1e-4 of the chain's force scale (its bending force, 7e-6 N):
            // free forces below 1e-9 N.
            tol: 1e-4,
            max_steps: 100,
            newton_per_step: 100,
            // One large step solved tightly: the chain has no friction or
            // sliding to continue through.
            h_initial: 1.0,
            h_max: 1.0,
            newton_rel_tol: 1e-8,
            ..RelaxOptions::default()
        },
        None,
        &mut |_, _| {},
        &mut |_, _| {},
    )
    .unwrap();
    assert!(rep.converged, "{rep:?}");
    let a = catenary_a(len, span);
    let sag = a * (span / (2.0 * a)).cosh() - a;
    let snap = sim.snapshot();
    // Sampled at the mid node (n even): the discrete chain's lowest point.
    let z_mid = snap.nodes[n / 2].x.z;
    ((-z_mid) - sag).abs() / sag
}

#[test]
fn hanging_yarn_matches_catenary_and_converges_with_refinement() {
    let errs: Vec<f64> = [8, 16, 32].iter().map(|&n| sag_error(n)).collect();
    eprintln!("relative sag error at 8, 16, 32 segments: {errs:?}");
    assert!(errs[2] < 2e-3, "{errs:?}");
    assert!(
        errs[1] < errs[0] && errs[2] < errs[1],
        "error must fall with refinement: {errs:?}"
    );
}
