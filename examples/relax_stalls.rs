//! Diagnostic: which energy term carries the largest free force at every
//! accepted Newton iterate of a relaxation, and, where it is bending, how
//! short the bend's shortest real segment is.
//!
//! `cargo run --release --no-default-features --example relax_stalls --
//! NAME N SEED STEPS` relaxes the shipped pattern NAME resized to N x N
//! stitches (jittered by SEED as in `bench_relax --spread`) for STEPS
//! relaxation steps, recording every accepted iterate
//! (`Simulation::iterate_log`). After each step it evaluates every stencil
//! set's gradient on each recorded iterate, under the assignment the step
//! used, and prints one line per iterate: the largest free force, the term
//! and unknown (`x` of a node or `u` of a point) it sits on, every term
//! whose largest force is above 1 N, and for the node carrying the largest
//! bending force its shortest real segment. (Friction is evaluated with the
//! anchors as the step left them, so its column is approximate.)
//!
//! docs/RELAX.md, "Closed segments", describes what stalls the float
//! patterns' Newton steps.

#[path = "common/mod.rs"]
mod common;

use common::relaxing;
use knitsim::sim::Simulation;
use knitsim::solver::newton::Problem;
use knitsim::topology::PointRef;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(String::as_str).unwrap_or("linen-stitch");
    let n: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(20);
    let seed: u64 = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(0);
    let steps: usize = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(6);
    let mut sim = relaxing(name, n, seed)?;
    let nx = 3 * sim.fabric.nodes.len();
    let unknown = |j: usize| {
        if j < nx {
            format!("x{}", j / 3)
        } else {
            format!("u{}", j - nx)
        }
    };
    for step in 0..steps {
        sim.iterate_log = Some(Vec::new());
        sim.step(false, None, &mut |_, _| {})?;
        let log = sim.iterate_log.take().unwrap_or_default();
        let problem = sim.problem(None)?;
        let mut h = problem.hessian_pattern();
        for (it, q) in log.iter().enumerate() {
            let mut total = vec![0.0; q.len()];
            let mut terms = Vec::new();
            let mut bending_at = None;
            for set in &problem.sets {
                let mut g = vec![0.0; q.len()];
                set.accumulate(q, &problem.free, &mut g, &mut h, false)?;
                let (j, f) = largest_free(&g, &problem.free);
                total.iter_mut().zip(&g).for_each(|(t, v)| *t += v);
                if f > 1.0 {
                    terms.push(format!("{}={f:.1e}@{}", set.name(), unknown(j)));
                }
                if set.name() == "bending" && j < nx {
                    bending_at = Some(j / 3);
                }
            }
            let (j, f) = largest_free(&total, &problem.free);
            let short = bending_at.map_or(String::new(), |node| {
                format!(
                    " | bending node {node}: shortest segment {:.2e} m",
                    shortest_segment(&sim, q, node)
                )
            });
            println!(
                "step {step} it {it} largest {f:.2e} N @{} | {}{short}",
                unknown(j),
                terms.join(" ")
            );
        }
    }
    Ok(())
}

/// (index, magnitude) of the largest free entry of `g`.
fn largest_free(g: &[f64], free: &[bool]) -> (usize, f64) {
    g.iter()
        .zip(free)
        .enumerate()
        .filter(|(_, (_, &f))| f)
        .fold(
            (0, 0.0),
            |best, (j, (v, _))| if v.abs() > best.1 { (j, v.abs()) } else { best },
        )
}

/// Shortest distance, at `q`, from `node` to a real neighbour along any of
/// its yarns in the step's assignment.
fn shortest_segment(sim: &Simulation, q: &[f64], node: usize) -> f64 {
    let at = |k: usize| {
        let x = sim.layout.x(k);
        nalgebra::Vector3::new(q[x], q[x + 1], q[x + 2])
    };
    let mut shortest = f64::INFINITY;
    for (yi, yarn) in sim.fabric.yarns.iter().enumerate() {
        let real: Vec<usize> = sim.assignment.real_points(&sim.layout, yi).collect();
        for (k, &p) in real.iter().enumerate() {
            if yarn.points[p].node != node || sim.assignment.is_eil(&sim.layout, PointRef { yarn: yi, point: p }) {
                continue;
            }
            for nb in [k.checked_sub(1), Some(k + 1)].into_iter().flatten() {
                if let Some(&other) = real.get(nb) {
                    shortest = shortest.min((at(yarn.points[other].node) - at(node)).norm());
                }
            }
        }
    }
    shortest
}
