//! Seconds per Newton iteration on a real relax problem: assembly plus one
//! linear solve, with the GPU (wgpu, f32 PCG) against the CPU solvers.
//!
//! The problem is the first proximal step of `knitsim relax` (h = 1 s) on a
//! square stockinette swatch sized to the requested number of unknowns, at
//! the compiled (unrelaxed) geometry. Per size it reports:
//! - assembly: gradient plus PSD-projected Hessian, shared by every solver;
//! - direct: numeric refactorization and solve with the symbolic analysis
//!   reused (what every Newton iteration after the first costs);
//! - cpu-cg and gpu: seconds per CG iteration (marginal, `(t(2N) - t(N)) / N`
//!   with a tolerance that never fires, so setup and transfers drop out),
//!   the iterations to the GPU's inexact-Newton tolerance (1e-5) and the
//!   time of that whole solve, value upload included for the GPU;
//! - per Newton iteration: assembly plus the solve, per solver.
//!
//! `cargo run --release --example bench_gpu_newton -- --sizes 5000,50000,500000`
//! (`--max-dofs` skips larger sizes, e.g. on a software adapter).

use clap::Parser;
use knitsim::sim::{SimParams, Simulation};
use knitsim::solver::linear::{pcg, BlockJacobi, CgParams, LinearSolver};
use knitsim::solver::newton::Problem;
use knitsim::sparse::CsrMatrix;
use std::time::Instant;

#[derive(Parser)]
struct Args {
    /// Target numbers of unknowns (the swatch is the nearest square).
    #[arg(long, value_delimiter = ',', default_values_t = [5_000, 50_000, 500_000])]
    sizes: Vec<usize>,
    /// Skip sizes above this many unknowns.
    #[arg(long, default_value_t = usize::MAX)]
    max_dofs: usize,
    /// N in the marginal per-iteration timing.
    #[arg(long, default_value_t = 20)]
    iters: usize,
    /// Relative tolerance of the "to tolerance" solves (the GPU Newton default).
    #[arg(long, default_value_t = 1e-5)]
    rel_tol: f64,
    /// Iteration cap of the "to tolerance" solves.
    #[arg(long, default_value_t = 5_000)]
    max_iter: usize,
}

const STOCKINETTE: &str = include_str!("../patterns/stockinette.knit");

/// The shipped stockinette chart resized to `side` x `side` stitches.
fn swatch(side: usize) -> anyhow::Result<knitsim::topology::Fabric> {
    let text = STOCKINETTE
        .replace("width: 16", &format!("width: {side}"))
        .replace("height: 16", &format!("height: {side}"));
    let parsed = knitsim::pattern::parse_str(&text, "stockinette")?;
    Ok(knitsim::topology::compile(&parsed.pattern, &Default::default())?)
}

fn dofs(side: usize) -> anyhow::Result<usize> {
    Ok(knitsim::sim::discretization::dofs::DofLayout::new(&swatch(side)?).len())
}

/// Smallest square swatch with at least `target` unknowns (DOFs grow as side^2).
fn side_for(target: usize) -> anyhow::Result<usize> {
    let per_stitch = dofs(8)? as f64 / 64.0;
    let mut side = ((target as f64 / per_stitch).sqrt().round() as usize).max(2);
    while side > 2 && dofs(side - 1)? >= target {
        side -= 1;
    }
    Ok(side)
}

/// Newton system of the first relax step: `(g, H, blocks)`.
fn newton_system(side: usize) -> anyhow::Result<(Vec<f64>, CsrMatrix, Vec<usize>, f64)> {
    let sim = Simulation::new(swatch(side)?, SimParams::default(), LinearSolver::direct(), 1.0);
    let mut problem = sim.problem(Some((sim.schedule().h, sim.q())))?;
    let mut h = problem.hessian_pattern();
    let mut g = vec![0.0; sim.q().len()];
    problem.gradient_hessian(sim.q(), &mut g, &mut h)?;
    let assembly = seconds(|| problem.gradient_hessian(sim.q(), &mut g, &mut h))?;
    Ok((g, h, problem.blocks(), assembly))
}

fn seconds<T, E>(f: impl FnOnce() -> Result<T, E>) -> Result<f64, E> {
    let start = Instant::now();
    f()?;
    Ok(start.elapsed().as_secs_f64())
}

/// Timings of one solver on one system.
struct Timing {
    per_iter: f64,
    iterations: usize,
    solve: f64,
}

fn cpu_cg(a: &CsrMatrix, b: &[f64], blocks: &[usize], args: &Args) -> Timing {
    let pre = BlockJacobi::new(a, blocks);
    let run = |max_iter, rel_tol| {
        let mut x = vec![0.0; a.n];
        let start = Instant::now();
        let r = pcg(a, b, &mut x, &pre, CgParams { rel_tol, max_iter });
        (start.elapsed().as_secs_f64(), r.iterations)
    };
    let per_iter = (run(2 * args.iters, 0.0).0 - run(args.iters, 0.0).0) / args.iters as f64;
    let start = Instant::now();
    let pre = BlockJacobi::new(a, blocks);
    let mut x = vec![0.0; a.n];
    let r = pcg(
        a,
        b,
        &mut x,
        &pre,
        CgParams {
            rel_tol: args.rel_tol,
            max_iter: args.max_iter,
        },
    );
    Timing {
        per_iter,
        iterations: r.iterations,
        solve: start.elapsed().as_secs_f64(),
    }
}

/// Refactorization plus solve with the symbolic analysis already done.
fn direct(a: &CsrMatrix, b: &[f64]) -> anyhow::Result<f64> {
    let mut solver = LinearSolver::direct();
    let mut x = vec![0.0; a.n];
    solver.solve(a, b, &mut x, &[])?;
    Ok(seconds(|| solver.solve(a, b, &mut x, &[]))?)
}

fn gpu(
    ctx: &knitsim::gpu::GpuContext,
    a: &CsrMatrix,
    b: &[f64],
    blocks: &[usize],
    args: &Args,
) -> anyhow::Result<(Timing, f64)> {
    use knitsim::gpu::{GpuPcg, GpuPcgParams};
    let start = Instant::now();
    let mut pcg = GpuPcg::new(ctx, a, blocks)?;
    let setup = start.elapsed().as_secs_f64();
    let zeros = vec![0.0; a.n];
    let params = |max_iter, rel_tol| GpuPcgParams {
        rel_tol,
        max_iter,
        ..Default::default()
    };
    pcg.solve(b, &zeros, &params(8, 0.0))?;
    let timed = |max_iter| seconds(|| pcg.solve(b, &zeros, &params(max_iter, 0.0)));
    let per_iter = (timed(2 * args.iters)? - timed(args.iters)?) / args.iters as f64;
    // A Newton iteration with the pattern resident: value upload and solve.
    let start = Instant::now();
    pcg.update_values(a)?;
    let (_, stats) = pcg.solve(b, &zeros, &params(args.max_iter, args.rel_tol))?;
    let timing = Timing {
        per_iter,
        iterations: stats.iterations,
        solve: start.elapsed().as_secs_f64(),
    };
    Ok((timing, setup))
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let ctx = knitsim::gpu::GpuContext::new()?;
    println!("adapter: {}", ctx.adapter);
    println!(
        "{:>8} {:>9} {:>10} | {:>9} {:>9} | {:>10} {:>6} {:>9} | {:>10} {:>6} {:>9} {:>8} | {:>9} {:>9} {:>9}",
        "stitches",
        "unknowns",
        "nnz",
        "assembly",
        "direct",
        "cg s/iter",
        "iters",
        "cg solve",
        "gpu s/iter",
        "iters",
        "gpu solve",
        "gpu set",
        "newton:dir",
        "newton:cg",
        "newton:gpu"
    );
    for &target in &args.sizes {
        if target > args.max_dofs {
            println!("{target:>19}: skipped (above --max-dofs {})", args.max_dofs);
            continue;
        }
        let side = side_for(target)?;
        let (g, a, blocks, assembly) = newton_system(side)?;
        let b: Vec<f64> = g.iter().map(|v| -v).collect();
        let direct_s = direct(&a, &b)?;
        let cg = cpu_cg(&a, &b, &blocks, &args);
        let (gpu, setup) = gpu(&ctx, &a, &b, &blocks, &args)?;
        println!(
            "{:>8} {:>9} {:>10} | {:>9.3e} {:>9.3e} | {:>10.3e} {:>6} {:>9.3e} | {:>10.3e} {:>6} {:>9.3e} {:>8.3} | {:>10.3e} {:>9.3e} {:>9.3e}",
            side * side,
            a.n,
            a.nnz(),
            assembly,
            direct_s,
            cg.per_iter,
            cg.iterations,
            cg.solve,
            gpu.per_iter,
            gpu.iterations,
            gpu.solve,
            setup,
            assembly + direct_s,
            assembly + cg.solve,
            assembly + gpu.solve,
        );
    }
    println!(
        "seconds; iters: CG iterations to |r| <= {:.0e} |b| (max {}); s/iter: marginal; gpu set: first upload \
         (pattern, buffers, pipelines); newton: assembly + one solve",
        args.rel_tol, args.max_iter
    );
    Ok(())
}
