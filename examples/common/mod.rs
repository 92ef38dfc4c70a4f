//! Helpers the relaxation examples share (`#[path]`-included, so it is not
//! an example target of its own): the shipped patterns resized to `n x n`
//! stitches, and seeded sub-nanometre jitter of a compiled fabric.

use knitsim::pattern::parse_str;
use knitsim::topology::{compile, CompileOptions};

pub use knitsim::topology::jitter::jitter;

/// Environment variable holding `CompileOptions::shape_gap` for
/// [`compiled`] (unset: the default, 0). `bench_relax --shape-gap` sets it
/// so its child processes compile the same way.
#[allow(dead_code)]
pub const SHAPE_GAP_VAR: &str = "KNITSIM_BENCH_SHAPE_GAP";

/// The shipped pattern `name` resized to `n x n` stitches, compiled (with
/// the shape gap of [`SHAPE_GAP_VAR`], if set).
pub fn compiled(name: &str, n: usize) -> anyhow::Result<knitsim::topology::Fabric> {
    let path = format!("{}/patterns/{name}.knit", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path)?;
    let text = knitsim::app::study::resize_text(&text, n);
    let parsed = parse_str(&text, &path)?;
    let shape_gap = match std::env::var(SHAPE_GAP_VAR) {
        Ok(g) => g.parse()?,
        Err(_) => 0.0,
    };
    let opts = CompileOptions {
        shape_gap,
        ..CompileOptions::default()
    };
    Ok(compile(&parsed.pattern, &opts)?)
}

/// A simulation of the shipped pattern `name` at `n x n` stitches, jittered
/// by `seed`, whose own schedule is the default relaxation schedule
/// (`sim::relax_schedule`): what the step-by-step diagnostics start from,
/// so that `Simulation::step` follows `sim::relax`'s path.
#[allow(dead_code)]
pub fn relaxing(name: &str, n: usize, seed: u64) -> anyhow::Result<knitsim::sim::Simulation> {
    use knitsim::sim::{relax_schedule, RelaxOptions, Simulation};
    let mut fabric = compiled(name, n)?;
    jitter(&mut fabric, seed);
    let opts = RelaxOptions::default();
    let params = knitsim::scene::params_for(&fabric, None)?;
    let mut sim = Simulation::new(
        fabric,
        params,
        knitsim::solver::linear::LinearSolver::direct(),
        opts.h_initial,
    );
    *sim.schedule_mut() = relax_schedule(&sim, &opts);
    Ok(sim)
}
