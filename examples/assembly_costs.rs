//! Diagnostic: where one Newton assembly's time goes, stencil set by
//! stencil set, with and without the per-stencil PSD projection.
//!
//! ```text
//! cargo run --release --no-default-features --example assembly_costs -- [NAME [N [STEPS [SEED]]]]
//! ```
//!
//! Relaxes the shipped pattern `NAME` resized to `N x N` stitches (default
//! `linen-stitch 40`) for `STEPS` relaxation steps (default 2, so that EIL
//! points exist), builds the next step's Newton problem and times each
//! stencil set's `accumulate` (gradient and Hessian, scattered into the
//! matrix) on [`knitsim::parallel::threads`] threads, the fastest of 5,
//! first plain, then projected. The difference of the two columns is what
//! the projection costs; docs/RELAX.md, "PSD projections", has the figures.
//! `KNITSIM_BENCH_BENDING=split` times the bending stencils with the
//! closed-form Hessian (`SimParams::bending_hessian`) instead.

#[path = "common/mod.rs"]
mod common;

use knitsim::solver::newton::Problem;
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(String::as_str).unwrap_or("linen-stitch");
    let n: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(40);
    let steps: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(2);
    let seed: u64 = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(0);
    let mut sim = common::relaxing(name, n, seed)?;
    for _ in 0..steps {
        sim.step(false, None, &mut |_, _| {})?;
    }
    // As in `bench_relax`: `KNITSIM_BENCH_BENDING=split` times the
    // closed-form bending Hessian (the steps before run the default).
    if let Ok(model) = std::env::var("KNITSIM_BENCH_BENDING") {
        sim.params_mut().bending_hessian = model.parse().map_err(anyhow::Error::msg)?;
    }
    let problem = sim.problem(Some((sim.schedule().h, sim.q())))?;
    let mut h = problem.hessian_pattern();
    let mut g = vec![0.0; sim.q().len()];
    println!(
        "{name} {n}x{n} after {steps} steps, {} unknowns, {} threads",
        sim.q().len(),
        knitsim::parallel::threads()
    );
    println!("| stencil set | stencils | plain ms | projected ms | projection ms |");
    println!("|---|---|---|---|---|");
    let (mut plain_sum, mut proj_sum) = (0.0, 0.0);
    for set in &problem.sets {
        let mut best = [f64::INFINITY; 2];
        for (k, project) in [false, true].into_iter().enumerate() {
            for _ in 0..5 {
                let t = Instant::now();
                set.accumulate(sim.q(), &problem.free, &mut g, &mut h, project)?;
                best[k] = best[k].min(t.elapsed().as_secs_f64());
            }
        }
        plain_sum += best[0];
        proj_sum += best[1];
        println!(
            "| {} | {} | {:.2} | {:.2} | {:.2} |",
            set.name(),
            set.len(),
            best[0] * 1e3,
            best[1] * 1e3,
            (best[1] - best[0]) * 1e3
        );
    }
    println!(
        "| all | | {:.2} | {:.2} | {:.2} |",
        plain_sum * 1e3,
        proj_sum * 1e3,
        (proj_sum - plain_sum) * 1e3
    );
    Ok(())
}
