//! How far the soft EIL contact constraint lets contacts open at
//! equilibrium: relaxes a pattern and prints the EIL gaps (distance between
//! where the two yarns put a contact) against the yarn radius, for each
//! `kc_factor` given. Not a test.
//! `cargo run --release --example relax_gaps -- PATTERN [KC_FACTORS]`
//! (default factors `10,1000`).

use knitsim::app::load_fabric;
use knitsim::sim::{relax, RelaxOptions, Simulation};
use knitsim::solver::linear::LinearSolver;
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).map(String::as_str).unwrap_or("patterns/linen-stitch.knit");
    let factors: Vec<f64> = args
        .get(2)
        .map(String::as_str)
        .unwrap_or("10,1000")
        .split(',')
        .map(str::parse)
        .collect::<Result<_, _>>()?;
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
        let r = sim.params.rod.radius;
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
