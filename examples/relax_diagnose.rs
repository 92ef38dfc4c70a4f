//! Relaxation diagnostics, one subcommand each. Not a test.
//!
//! ```text
//! cargo run --release --no-default-features --example relax_diagnose -- SUBCOMMAND ...
//! ```
//!
//! - `gaps [PATTERN] [--kc 10,1000]`: how far the soft EIL contact
//!   constraint lets contacts open at equilibrium: relaxes a pattern file
//!   once per `kc_factor` and prints the EIL gaps (distance between where the
//!   two yarns put a contact) against the yarn radius.
//! - `steps [NAME] [N] [--past P] [--seed S]`: one line per relaxation step
//!   of a shipped pattern resized to `N x N` stitches, on the exact schedule
//!   `knitsim relax` uses (`sim::relax_schedule`). Per step: Newton
//!   iterations; how many of them lowered the energy by less than 0.1%
//!   ("stalled": in the traces these are a sliding contact pressed against a
//!   real neighbour, docs/RELAX.md, "Slide stops"); the EIL count; the static
//!   residual where the step ended and which unknown carries the largest free
//!   force; and the real segments shorter than 1% of the yarn's mean rest
//!   segment, by what their two ends are (contact, resolution node, yarn
//!   end). With `--past P` the run goes on for P steps after the equilibrium
//!   test first passes, to show whether the state stays put.
//! - `stalls [NAME] [N] [--seed S] [--steps K]`: which energy term carries
//!   the largest free force at every accepted Newton iterate of K relaxation
//!   steps (`Simulation::record_iterates`), evaluated under the assignment
//!   the step used: the largest free force, the term and unknown (`x` of a
//!   node or `u` of a point) it sits on, every term whose largest force is
//!   above 1 N, and for the node carrying the largest bending force its
//!   shortest real segment. (Friction is evaluated with the anchors as the
//!   step left them, so its column is approximate.) docs/RELAX.md, "Closed
//!   segments", describes what stalls the float patterns' Newton steps.
//! - `trace [PATTERN] [--steps K]`: every Newton iteration (damping,
//!   direction, line-search trials) of K steps and, per step, which energy
//!   term carries the largest free force, and how many unknowns Newton held
//!   at a bound. Environment: `KNITSIM_DIAG_STOP` sets
//!   `assign.stop_fraction` (docs/RELAX.md, "Slide stops"),
//!   `KNITSIM_DIAG_H` the time step (default 1 s), `KNITSIM_DIAG_HMAX` its
//!   largest value (default the time step), `KNITSIM_DIAG_RTOL` Newton's
//!   relative tolerance (default 1e-8), and `KNITSIM_DIAG_FD` (any value) adds
//!   a global finite-difference check of every term before and after each
//!   step.
//!
//! `--seed` jitters the compiled nodes by up to 1 nm as `bench_relax
//! --spread` does.

#[path = "common/mod.rs"]
mod common;

use clap::{Parser, Subcommand};
use common::relaxing;
use knitsim::app::load_fabric;
use knitsim::sim::{relax, RelaxOptions, Simulation};
use knitsim::solver::linear::LinearSolver;
use knitsim::solver::newton::Problem;
use knitsim::topology::{Fabric, PointRef};
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "Relaxation diagnostics (see the example's module docs)")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// EIL gaps at equilibrium against the yarn radius, per `kc_factor`.
    Gaps {
        #[arg(default_value = "patterns/linen-stitch.knit")]
        pattern: String,
        /// Comma-separated `kc_factor` values.
        #[arg(long, default_value = "10,1000")]
        kc: String,
    },
    /// One line per relaxation step of a shipped pattern at N x N.
    Steps {
        #[arg(default_value = "linen-stitch")]
        name: String,
        #[arg(default_value_t = 20)]
        n: usize,
        /// Steps to go on after the equilibrium test first passes.
        #[arg(long, default_value_t = 0)]
        past: usize,
        #[arg(long, default_value_t = 0)]
        seed: u64,
    },
    /// The term with the largest free force at every accepted iterate.
    Stalls {
        #[arg(default_value = "linen-stitch")]
        name: String,
        #[arg(default_value_t = 20)]
        n: usize,
        #[arg(long, default_value_t = 0)]
        seed: u64,
        #[arg(long, default_value_t = 6)]
        steps: usize,
    },
    /// Every Newton iteration of a few steps, with the largest force per term.
    Trace {
        #[arg(default_value = "patterns/stockinette.knit")]
        pattern: String,
        #[arg(long, default_value_t = 5)]
        steps: usize,
    },
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Gaps { pattern, kc } => gaps(&pattern, &kc),
        Command::Steps { name, n, past, seed } => steps(&name, n, past, seed),
        Command::Stalls { name, n, seed, steps } => stalls(&name, n, seed, steps),
        Command::Trace { pattern, steps } => trace(&pattern, steps),
    }
}

/// `KNITSIM_DIAG_<name>` parsed, if set and valid.
fn env<T: std::str::FromStr>(name: &str) -> Option<T> {
    std::env::var(format!("KNITSIM_DIAG_{name}"))
        .ok()
        .and_then(|s| s.parse().ok())
}

fn gaps(path: &str, kc: &str) -> anyhow::Result<()> {
    let factors: Vec<f64> = kc.split(',').map(str::parse).collect::<Result<_, _>>()?;
    println!("| kc_factor | steps | Newton its | seconds | residual | EIL contacts | max gap / r | median gap / r |");
    println!("|---|---|---|---|---|---|---|---|");
    for kc in factors {
        let fabric = load_fabric(std::path::Path::new(path), &Default::default())?.fabric;
        let mut params = knitsim::scene::params_for(&fabric, None)?;
        params.rod.kc_factor = kc;
        let opts = RelaxOptions::default();
        let mut sim = Simulation::new(fabric, params, LinearSolver::direct(), opts.h_initial);
        let t = Instant::now();
        let rep = relax(&mut sim, opts, None, &mut |_, _| {}, &mut |_, _| {})?;
        let secs = t.elapsed().as_secs_f64();
        let r = sim.params().rod.radius;
        let mut gaps: Vec<f64> = sim.eil_gaps().iter().map(|g| g / r).collect();
        gaps.sort_by(f64::total_cmp);
        let max = gaps.last().copied().unwrap_or(0.0);
        let median = gaps.get(gaps.len() / 2).copied().unwrap_or(0.0);
        println!(
            "| {kc} | {} | {} | {secs:.2} | {:.2e}{} | {} | {max:.4} | {median:.4} |",
            rep.steps,
            rep.newton_iterations,
            rep.residual,
            if rep.converged { "" } else { " (not converged)" },
            gaps.len()
        );
    }
    Ok(())
}

fn steps(name: &str, n: usize, past: usize, seed: u64) -> anyhow::Result<()> {
    let opts = RelaxOptions::default();
    let mut sim = relaxing(name, n, seed)?;
    let kinds = point_kinds(sim.fabric());
    println!("{name} {n}x{n}, {} unknowns, seed {seed}", sim.q().len());
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

fn stalls(name: &str, n: usize, seed: u64, steps: usize) -> anyhow::Result<()> {
    let mut sim = relaxing(name, n, seed)?;
    let nx = 3 * sim.fabric().nodes.len();
    let unknown = |j: usize| {
        if j < nx {
            format!("x{}", j / 3)
        } else {
            format!("u{}", j - nx)
        }
    };
    sim.record_iterates(true);
    for step in 0..steps {
        sim.step(false, None, &mut |_, _| {})?;
        let log = sim.take_iterates();
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

fn trace(path: &str, steps: usize) -> anyhow::Result<()> {
    let loaded = load_fabric(std::path::Path::new(path), &Default::default())?;
    let mut params = knitsim::scene::params_for(&loaded.fabric, None)?;
    params.assign.stop_fraction = env("STOP").unwrap_or(0.0);
    let mut sim = Simulation::new(loaded.fabric, params, LinearSolver::direct(), env("H").unwrap_or(1.0));
    let schedule = sim.schedule_mut();
    schedule.newton.max_iterations = 20;
    schedule.h_max = env("HMAX").unwrap_or(schedule.h);
    schedule.newton.rel_residual_tol = env("RTOL").unwrap_or(1e-8);
    println!("dofs {}", sim.q().len());
    if std::env::var_os("KNITSIM_DIAG_FD").is_some() {
        fd_check(&sim)?;
    }
    for k in 0..steps {
        let mut cb = |s: &knitsim::solver::newton::IterStats, eil: usize| {
            println!(
                "  it {:3} E {:.6e} |g| {:.3e} rel {:.2e} dec {:.2e} step {:.2e} {:?} damp {:.1e} ls {} held {} eil {}",
                s.iteration,
                s.energy,
                s.residual,
                s.rel_residual,
                s.decrement,
                s.step,
                s.direction,
                s.damping,
                s.line_search_trials,
                s.held,
                eil
            )
        };
        let r = sim.step(false, None, &mut cb)?;
        let p = sim.problem(None)?;
        let mut worst = Vec::new();
        for s in &p.sets {
            let mut g = vec![0.0; sim.q().len()];
            let mut h = p.hessian_pattern();
            s.accumulate(sim.q(), &p.free, &mut g, &mut h, false)?;
            let m = g.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            worst.push(format!("{}={:.2e}", s.name(), m));
        }
        println!(
            "step {k} h {:.1e} its {} conv {} static {:.3e} | {}",
            r.h,
            r.newton_iterations,
            r.converged,
            sim.static_residual()?,
            worst.join(" ")
        );
        if std::env::var_os("KNITSIM_DIAG_FD").is_some() {
            fd_check(&sim)?;
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
    let g = sim.problem(None)?.free_gradient(sim.q())?;
    let (i, _) = g.iter().enumerate().fold(
        (0, 0.0f64),
        |(bi, bv), (i, v)| if v.abs() > bv { (i, v.abs()) } else { (bi, bv) },
    );
    let nodes = sim.layout().n_nodes;
    if i < 3 * nodes {
        return Ok(format!("x of node {}", i / 3));
    }
    let point = i - 3 * nodes;
    let yarn = sim.layout().yarn_offsets.partition_point(|&o| o <= point) - 1;
    let pi = point - sim.layout().yarn_offsets[yarn];
    let eil = if sim.assignment().eil[point] { ", EIL" } else { "" };
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
            if y.points[w[1]].u - y.points[w[0]].u < 0.01 * sim.rest().rest_seg[yi] {
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
        let x = sim.layout().x(k);
        nalgebra::Vector3::new(q[x], q[x + 1], q[x + 2])
    };
    let mut shortest = f64::INFINITY;
    for (yi, yarn) in sim.fabric().yarns.iter().enumerate() {
        let real: Vec<usize> = sim.assignment().real_points(sim.layout(), yi).collect();
        for (k, &p) in real.iter().enumerate() {
            if yarn.points[p].node != node || sim.assignment().is_eil(sim.layout(), PointRef { yarn: yi, point: p }) {
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

/// Global finite-difference check of the assembled gradient and Hessian, per term.
fn fd_check(sim: &Simulation) -> anyhow::Result<()> {
    use knitsim::solver::assembly::AnyStencilSet;
    let p = sim.problem(Some((sim.schedule().h, sim.q())))?;
    let n = sim.q().len();
    let mut rng = 12345u64;
    let mut rnd = || {
        rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((rng >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let d: Vec<f64> = (0..n).map(|i| if p.free[i] { rnd() * 1e-4 } else { 0.0 }).collect();
    for s in &p.sets {
        let s: &dyn AnyStencilSet = s.as_ref();
        let eval = |q: &[f64]| -> (f64, Vec<f64>, Vec<f64>) {
            let mut g = vec![0.0; n];
            let mut h = p.hessian_pattern();
            h.values.fill(0.0);
            s.accumulate(q, &p.free, &mut g, &mut h, false).unwrap();
            let mut hd = vec![0.0; n];
            h.mul_vec(&d, &mut hd);
            (s.energy(q), g, hd)
        };
        let (_, g0, hd) = eval(sim.q());
        for eps in [1e-2, 1e-3] {
            let qp: Vec<f64> = sim.q().iter().zip(&d).map(|(a, b)| a + eps * b).collect();
            let qm: Vec<f64> = sim.q().iter().zip(&d).map(|(a, b)| a - eps * b).collect();
            let (ep, gp, _) = eval(&qp);
            let (em, gm, _) = eval(&qm);
            let gd: f64 = g0.iter().zip(&d).map(|(a, b)| a * b).sum();
            let fd_e = (ep - em) / (2.0 * eps);
            let mut num = 0.0;
            let mut den = 0.0;
            for i in 0..n {
                if !p.free[i] {
                    continue;
                }
                let f = (gp[i] - gm[i]) / (2.0 * eps);
                num += (f - hd[i]).powi(2);
                den += hd[i].powi(2);
            }
            println!(
                "{:16} eps {eps:.0e}: g.d {gd:.4e} fd {fd_e:.4e} | |Hd-fd|/|Hd| {:.2e} (|Hd| {:.2e})",
                s.name(),
                (num / den.max(1e-300)).sqrt(),
                den.sqrt()
            );
        }
    }
    Ok(())
}
