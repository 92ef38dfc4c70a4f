//! Seconds per CG iteration: GPU (wgpu, f32) vs CPU (f64) block-Jacobi PCG.
//!
//! The systems mimic a knit Newton matrix: yarns are chains of nodes with 3
//! unknowns each; stretch couples consecutive nodes along the (helical)
//! tangent, bending couples nodes two apart, and every other node touches a
//! node of the neighbouring yarn (the off-band contact coupling). Each term
//! adds an SPD 3x3 block K as [K -K; -K K], plus a mass term on the
//! diagonal, so the matrix is SPD with 3x3 node blocks, like the real one.
//!
//! The per-iteration time is the marginal cost: `(t(2N) - t(N)) / N` for
//! solves capped at N and 2N iterations with a tolerance that never fires,
//! so uploads of b and x0, the final readback and the solver setup are
//! excluded (setup is reported separately).
//!
//! `cargo run --release --example bench_gpu_cg -- --sizes 5000,50000,500000`
//!
//! Built without the `gpu` feature it only says so (the system generator
//! still compiles, hence the dead-code allowance there).
#![cfg_attr(not(feature = "gpu"), allow(dead_code))]

use clap::Parser;
#[cfg(feature = "gpu")]
use knitsim::gpu::{GpuContext, GpuPcg, GpuPcgParams};
#[cfg(feature = "gpu")]
use knitsim::solver::linear::{pcg, BlockJacobi, CgParams};
use knitsim::sparse::CsrMatrix;
use std::time::Instant;

#[derive(Parser)]
struct Args {
    /// Approximate numbers of unknowns (rounded to whole nodes of 3).
    #[arg(long, value_delimiter = ',', default_values_t = [5_000, 50_000, 500_000])]
    sizes: Vec<usize>,
    /// N in the marginal timing (solves of N and 2N iterations).
    #[arg(long, default_value_t = 20)]
    iters: usize,
    /// Nodes per yarn.
    #[arg(long, default_value_t = 100)]
    yarn_nodes: usize,
}

/// Stiffness parameters of the synthetic rod/knit Hessian.
struct RodSystem {
    stretch: f64,
    bend: f64,
    contact: f64,
    mass: f64,
}

impl Default for RodSystem {
    fn default() -> Self {
        RodSystem {
            stretch: 100.0,
            bend: 1.0,
            contact: 10.0,
            mass: 0.01,
        }
    }
}

type Block = [[f64; 3]; 3];

fn outer(t: [f64; 3], scale: f64, shift: f64) -> Block {
    let norm = t.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut b = [[0.0; 3]; 3];
    for r in 0..3 {
        for c in 0..3 {
            b[r][c] = scale * t[r] * t[c] / (norm * norm) + if r == c { shift } else { 0.0 };
        }
    }
    b
}

impl RodSystem {
    fn couplings(&self, nodes: usize, yarn: usize) -> Vec<(usize, usize, Block)> {
        let mut out = Vec::new();
        for i in 0..nodes {
            let along = i % yarn;
            let angle = 0.3 * i as f64;
            if along + 1 < yarn && i + 1 < nodes {
                let tangent = [angle.cos(), angle.sin(), 0.3];
                out.push((i, i + 1, outer(tangent, self.stretch, 0.01 * self.stretch)));
            }
            if along + 2 < yarn && i + 2 < nodes {
                out.push((i, i + 2, outer([1.0, 0.0, 0.0], 0.0, self.bend)));
            }
            let partner = i + yarn + 1;
            if i % 2 == 0 && partner < nodes {
                let normal = [0.2 * angle.sin(), 0.2, 1.0];
                out.push((i, partner, outer(normal, self.contact, 0.0)));
            }
        }
        out
    }

    fn assemble(&self, nodes: usize, yarn: usize) -> CsrMatrix {
        let couplings = self.couplings(nodes, yarn);
        let mut entries = Vec::with_capacity(couplings.len() * 36 + nodes * 9);
        let mut push_block = |p: usize, q: usize| {
            for r in 0..3 {
                for c in 0..3 {
                    entries.push(((3 * p + r) as u32, (3 * q + c) as u32));
                }
            }
        };
        (0..nodes).for_each(|p| push_block(p, p));
        for &(p, q, _) in &couplings {
            push_block(p, q);
            push_block(q, p);
        }
        let mut a = CsrMatrix::from_pattern(3 * nodes, entries);
        let mut add_block = |p: usize, q: usize, b: &Block, sign: f64| {
            for (r, row) in b.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    if let Some(k) = a.find(3 * p + r, 3 * q + c) {
                        a.values[k] += sign * v;
                    }
                }
            }
        };
        for (p, q, b) in &couplings {
            add_block(*p, *p, b, 1.0);
            add_block(*q, *q, b, 1.0);
            add_block(*p, *q, b, -1.0);
            add_block(*q, *p, b, -1.0);
        }
        let mass = outer([1.0, 0.0, 0.0], 0.0, self.mass);
        (0..nodes).for_each(|p| add_block(p, p, &mass, 1.0));
        a
    }
}

fn seconds(f: impl FnOnce()) -> f64 {
    let start = Instant::now();
    f();
    start.elapsed().as_secs_f64()
}

struct Row {
    n: usize,
    nnz: usize,
    cpu_per_iter: f64,
    gpu_per_iter: f64,
    cpu_iters: usize,
    gpu_iters: usize,
    gpu_setup: f64,
}

#[cfg(feature = "gpu")]
fn bench(ctx: &GpuContext, a: &CsrMatrix, iters: usize) -> anyhow::Result<Row> {
    let starts: Vec<usize> = (0..=a.n).step_by(3).collect();
    let b: Vec<f64> = (0..a.n).map(|i| ((i * 7919) % 201) as f64 / 100.0 - 1.0).collect();
    let zeros = vec![0.0; a.n];
    let pre = BlockJacobi::new(a, &starts);

    let cpu_run = |max_iter, rel_tol| {
        let mut x = zeros.clone();
        pcg(a, &b, &mut x, &pre, CgParams { rel_tol, max_iter })
    };
    let cpu_time = |max_iter| {
        seconds(|| {
            cpu_run(max_iter, 0.0);
        })
    };
    let cpu_per_iter = (cpu_time(2 * iters) - cpu_time(iters)) / iters as f64;

    let mut gpu = None;
    let gpu_setup = seconds(|| gpu = Some(GpuPcg::new(ctx, a, &starts)));
    let gpu = gpu.expect("set above")?;
    let gpu_params = |max_iter, rel_tol| GpuPcgParams {
        rel_tol,
        max_iter,
        ..Default::default()
    };
    // Warm-up: first submissions pay for pipeline and memory setup.
    gpu.solve(&b, &zeros, &gpu_params(8, 0.0))?;
    let gpu_time = |max_iter| -> anyhow::Result<f64> {
        let start = Instant::now();
        gpu.solve(&b, &zeros, &gpu_params(max_iter, 0.0))?;
        Ok(start.elapsed().as_secs_f64())
    };
    let gpu_per_iter = (gpu_time(2 * iters)? - gpu_time(iters)?) / iters as f64;

    let tol = 1e-5;
    let cpu_iters = cpu_run(5000, tol).iterations;
    let gpu_iters = gpu.solve(&b, &zeros, &gpu_params(5000, tol))?.1.iterations;
    Ok(Row {
        n: a.n,
        nnz: a.nnz(),
        cpu_per_iter,
        gpu_per_iter,
        cpu_iters,
        gpu_iters,
        gpu_setup,
    })
}

#[cfg(not(feature = "gpu"))]
fn main() {
    eprintln!("bench_gpu_cg needs the `gpu` feature");
}

#[cfg(feature = "gpu")]
fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let ctx = GpuContext::new()?;
    println!("adapter: {}", ctx.adapter);
    println!(
        "{:>9} {:>10} {:>13} {:>13} {:>8} {:>10} {:>10} {:>11}",
        "unknowns", "nnz", "cpu s/iter", "gpu s/iter", "cpu/gpu", "cpu iters", "gpu iters", "gpu setup s"
    );
    for &size in &args.sizes {
        let a = RodSystem::default().assemble(size.div_ceil(3), args.yarn_nodes);
        let row = bench(&ctx, &a, args.iters)?;
        println!(
            "{:>9} {:>10} {:>13.3e} {:>13.3e} {:>8.2} {:>10} {:>10} {:>11.3}",
            row.n,
            row.nnz,
            row.cpu_per_iter,
            row.gpu_per_iter,
            row.cpu_per_iter / row.gpu_per_iter,
            row.cpu_iters,
            row.gpu_iters,
            row.gpu_setup
        );
    }
    println!("iters: iterations to |r| <= 1e-5 |b| (max 5000); s/iter: marginal, excludes setup and transfers");
    Ok(())
}
