//! Prints every Newton iteration of the first dynamic steps of a drape
//! (a small swatch by default): energy, largest force against the step's
//! tolerance, decrement, step length, damping. For finding out why a
//! step needs many iterations or retries.
//!
//! `cargo run --release --example drape_diagnose -- [PATTERN] [SIZE] [STEPS]`
//!
//! Switches (environment variables, set to anything): `DIAG_NO_CONTACT`,
//! `DIAG_SPLIT` (split bending Hessian), `DIAG_NO_FRICTION`,
//! `DIAG_NO_WRAP`, `DIAG_NO_SHEAR`, `DIAG_NO_PARALLEL`, `DIAG_NO_GRAVITY`,
//! `DIAG_NO_EIL`, `DIAG_KEEP_EIL`, `DIAG_PROJECTED` (projected Hessian throughout); `DIAG_TOL=x` sets `dynamics.newton_tol`
//! and `DIAG_ITS=n` `dynamics.newton_max_iterations`. docs/MODEL.md,
//! "Dynamics", quotes what they showed.

use knitsim::app::drape::scene::with_default_scene;
use knitsim::sim::dynamics::{dynamic_params, schedule};
use knitsim::sim::{relax, RelaxOptions, Simulation};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::{compile, CompileOptions};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).cloned().unwrap_or("patterns/linen-stitch.knit".into());
    let size: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(6);
    let steps: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(5);
    let text = std::fs::read_to_string(&path).expect("pattern");
    let text = knitsim::app::study::resize_text(&text, size);
    let parsed = knitsim::pattern::parse_str(&text, &path).expect("parses");
    let f = compile(&parsed.pattern, &CompileOptions::default()).expect("compiles");
    let p = knitsim::scene::params_for(&f, None).expect("params");
    let mut sim = Simulation::new(f, p.clone(), LinearSolver::direct(), 1e-3);
    let t = std::time::Instant::now();
    let r = relax(&mut sim, RelaxOptions::default(), None, &mut |_, _| {}, &mut |_, _| {}).expect("relax");
    eprintln!("relaxed: {} steps in {:.1} s", r.steps, t.elapsed().as_secs_f64());
    let relaxed = sim.snapshot();
    let mut p = dynamic_params(with_default_scene(p, &relaxed));
    // Switches for finding the term that slows Newton down.
    let on = |k: &str| std::env::var_os(k).is_some();
    if on("DIAG_NO_CONTACT") {
        p.contact = None;
    }
    if on("DIAG_SPLIT") {
        p.bending_hessian = knitsim::rod::bending::BendingHessian::Split;
    }
    for (k, t) in [
        ("DIAG_NO_FRICTION", &mut p.terms.friction),
        ("DIAG_NO_WRAP", &mut p.terms.wrapping),
        ("DIAG_NO_SHEAR", &mut p.terms.shear),
        ("DIAG_NO_PARALLEL", &mut p.terms.parallel),
        ("DIAG_NO_GRAVITY", &mut p.terms.gravity),
    ] {
        if on(k) {
            *t = false;
        }
    }
    if let Some(t) = std::env::var("DIAG_TOL").ok().and_then(|v| v.parse().ok()) {
        p.dynamics.newton_tol = t;
    }
    if let Some(t) = std::env::var("DIAG_ITS").ok().and_then(|v| v.parse().ok()) {
        p.dynamics.newton_max_iterations = t;
    }
    if on("DIAG_NO_EIL") {
        p.assign.enable_eil = false;
    }
    let mut sim = Simulation::new(relaxed, p.clone(), LinearSolver::direct(), p.dynamics.dt);
    let mut s = schedule(&sim, &p.dynamics);
    s.keep_eil = std::env::var_os("DIAG_KEEP_EIL").is_some();
    s.newton.exact_hessian = std::env::var_os("DIAG_PROJECTED").is_none();
    eprintln!("force tolerance {:.3e} N", s.newton.max_force_tol);
    for k in 0..steps {
        let t = std::time::Instant::now();
        let rep = sim
            .step_with(&mut s, true, None, &mut |it, eil| {
                eprintln!(
                    "  it {:>2}: E {:.9e} max force {:.3e} decrement {:.2e} step {:.2e} damping {:.1e} {:?} eil {eil}",
                    it.iteration, it.energy, it.max_force, it.decrement, it.step, it.damping, it.direction
                )
            })
            .expect("step");
        eprintln!(
            "step {k}: h {:.2e}, {} Newton, {} retries, converged {}, {:.2} s",
            rep.h,
            rep.newton_iterations,
            rep.retries,
            rep.converged,
            t.elapsed().as_secs_f64()
        );
    }
}
