//! Benchmark: seconds per time step of a large knit dropped onto the
//! default drape scene's sphere, the setting of the EoL paper's Table 1
//! (its Knit1: 75,096 nodes, 0.5 ms steps).
//!
//! `cargo run --release --example bench_drape -- [PATTERN] [N] [STEPS] [DT]`
//!
//! Compiles the shipped pattern `PATTERN` (default `stockinette`) at
//! `N x N` stitches (default 97, 76,148 nodes), puts the default
//! scene's sphere under it (`app::drape::scene`: gravity, friction 0.3,
//! air drag) and runs `STEPS` backward Euler steps (default 3) of `DT`
//! seconds (default 5e-4) with the direct solver, each solved to the
//! dynamics' Newton tolerance. It starts from the compiled layout, not a
//! relaxed one: relaxing a swatch of this size first takes far longer than
//! the steps measured, and the first steps of an unrelaxed knit are the
//! harder ones (its loops spring while it falls), so the figure is an upper
//! bound for steps of a relaxed knit.
//!
//! Prints per step the wall time, Newton iterations and retries, then the
//! node and unknown counts, the median seconds per step, the time by term
//! and the peak resident memory (`VmHWM` of `/proc/self/status`).

use knitsim::app::drape::scene::with_default_scene;
use knitsim::sim::dynamics::{dynamic_params, schedule};
use knitsim::sim::Simulation;
use knitsim::solver::assembly::timing::TermTimes;
use knitsim::solver::linear::LinearSolver;
use std::time::Instant;

#[path = "common/mod.rs"]
mod common;

/// Peak resident memory of this process (MiB), where the kernel says.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).cloned().unwrap_or_else(|| "stockinette".into());
    let n: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(97);
    let steps: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(3);
    let dt: f64 = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(5e-4);

    let t = Instant::now();
    let fabric = common::compiled(&name, n)?;
    let base = knitsim::scene::params_for(&fabric, None)?;
    let mut params = dynamic_params(with_default_scene(base, &fabric));
    params.dynamics.dt = dt;
    params.dynamics.max_dt = Some(dt);
    let nodes = fabric.nodes.len();
    let mut sim = Simulation::new(fabric, params.clone(), LinearSolver::direct(), dt);
    let mut sched = schedule(&sim, &params.dynamics);
    println!(
        "{name} {n} x {n}: {nodes} nodes, {} unknowns, set up in {:.1} s",
        sim.layout().len(),
        t.elapsed().as_secs_f64()
    );

    let mut times = TermTimes::default();
    let mut per_step = Vec::new();
    let run = Instant::now();
    for k in 0..steps {
        let t = Instant::now();
        let rep = sim.step_with(&mut sched, true, None, &mut |_, _| {})?;
        let s = t.elapsed().as_secs_f64();
        per_step.push(s);
        times.merge(&rep.times);
        println!(
            "step {k}: h {:.1e} s, {} Newton, {} retries, converged {}, {s:.2} s",
            rep.h, rep.newton_iterations, rep.retries, rep.converged
        );
    }
    let wall = run.elapsed().as_secs_f64();
    per_step.sort_by(f64::total_cmp);
    let median = per_step.get(per_step.len() / 2).copied().unwrap_or(f64::NAN);
    println!(
        "median {median:.2} s per step ({steps} steps, {:.2e} s simulated at steps of up to {dt:.1e} s, {wall:.1} s)",
        sim.time()
    );
    println!("{}", times.shares_line(wall));
    match peak_rss_mib() {
        Some(m) => println!("peak resident memory {m:.0} MiB"),
        None => println!("peak resident memory: not available on this system"),
    }
    Ok(())
}
