//! Relaxes one swatch with cpu-direct and with cpu-cg and prints how far
//! apart the two answers end, rigid motion aside, with the smallest
//! eigenvalues of the exact Hessian at the cpu-direct answer: more than six
//! near-zero ones mean a mechanism (a curve of equal-energy equilibria)
//! along which no stopping test can pin the answer (docs/RELAX.md,
//! "Solver independence").
//!
//! `cargo run --release --example solver_parity -- [PATTERN_STEM] [N] [TOL]`
//! (defaults: stockinette, 4, the default tolerance).

use knitsim::app::study::load_resized;
use knitsim::scene::params_for;
use knitsim::sim::{relax, RelaxOptions, Simulation};
use knitsim::solver::linear::LinearSolver;
use knitsim::solver::newton::Problem;
use knitsim::topology::align::aligned_rms;
use knitsim::topology::{CompileOptions, Vec3};
use nalgebra::{DMatrix, DVector};
use std::path::Path;

/// Eigenvalues below this (N/m) count as null.
const NULL: f64 = 1e-6;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let stem = args.get(1).map_or("stockinette", String::as_str);
    let n: usize = args.get(2).map_or(4, |s| s.parse().expect("N"));
    let tol: f64 = args
        .get(3)
        .map_or(RelaxOptions::default().tol, |s| s.parse().expect("TOL"));
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("patterns/{stem}.knit"));
    let fabric = load_resized(&path, Some(n), &CompileOptions::default())
        .expect("pattern")
        .0;
    let params = params_for(&fabric, None).expect("parameters");
    let radius = params.yarn_radii(&fabric).into_iter().fold(0.0, f64::max);
    let opts = RelaxOptions {
        tol,
        ..RelaxOptions::default()
    };
    let run = |solver: LinearSolver| {
        let name = solver.name();
        let mut sim = Simulation::new(fabric.clone(), params.clone(), solver, opts.h_initial);
        let (mut projected, mut linear) = (0, 0);
        let start = std::time::Instant::now();
        let rep = relax(
            &mut sim,
            opts,
            None,
            &mut |s, _| {
                projected += usize::from(s.projected);
                linear += s.linear_iterations;
            },
            &mut |_, _| {},
        )
        .expect("relax");
        println!(
            "{name}: converged {}, {} steps, {} Newton its ({projected} projected), {linear} CG its, {:.1} s, E {:.10e} J",
            rep.converged,
            rep.steps,
            rep.newton_iterations,
            start.elapsed().as_secs_f64(),
            sim.potential_energy().expect("energy")
        );
        sim
    };
    let direct = run(LinearSolver::direct());
    let cg = run(LinearSolver::cg());
    let nodes = |s: &Simulation| -> Vec<Vec3> { s.snapshot().nodes.iter().map(|n| n.x).collect() };
    let (xa, xb) = (nodes(&direct), nodes(&cg));
    let rms = aligned_rms(&xb, &xa).expect("same nodes") / radius;
    println!(
        "RMS distance after a rigid fit: {rms:.3e} yarn radii over {} nodes",
        xa.len()
    );

    // The exact Hessian over the free coordinates at the cpu-direct answer.
    let q = direct.q().to_vec();
    let mut problem = direct.problem(None).expect("problem");
    problem.set_projection(false);
    let mut h = problem.hessian_pattern();
    let mut g = vec![0.0; q.len()];
    problem.gradient_hessian(&q, &mut g, &mut h).expect("assembly");
    let free: Vec<usize> = (0..h.n).filter(|&i| problem.free()[i]).collect();
    let dense = DMatrix::from_fn(free.len(), free.len(), |r, c| {
        h.find(free[r], free[c]).map_or(0.0, |k| h.values[k])
    });
    let eig = dense.symmetric_eigen();
    let mut values: Vec<f64> = eig.eigenvalues.iter().copied().collect();
    values.sort_by(f64::total_cmp);
    let shown: Vec<String> = values.iter().take(9).map(|v| format!("{v:.2e}")).collect();
    println!("smallest Hessian eigenvalues (N/m): {}", shown.join(", "));

    // The node difference (cg rigidly fitted onto direct is not needed for
    // the null modes: they include the rigid ones) with the null modes removed.
    if cg.q().len() == q.len() {
        let mut d = DVector::from_fn(free.len(), |k, _| cg.q()[free[k]] - q[free[k]]);
        let mut nulls = 0;
        for (k, lam) in eig.eigenvalues.iter().enumerate() {
            if lam.abs() < NULL {
                let v = eig.eigenvectors.column(k);
                d -= v * v.dot(&d);
                nulls += 1;
            }
        }
        let n_nodes = direct.layout().n_nodes;
        let sq: f64 = (0..free.len())
            .filter(|&k| free[k] < 3 * n_nodes)
            .map(|k| d[k] * d[k])
            .sum();
        println!(
            "{nulls} null modes; without them the answers are {:.3e} radii RMS apart (to first order)",
            (sq / n_nodes as f64).sqrt() / radius
        );
    }
}
