//! Implicit dynamics: a fabric moving under gravity, pins, prescribed
//! motions, obstacles with friction and damping, step by step until it
//! comes to rest or its duration is over (docs/MODEL.md, "Dynamics").
//!
//! Every step is a backward Euler step of [`Simulation::step_with`]: one
//! Newton solve of the incremental potential with the EoL mass matrix,
//! solved to a force tolerance ([`schedule`]); a step whose solve fails is
//! retried at half the time step, and converged steps double it back up
//! to `dynamics.max_dt`. Before each step the pinned nodes of a motion are
//! put where the motion has them at the end of the step (a retried step
//! keeps those targets). After each step the caller sees a [`StepRow`]
//! (time, kinetic and potential energy, Newton iterations, the stopping
//! quantity) and the simulation, to write frames.
//!
//! The run stops when the largest speed of a node has stayed below
//! `dynamics.rest_speed` for `dynamics.rest_time` of simulated time (at
//! rest), at `dynamics.duration`, or when cancelled.

pub mod pins;

use super::dynamics_settings::DynamicsParams;
use super::schedule::Schedule;
use super::{SimError, SimParams, Simulation};
use crate::rod::mass::segment_mass;
use crate::sim::discretization::{gather, Discretization};
use crate::sim::terms::rod_segments::segment_dofs;
use crate::solver::assembly::timing::TermTimes;
use crate::topology::Fabric;
use serde::Serialize;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// One accepted time step.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct StepRow {
    pub step: usize,
    /// Simulated time at the step's end (s).
    pub time: f64,
    /// The step's length (s).
    pub h: f64,
    /// `1/2 v^T M v` with the EoL segment masses (J).
    pub kinetic: f64,
    /// Every potential term, gravity included (J).
    pub potential: f64,
    pub newton_iterations: usize,
    /// Attempts at a smaller step before this one converged.
    pub retries: usize,
    /// The stopping quantity: the largest node speed (m/s).
    pub max_speed: f64,
    /// Wall time since the run started (s).
    pub wall_s: f64,
    /// Whether Newton met its tolerance (false only for a cancelled step).
    pub converged: bool,
}

/// How a dynamic run ended.
#[derive(Clone, Debug, Serialize)]
pub struct DynamicsReport {
    pub steps: usize,
    pub newton_iterations: usize,
    /// Simulated time reached (s).
    pub time: f64,
    /// The rest test passed.
    pub at_rest: bool,
    pub cancelled: bool,
    /// Newton's force tolerance of every step (N).
    pub newton_force_tol: f64,
    pub max_eil: usize,
    /// Seconds per stencil set (the active terms) and in the linear solver.
    pub term_seconds: TermTimes,
}

/// `params` for a dynamic run: gravity on with `dynamics.gravity` (off if
/// that is zero).
pub fn dynamic_params(mut params: SimParams) -> SimParams {
    let g = params.dynamics.gravity;
    params.terms.gravity = g.iter().any(|v| *v != 0.0);
    params.rod.gravity = nalgebra::Vector3::from(g);
    params
}

/// Pins every node of `sets` in `fabric` (their coordinates are then not
/// unknowns).
pub fn pin_nodes(fabric: &mut Fabric, sets: &[Vec<usize>]) {
    for &n in sets.iter().flatten() {
        fabric.nodes[n].pinned = true;
    }
}

/// Newton's force tolerance (N): `newton_tol` times the weight of the
/// mean rest segment (with `|g| = 9.81` when gravity is off).
pub fn newton_force_tol(sim: &Simulation) -> f64 {
    let p = sim.params();
    let seg = sim.rest().rest_seg.iter().sum::<f64>() / sim.rest().rest_seg.len().max(1) as f64;
    let g = nalgebra::Vector3::from(p.dynamics.gravity).norm();
    let g = if g > 0.0 { g } else { 9.81 };
    p.dynamics.newton_tol * p.rod.rho * seg * g
}

/// The schedule of a dynamic run: `dt` growing to `max_dt`, Newton with
/// the exact Hessian (projected fallback) to [`newton_force_tol`] within
/// `newton_max_iterations`.
pub fn schedule(sim: &Simulation, d: &DynamicsParams) -> Schedule {
    let mut s = Schedule {
        newton: sim.schedule().newton,
        ..Schedule::new(d.dt)
    };
    s.h_max = d.max_dt.unwrap_or(d.dt).max(d.dt);
    s.newton.max_iterations = d.newton_max_iterations;
    // The exact Hessian, as in relaxation: with the projected one the
    // steps of a falling swatch collapsed to microseconds (docs/MODEL.md,
    // "Dynamics").
    s.newton.exact_hessian = true;
    s.newton.max_force_tol = newton_force_tol(sim);
    s.stick = !d.sliding;
    s
}

/// Kinetic energy `1/2 v^T M v` over the segments between real points (J).
pub fn kinetic_energy(sim: &Simulation) -> f64 {
    let st = sim.state();
    let disc = Discretization::new(&st.fabric, &st.layout, &st.assignment);
    let rho = sim.params().rod.rho;
    let mut e = 0.0;
    for (y, real) in disc.real.iter().enumerate() {
        for d in segment_dofs(&disc, y, real) {
            let v = gather(&st.v, &d);
            e += 0.5 * v.dot(&(segment_mass(rho, &gather(&st.q, &d)) * v));
        }
    }
    e
}

/// The largest speed of a node (m/s).
pub fn max_speed(sim: &Simulation) -> f64 {
    let st = sim.state();
    (0..st.fabric.nodes.len())
        .map(|n| {
            let i = st.layout.x(n);
            (st.v[i].powi(2) + st.v[i + 1].powi(2) + st.v[i + 2].powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

/// The centre of mass of the real segments (m), with the segment masses
/// `rho du`.
pub fn centre_of_mass(sim: &Simulation) -> [f64; 3] {
    let st = sim.state();
    let disc = Discretization::new(&st.fabric, &st.layout, &st.assignment);
    let (mut m, mut c) = (0.0, [0.0; 3]);
    for (y, real) in disc.real.iter().enumerate() {
        for d in segment_dofs(&disc, y, real) {
            let q = gather(&st.q, &d);
            let du = q[7] - q[3];
            m += du;
            for k in 0..3 {
                c[k] += du * 0.5 * (q[k] + q[4 + k]);
            }
        }
    }
    c.map(|v| v / m)
}

/// Runs `sim` under its `dynamics` settings with the pin sets `pin_sets`
/// (already pinned in its fabric, see [`pin_nodes`]). `on_step` sees every
/// accepted step; returning `false` stops the run.
pub fn run_dynamics(
    sim: &mut Simulation,
    pin_sets: &[Vec<usize>],
    cancel: Option<&AtomicBool>,
    on_step: &mut dyn FnMut(&Simulation, &StepRow) -> bool,
) -> Result<DynamicsReport, SimError> {
    let d = sim.params().dynamics.clone();
    let mut schedule = schedule(sim, &d);
    let start = Instant::now();
    let t0 = sim.time();
    let starts: Vec<Vec<[f64; 3]>> = pin_sets
        .iter()
        .map(|set| {
            set.iter()
                .map(|&n| {
                    let i = sim.layout().x(n);
                    [sim.q()[i], sim.q()[i + 1], sim.q()[i + 2]]
                })
                .collect()
        })
        .collect();
    let mut rep = DynamicsReport {
        steps: 0,
        newton_iterations: 0,
        time: 0.0,
        at_rest: false,
        cancelled: false,
        newton_force_tol: schedule.newton.max_force_tol,
        max_eil: 0,
        term_seconds: TermTimes::default(),
    };
    let mut rest_since: Option<f64> = None;
    while sim.time() - t0 < d.duration * (1.0 - 1e-12) {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            rep.cancelled = true;
            break;
        }
        // Never step past the duration.
        let left = t0 + d.duration - sim.time();
        if schedule.h > left {
            schedule.h = left.max(schedule.h_min);
        }
        move_pins(sim, &d, pin_sets, &starts, sim.time() - t0 + schedule.h);
        let s = sim.step_with(&mut schedule, true, cancel, &mut |_, _| {})?;
        rep.steps += 1;
        rep.newton_iterations += s.newton_iterations;
        rep.max_eil = rep.max_eil.max(s.eil_count);
        rep.term_seconds.merge(&s.times);
        rep.time = sim.time() - t0;
        let row = StepRow {
            step: rep.steps,
            time: rep.time,
            h: s.h,
            kinetic: kinetic_energy(sim),
            potential: sim.potential_energy()?,
            newton_iterations: s.newton_iterations,
            retries: s.retries,
            max_speed: max_speed(sim),
            wall_s: start.elapsed().as_secs_f64(),
            converged: s.converged,
        };
        if !s.converged {
            rep.cancelled = true;
        }
        let go_on = on_step(sim, &row);
        if row.max_speed < d.rest_speed && d.rest_time > 0.0 {
            let since = *rest_since.get_or_insert(rep.time - s.h);
            if rep.time - since >= d.rest_time {
                rep.at_rest = true;
            }
        } else {
            rest_since = None;
        }
        if rep.at_rest || rep.cancelled || !go_on {
            break;
        }
    }
    Ok(rep)
}

/// Puts the nodes of every moving pin set where their motions have them
/// at run time `t`: the start position plus the sum of the motions'
/// displacements.
fn move_pins(sim: &mut Simulation, d: &DynamicsParams, pin_sets: &[Vec<usize>], starts: &[Vec<[f64; 3]>], t: f64) {
    if d.motions.is_empty() {
        return;
    }
    let targets: Vec<(usize, [f64; 3])> = pin_sets
        .iter()
        .enumerate()
        .flat_map(|(k, set)| {
            set.iter().zip(&starts[k]).map(move |(&n, &x0)| {
                let mut x = x0;
                for m in d.motions.iter().filter(|m| m.pins == k) {
                    let to = m.position(x0, t);
                    for i in 0..3 {
                        x[i] += to[i] - x0[i];
                    }
                }
                (n, x)
            })
        })
        .collect();
    for (n, x) in targets {
        let i = sim.layout().x(n);
        sim.q_mut()[i..i + 3].copy_from_slice(&x);
    }
}
