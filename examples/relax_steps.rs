//! Diagnostic: one line per relaxation step of a shipped pattern resized to
//! `N x N` stitches, on the exact schedule `knitsim relax` uses
//! (`sim::configure_relax`).
//!
//! ```text
//! cargo run --release --no-default-features --example relax_steps -- NAME N [PAST [SEED]]
//! ```
//!
//! Per step: Newton iterations; how many of them lowered the energy by
//! less than 0.1% ("stalled": in the traces these are a sliding contact
//! pressed against a real neighbour, docs/RELAX.md, "Slide stops"); the EIL count; the
//! static residual where the step ended and which unknown carries the
//! largest free force; and the real segments shorter than 1% of the yarn's
//! mean rest segment, by what their two ends are (contact, resolution node,
//! yarn end). With `PAST > 0` the run goes on for that many steps after the
//! equilibrium test first passes, to show whether the state stays put.
//! `SEED` jitters the compiled nodes by up to 1 nm as `bench_relax --spread`
//! does. Not a test.

#[path = "common/mod.rs"]
mod common;

use common::relaxing;
use knitsim::sim::{RelaxOptions, Simulation};
use knitsim::topology::Fabric;
use std::collections::BTreeMap;
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(String::as_str).unwrap_or("linen-stitch");
    let n: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(20);
    let past: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(0);
    let seed: u64 = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(0);
    let opts = RelaxOptions::default();
    let mut sim = relaxing(name, n, seed)?;
    let kinds = point_kinds(&sim.fabric);
    println!("{name} {n}x{n}, {} unknowns, seed {seed}", sim.q.len());
    let t0 = Instant::now();
    let (mut iterations, mut passed_at) = (0, None);
    for step in 1..=opts.max_steps {
        let mut energies = Vec::new();
        let rep = sim.step(false, None, &mut |s, _| energies.push(s.energy))?;
        iterations += rep.newton_iterations;
        let stalled = energies.windows(2).filter(|e| e[0] - e[1] < 1e-3 * e[0].abs()).count();
        let residual = sim.static_residual()?;
        println!(
            "step {step:3} its {:2} stalled {:2} eil {:5} residual {residual:.2e} at {} | short {} | {iterations} its {:.1} s",
            rep.newton_iterations,
            stalled,
            rep.eil_count,
            largest_force(&sim, &kinds)?,
            short_segments(&sim, &kinds),
            t0.elapsed().as_secs_f64()
        );
        if residual <= opts.tol && passed_at.is_none() {
            passed_at = Some(step);
            println!("equilibrium test passed after {iterations} Newton iterations");
        }
        if passed_at.is_some_and(|p| step >= p + past) {
            break;
        }
    }
    Ok(())
}

/// What each yarn point is, yarn after yarn: 'C' contact, 'R' resolution
/// node, 'E' yarn end.
fn point_kinds(f: &Fabric) -> Vec<Vec<char>> {
    let mut kinds: Vec<Vec<char>> = f.yarns.iter().map(|y| vec!['R'; y.points.len()]).collect();
    for c in &f.contacts {
        for p in [c.front, c.back] {
            kinds[p.yarn][p.point] = 'C';
        }
    }
    for k in &mut kinds {
        if let Some(first) = k.first_mut() {
            *first = 'E';
        }
        if let Some(last) = k.last_mut() {
            *last = 'E';
        }
    }
    kinds
}

/// The free unknown with the largest force, described.
fn largest_force(sim: &Simulation, kinds: &[Vec<char>]) -> anyhow::Result<String> {
    let g = sim.problem(None)?.free_gradient(&sim.q)?;
    let (i, _) = g.iter().enumerate().fold(
        (0, 0.0f64),
        |(bi, bv), (i, v)| if v.abs() > bv { (i, v.abs()) } else { (bi, bv) },
    );
    let nodes = sim.layout.n_nodes;
    if i < 3 * nodes {
        return Ok(format!("x of node {}", i / 3));
    }
    let point = i - 3 * nodes;
    let yarn = sim.layout.yarn_offsets.partition_point(|&o| o <= point) - 1;
    let pi = point - sim.layout.yarn_offsets[yarn];
    let eil = if sim.assignment.eil[point] { ", EIL" } else { "" };
    Ok(format!("u of yarn {yarn} point {pi} ({}{eil})", kinds[yarn][pi]))
}

/// Real segments under 1% of their yarn's mean rest segment, counted by
/// the kinds of their ends.
fn short_segments(sim: &Simulation, kinds: &[Vec<char>]) -> String {
    let f = sim.snapshot();
    let mut count: BTreeMap<String, usize> = BTreeMap::new();
    for (yi, y) in f.yarns.iter().enumerate() {
        let mut real: Vec<usize> = (0..y.points.len()).filter(|&p| !y.points[p].eil).collect();
        real.sort_by(|&a, &b| y.points[a].u.total_cmp(&y.points[b].u));
        for w in real.windows(2) {
            if y.points[w[1]].u - y.points[w[0]].u < 0.01 * sim.rest.rest_seg[yi] {
                let (a, b) = (kinds[yi][w[0]], kinds[yi][w[1]]);
                *count.entry(format!("{}{}", a.min(b), a.max(b))).or_default() += 1;
            }
        }
    }
    if count.is_empty() {
        return "none".into();
    }
    count
        .iter()
        .map(|(k, v)| format!("{k} {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}
