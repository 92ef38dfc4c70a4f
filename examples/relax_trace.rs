//! Diagnostic: relaxes a pattern and prints every Newton iteration (damping,
//! direction, line-search trials) and, per step, which energy term carries
//! the largest free force, and how many unknowns Newton held at a bound.
//! `cargo run --release --example relax_trace -- PATTERN [steps]`; the
//! environment variable `STOP` sets `assign.stop_fraction` (docs/RELAX.md,
//! "Slide stops").

use knitsim::app::load_fabric;
use knitsim::sim::Simulation;
use knitsim::solver::linear::LinearSolver;
use knitsim::solver::newton::Problem;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).map(String::as_str).unwrap_or("patterns/stockinette.knit");
    let steps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let loaded = load_fabric(std::path::Path::new(path), &Default::default())?;
    let mut params = knitsim::scene::params_for(&loaded.fabric, None)?;
    params.assign.stop_fraction = std::env::var("STOP").ok().and_then(|s| s.parse().ok()).unwrap_or(0.0);
    let mut sim = Simulation::new(
        loaded.fabric,
        params,
        LinearSolver::direct(),
        std::env::var("H").ok().and_then(|s| s.parse().ok()).unwrap_or(1.0),
    );
    sim.newton.max_iterations = 20;
    sim.h_max = std::env::var("HMAX").ok().and_then(|s| s.parse().ok()).unwrap_or(sim.h);
    sim.newton.rel_residual_tol = std::env::var("RTOL").ok().and_then(|s| s.parse().ok()).unwrap_or(1e-8);
    println!("dofs {}", sim.q.len());
    if std::env::var("FD").is_ok() {
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
            let mut g = vec![0.0; sim.q.len()];
            let mut h = p.hessian_pattern();
            s.accumulate(&sim.q, &p.free, &mut g, &mut h, false)?;
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
        if std::env::var("FD").is_ok() {
            fd_check(&sim)?;
        }
    }
    Ok(())
}

/// Global finite-difference check of the assembled gradient and Hessian, per term.
#[allow(dead_code)]
pub fn fd_check(sim: &Simulation) -> anyhow::Result<()> {
    use knitsim::solver::assembly::AnyStencilSet;
    let p = sim.problem(Some((sim.h, &sim.q.clone())))?;
    let n = sim.q.len();
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
        let (_, g0, hd) = eval(&sim.q);
        for eps in [1e-2, 1e-3] {
            let qp: Vec<f64> = sim.q.iter().zip(&d).map(|(a, b)| a + eps * b).collect();
            let qm: Vec<f64> = sim.q.iter().zip(&d).map(|(a, b)| a - eps * b).collect();
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
