//! Relaxation benchmark: stockinette and linen stitch at N x N stitches.
//!
//! Prints, per case: nodes, DOFs, Newton iterations, seconds to
//! equilibrium (the default `RelaxOptions` tolerance), seconds per Newton
//! iteration, peak resident memory, the final static residual, the relaxed
//! energy and bounding box, and the relaxation steps (in brackets those
//! that ended early at a closed segment, `sim::problem::tripwire`); then the fitted exponent of seconds per iteration against DOFs.
//!
//! Each case runs in a child process so its peak memory (`VmHWM`) is its
//! own. Not a test. Run with
//! `cargo run --release --no-default-features --example bench_relax -- [SIZES]`
//! where SIZES defaults to `20,40` (add 80 for the full table: minutes).
//!
//! `-- --spread SIZES SEEDS` measures how much the iteration counts move
//! under perturbations far below any physical scale: each case is run
//! unperturbed and with SEEDS-1 seeded jitters of every compiled node
//! position by up to 1 nm (the yarn radius is 0.75 mm). The float
//! patterns' counts depend on rounding (docs/RELAX.md, "Sensitivity to rounding"), so a single count
//! is one sample of a spread; this prints the spread.
//!
//! `KNITSIM_BENCH_BENDING=split` (or `eigen`) picks the bending stencils'
//! PSD Hessian (`SimParams::bending_hessian`) for every case run.
//!
//! `--case NAME N [SEED [STOP]]` runs one case (with the environment
//! variable `KNITSIM_BENCH_TRACE` set it prints every Newton iteration and
//! every step's static residual on stderr); `--spread SIZES SEEDS
//! [STOP]` passes STOP on. STOP is `AssignParams::stop_fraction` (default
//! 0: off; docs/RELAX.md, "Slide stops", measured 0.05).
//!
//! `-- --iteration-cost SIZES REPS` measures seconds per Newton iteration
//! on a workload that does not depend on when the equilibrium test happens
//! to pass: the first two relaxation steps (each runs to its Newton cap
//! unless a segment closes first; the second has the first EIL points), `REPS` times per
//! case, sizes interleaved, keeping each case's fastest run. The development
//! machine's speed drifts by up to 25% over minutes (docs/BENCHMARKS.md), so single runs
//! of different sizes are not comparable; the minimum over interleaved
//! repetitions is. Prints the exponent of seconds per iteration against
//! DOFs between consecutive sizes and fitted over all of them.
//!
//! `--shape-gap G`, before or after any mode, compiles every case with the
//! layout's shape points thinned at G yarn diameters
//! (`CompileOptions::shape_gap`, docs/RELAX.md, "Shape gap").
//!
//! `-- --orderings SIZES [STEPS]` prints, for each case's Newton matrix
//! after STEPS relaxation steps (default 0: the first one), the Cholesky
//! factor's entries, multiply-adds and numeric factorization seconds
//! (fastest of 3, the solver's residual probe included) under scalar and
//! grouped AMD (`solver::linear::Ordering`), and which one the solver's
//! default rule keeps.

#[path = "common/mod.rs"]
mod common;

use common::{compiled, jitter};
use knitsim::scene::params_for;
use knitsim::sim::{relax, RelaxOptions, Simulation};
use knitsim::solver::linear::{DirectParams, DirectSolver, LinearSolver, Ordering};
use knitsim::solver::newton::{IterStats, Problem};
use std::process::Command;
use std::time::Instant;

const PATTERNS: [&str; 2] = ["stockinette", "linen-stitch"];

/// Environment variable choosing the bending stencils' PSD Hessian
/// (`eigen` or `split`, `SimParams::bending_hessian`) for `--case` and the
/// modes that run it; unset: the default.
const BENDING_VAR: &str = "KNITSIM_BENCH_BENDING";

fn main() -> anyhow::Result<()> {
    let mut args: Vec<String> = std::env::args().collect();
    // `--shape-gap G` (anywhere): compile with `CompileOptions::shape_gap`
    // = G. Passed to the child processes through the environment.
    if let Some(i) = args.iter().position(|a| a == "--shape-gap") {
        let gap: f64 = args.get(i + 1).map(|g| g.parse()).transpose()?.unwrap_or(0.0);
        std::env::set_var(common::SHAPE_GAP_VAR, gap.to_string());
        args.drain(i..(i + 2).min(args.len()));
    }
    if args.get(1).map(String::as_str) == Some("--case") {
        let seed = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(0);
        let stop = args.get(5).map(|s| s.parse()).transpose()?.unwrap_or(0.0);
        return run_case(&args[2], args[3].parse()?, seed, stop);
    }
    if args.get(1).map(String::as_str) == Some("--spread") {
        let stop = args.get(4).map(String::as_str).unwrap_or("0");
        return spread(&args[0], &args[2], args[3].parse()?, stop);
    }
    if args.get(1).map(String::as_str) == Some("--fixed-steps") {
        return fixed_steps(&args[2], args[3].parse()?, args[4].parse()?);
    }
    if args.get(1).map(String::as_str) == Some("--orderings") {
        let steps = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(0);
        return orderings(&args[2], steps);
    }
    if args.get(1).map(String::as_str) == Some("--iteration-cost") {
        return iteration_cost(&args[0], &args[2], args[3].parse()?);
    }
    let sizes: Vec<usize> = args
        .get(1)
        .map(String::as_str)
        .unwrap_or("20,40")
        .split(',')
        .map(str::parse)
        .collect::<Result<_, _>>()?;
    println!(
        "| pattern | stitches | nodes | DOFs | Newton its | s to equilibrium | s / Newton it | peak MiB | residual | energy (J) | extent (mm) | steps (closed) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut fit: Vec<(f64, f64)> = Vec::new();
    for name in PATTERNS {
        for &n in &sizes {
            let out = Command::new(&args[0]).args(["--case", name, &n.to_string()]).output()?;
            let row = String::from_utf8_lossy(&out.stdout);
            let row = row.trim();
            if !out.status.success() || row.is_empty() {
                println!(
                    "| {name} | {n}x{n} | failed: {} |",
                    String::from_utf8_lossy(&out.stderr).trim()
                );
                continue;
            }
            println!("{row}");
            let cols: Vec<&str> = row.split('|').map(str::trim).collect();
            if let (Ok(dofs), Ok(per_it)) = (cols[4].parse::<f64>(), cols[7].parse::<f64>()) {
                fit.push((dofs.ln(), per_it.ln()));
            }
        }
    }
    if sizes.len() >= 2 && fit.len() >= 2 {
        println!(
            "\nseconds per Newton iteration ~ DOFs^{:.2} (least squares over all rows)",
            slope(&fit)
        );
    }
    Ok(())
}

/// Least-squares slope of `(x, y)` points.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx).powi(2))
    });
    num / den
}

/// The `--fixed-steps` runs of one case.
struct CostRuns {
    pattern: &'static str,
    n: usize,
    dofs: f64,
    iterations: usize,
    /// Seconds per Newton iteration, one entry per run.
    per_it: Vec<f64>,
}

impl CostRuns {
    fn fastest(&self) -> f64 {
        self.per_it.iter().copied().fold(f64::INFINITY, f64::min)
    }
}

/// Seconds per Newton iteration of the first two relaxation steps, the
/// fastest of `reps` interleaved runs per case (see the module docs).
fn iteration_cost(exe: &str, sizes: &str, reps: usize) -> anyhow::Result<()> {
    let sizes: Vec<usize> = sizes.split(',').map(str::parse).collect::<Result<_, _>>()?;
    let mut runs: Vec<CostRuns> = Vec::new();
    for _ in 0..reps.max(1) {
        for pattern in PATTERNS {
            for &n in &sizes {
                let out = Command::new(exe)
                    .args(["--fixed-steps", pattern, &n.to_string(), "2"])
                    .output()?;
                let text = String::from_utf8_lossy(&out.stdout);
                let v: Vec<f64> = text.split_whitespace().filter_map(|t| t.parse().ok()).collect();
                anyhow::ensure!(out.status.success() && v.len() == 3, "{pattern} {n}: {text}");
                match runs.iter_mut().find(|r| r.pattern == pattern && r.n == n) {
                    Some(r) => r.per_it.push(v[2] / v[1]),
                    None => runs.push(CostRuns {
                        pattern,
                        n,
                        dofs: v[0],
                        iterations: v[1] as usize,
                        per_it: vec![v[2] / v[1]],
                    }),
                }
            }
        }
    }
    println!("| pattern | stitches | DOFs | Newton its per run | fastest s / it | all runs s / it |");
    println!("|---|---|---|---|---|---|");
    for r in &runs {
        let all: Vec<String> = r.per_it.iter().map(|s| format!("{s:.4}")).collect();
        println!(
            "| {} | {n}x{n} | {} | {} | {:.4} | {} |",
            r.pattern,
            r.dofs,
            r.iterations,
            r.fastest(),
            all.join(", "),
            n = r.n
        );
    }
    for pattern in PATTERNS {
        let pts: Vec<(f64, f64)> = runs
            .iter()
            .filter(|r| r.pattern == pattern)
            .map(|r| (r.dofs.ln(), r.fastest().ln()))
            .collect();
        let steps: Vec<String> = pts.windows(2).map(|w| format!("{:.2}", slope(w))).collect();
        println!(
            "{pattern}: fastest s / it ~ DOFs^({}) between consecutive sizes, DOFs^{:.2} fitted",
            steps.join(", "),
            slope(&pts)
        );
    }
    Ok(())
}

/// Per case, after `steps` relaxation steps (0: the compiled state), the
/// next Newton matrix's factor under scalar and grouped AMD: entries,
/// multiply-adds ([`DirectSolver::factor_flops`]) and the numeric
/// factorization's seconds (fastest of 3, the residual probe included),
/// and which one the solver's default rule keeps.
fn orderings(sizes: &str, steps: usize) -> anyhow::Result<()> {
    println!("| pattern | stitches | steps before | DOFs | scalar AMD: entries | Gflop | s | grouped AMD: entries | Gflop | s | default keeps |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for name in PATTERNS {
        for n in sizes.split(',') {
            let n: usize = n.parse()?;
            let opts = RelaxOptions::default();
            let fabric = compiled(name, n)?;
            let params = params_for(&fabric, None)?;
            let mut sim = Simulation::new(fabric, params, LinearSolver::direct(), opts.h_initial);
            if steps > 0 {
                let opts = RelaxOptions {
                    tol: 0.0,
                    max_steps: steps,
                    ..opts
                };
                relax(&mut sim, opts, None, &mut |_, _| {}, &mut |_, _| {})?;
            }
            let mut problem = sim.problem(Some((sim.schedule().h, sim.q())))?;
            let mut h = problem.hessian_pattern();
            let mut g = vec![0.0; sim.q().len()];
            problem.gradient_hessian(sim.q(), &mut g, &mut h)?;
            let mut cells = Vec::new();
            for ordering in [Some(Ordering::Scalar), Some(Ordering::Grouped), None] {
                let mut solver = DirectSolver::new(DirectParams {
                    ordering,
                    ..DirectParams::default()
                });
                solver.set_ordering_groups(&problem.ordering_groups());
                solver.analyze(&h)?;
                let mut fastest = f64::INFINITY;
                for _ in 0..3 {
                    let t = Instant::now();
                    solver.factorize(&h)?;
                    fastest = fastest.min(t.elapsed().as_secs_f64());
                }
                match ordering {
                    Some(_) => cells.push(format!(
                        "{} | {:.2} | {fastest:.4}",
                        solver.factor_len().unwrap_or(0),
                        solver.factor_flops().unwrap_or(f64::NAN) * 1e-9
                    )),
                    None => cells.push(format!("{:?}", solver.ordering())),
                }
            }
            println!("| {name} | {n}x{n} | {steps} | {} | {} |", h.n, cells.join(" | "));
        }
    }
    Ok(())
}

/// Prints `DOFs iterations seconds` for the first `steps` relaxation steps
/// of a case, with the equilibrium test off so every step runs its course.
fn fixed_steps(name: &str, n: usize, steps: usize) -> anyhow::Result<()> {
    let fabric = compiled(name, n)?;
    let opts = RelaxOptions {
        tol: 0.0,
        max_steps: steps,
        ..RelaxOptions::default()
    };
    let params = params_for(&fabric, None)?;
    let mut sim = Simulation::new(fabric, params, LinearSolver::direct(), opts.h_initial);
    let t0 = Instant::now();
    let rep = relax(&mut sim, opts, None, &mut |_, _| {}, &mut |_, _| {})?;
    println!(
        "{} {} {:.4}",
        sim.q().len(),
        rep.newton_iterations,
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Per case, the Newton iterations and seconds of `seeds` runs (seed 0
/// unperturbed), then their median.
fn spread(exe: &str, sizes: &str, seeds: u64, stop: &str) -> anyhow::Result<()> {
    println!("| pattern | stitches | Newton its per seed | median its | seconds per seed | median s |");
    println!("|---|---|---|---|---|---|");
    for name in PATTERNS {
        for n in sizes.split(',') {
            let (mut its, mut secs) = (Vec::new(), Vec::new());
            for seed in 0..seeds.max(1) {
                let out = Command::new(exe)
                    .args(["--case", name, n, &seed.to_string(), stop])
                    .output()?;
                let row = String::from_utf8_lossy(&out.stdout);
                let cols: Vec<&str> = row.split('|').map(str::trim).collect();
                match (
                    cols.get(5).map(|c| c.parse::<usize>()),
                    cols.get(6).map(|c| c.parse::<f64>()),
                ) {
                    (Some(Ok(i)), Some(Ok(s))) if out.status.success() && !row.contains("not converged") => {
                        its.push(i.to_string());
                        secs.push(s);
                    }
                    _ => {
                        its.push("failed".into());
                        secs.push(f64::NAN);
                    }
                }
            }
            let mut sorted: Vec<usize> = its.iter().filter_map(|i| i.parse().ok()).collect();
            sorted.sort_unstable();
            let mut s_sorted: Vec<f64> = secs.iter().copied().filter(|s| s.is_finite()).collect();
            s_sorted.sort_by(f64::total_cmp);
            let med = |v: &[usize]| v.get(v.len() / 2).map_or("-".into(), |m| m.to_string());
            let med_s = s_sorted
                .get(s_sorted.len() / 2)
                .map_or("-".into(), |m| format!("{m:.2}"));
            let secs: Vec<String> = secs.iter().map(|s| format!("{s:.2}")).collect();
            println!(
                "| {name} | {n}x{n} | {} | {} | {} | {med_s} |",
                its.join(", "),
                med(&sorted),
                secs.join(", ")
            );
        }
    }
    Ok(())
}

/// One case, printed as a table row; `seed` as in [`jitter`]. The last
/// column is the potential energy of the relaxed state: two states that
/// both pass the equilibrium test can differ in it by a quarter
/// (docs/RELAX.md, "What the default tolerance means").
fn run_case(name: &str, n: usize, seed: u64, stop_fraction: f64) -> anyhow::Result<()> {
    let mut fabric = compiled(name, n)?;
    jitter(&mut fabric, seed);
    let nodes = fabric.nodes.len();
    let opts = RelaxOptions::default();
    let mut params = params_for(&fabric, None)?;
    params.assign.stop_fraction = stop_fraction;
    if let Ok(model) = std::env::var(BENDING_VAR) {
        params.bending_hessian = model.parse().map_err(anyhow::Error::msg)?;
    }
    let mut sim = Simulation::new(fabric, params, LinearSolver::direct(), opts.h_initial);
    let dofs = sim.q().len();
    let t0 = Instant::now();
    let mut phases = [0.0f64; 3];
    // `KNITSIM_BENCH_TRACE=1`: every Newton iteration and step on stderr.
    let trace = std::env::var_os("KNITSIM_BENCH_TRACE").is_some();
    let mut add_phases = |s: &IterStats, eil: usize| {
        if trace {
            eprintln!(
                "  it {:2} E {:.6e} |g| {:.3e} step {:.2e} {:?} damping {:.0e} trials {} eil {} | {:.3} {:.3} {:.3} s",
                s.iteration,
                s.energy,
                s.residual,
                s.step,
                s.direction,
                s.damping,
                s.line_search_trials,
                eil,
                s.assembly_s,
                s.solve_s,
                s.line_search_s
            );
        }
        phases[0] += s.assembly_s;
        phases[1] += s.solve_s;
        phases[2] += s.line_search_s;
    };
    let rep = relax(&mut sim, opts, None, &mut add_phases, &mut |k, r| {
        if trace {
            eprintln!("step {k}: static residual {r:.3e}");
        }
    })?;
    let secs = t0.elapsed().as_secs_f64();
    // On stderr, so that `--spread` still reads one row from stdout.
    eprintln!(
        "{name} {n}x{n}: assembly {:.2} s, linear solves {:.2} s, line search {:.2} s, \
         the rest (step set-up, re-assignment) {:.2} s, of {secs:.2} s",
        phases[0],
        phases[1],
        phases[2],
        secs - phases.iter().sum::<f64>()
    );
    let energy: f64 = sim.problem(None)?.breakdown(sim.q()).iter().map(|(_, e)| e).sum();
    let extent = extent_mm(&sim.snapshot());
    println!(
        "| {name} | {n}x{n} | {nodes} | {dofs} | {} | {secs:.2} | {:.4} | {:.0} | {:.2e}{} | {energy:.4e} | {extent} | {} ({}) |",
        rep.newton_iterations,
        secs / rep.newton_iterations.max(1) as f64,
        peak_mib(),
        rep.residual,
        if rep.converged { "" } else { " (not converged)" },
        rep.steps,
        rep.closed_segment_steps
    );
    Ok(())
}

/// The relaxed fabric's bounding box, `x by y by z` in millimetres: what a
/// designer sees of the shape (width, height, and how far it curls).
fn extent_mm(f: &knitsim::topology::Fabric) -> String {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for node in &f.nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(node.x[k]);
            hi[k] = hi[k].max(node.x[k]);
        }
    }
    let mm = |k: usize| (hi[k] - lo[k]) * 1e3;
    format!("{:.1} x {:.1} x {:.1}", mm(0), mm(1), mm(2))
}

/// Peak resident set size of this process (Linux `VmHWM`), MiB; NaN elsewhere.
fn peak_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1).and_then(|v| v.parse::<f64>().ok()))
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}
