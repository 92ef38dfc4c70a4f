#[path = "common/mod.rs"]
mod common;
use knitsim::solver::assembly::assemble;
use knitsim::solver::linear::direct::{DirectParams, DirectSolver};
use knitsim::solver::newton::Problem;
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let mut sim = common::relaxing("linen-stitch", 40, 0)?;
    for _ in 0..2 {
        sim.step(false, None, &mut |_, _| {})?;
    }
    let problem = sim.problem(Some((sim.h, &sim.q.clone())))?;
    let mut h = problem.hessian_pattern();
    let mut g = vec![0.0; sim.q.len()];
    assemble(&problem.sets, &sim.q, &problem.free, &mut g, &mut h, true)?;
    let mut solver = DirectSolver::new(DirectParams::default());
    solver.set_ordering_groups(&problem.ordering_groups);
    let mut x = vec![0.0; g.len()];
    solver.solve(&h, &g, &mut x)?;
    let reps: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(40);
    for _ in 0..3 {
        let t = Instant::now();
        for _ in 0..reps {
            solver.solve(&h, &g, &mut x)?;
        }
        let hash = x.iter().fold(0u64, |a, v| a.rotate_left(5) ^ v.to_bits());
        println!(
            "{:.2} ms per factorize+solve, hash {hash:x}",
            t.elapsed().as_secs_f64() / reps as f64 * 1e3
        );
    }
    Ok(())
}
