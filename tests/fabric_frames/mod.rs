//! Frame-to-frame pass-through check of a simulated fabric, for the tight
//! pattern tests: every accepted quasi-static step is a frame, and between
//! two frames the independent checker of `contact_support` looks for any
//! two yarn segments passing through each other.
//!
//! **What a frame is.** The geometry the barrier protects during one step
//! is the simulator's: per yarn, the segments between consecutive non-EIL
//! points of that step's assignment (docs/CONTACT.md, "How a solve uses
//! it"). EIL points lie on those segments by construction, so they add no
//! geometry. The endpoints are nodes, and nodes are the vertex ids: the two
//! yarns of an EoL contact share its node, so their segments there are
//! adjacent (skipped), not crossing. A step first re-assigns EIL points and
//! moves the affected contacts (`sim::discretization::transfer`), then solves; the check
//! covers the solve, from that start to the accepted state.
//!
//! **Skipped pairs**, besides those sharing a node:
//! - exactly the pairs the simulator gives no barrier: one segment within
//!   `eol_exclusion h` (rest arc length `u`, at the step's start) of one
//!   side of a persistent contact and the other within that distance of its
//!   other side (docs/CONTACT.md, point 2). There the two centrelines meet
//!   at the contact node even when it is EIL on one yarn. The rule is
//!   written out again here rather than taken from
//!   `knitsim::contact::exclusion`, so the check stays independent;
//! - two segments of one yarn joined by less than the touch tolerance of
//!   yarn (a sliding contact point that has reached the next point; the
//!   next re-assignment makes it EIL). They meet at that joint like two
//!   segments sharing a node, and a sign change of their triple product
//!   there is bending, not a crossing.
#![allow(dead_code)]

use crate::contact_support::{crossing_pairs, min_separation_where};
use knitsim::sim::discretization::assignment::Assignment;
use knitsim::sim::discretization::transfer::transfer;
use knitsim::sim::{SimParams, Simulation};
use knitsim::solver::linear::LinearSolver;
use knitsim::solver::newton::Problem;
use knitsim::topology::{Fabric, PointRef, Vec3};

/// The segments of one step as node pairs, with what the skip rules need.
pub struct Segments {
    pub segs: Vec<[usize; 2]>,
    /// Yarn of each segment; a yarn's segments are consecutive, in order.
    pub yarn: Vec<usize>,
    /// Per segment, the contact sides (`2 contact + side`) within the
    /// exclusion radius, sorted.
    near: Vec<Vec<usize>>,
}

impl Segments {
    /// The segments of assignment `a`, with the exclusion `radius` measured
    /// at the `u` of `q` (the state the step's solve started from).
    pub fn new(sim: &Simulation, a: &Assignment, q: &[f64], radius: f64) -> Self {
        let (f, l) = (sim.fabric(), sim.layout());
        let u = |yarn: usize, point: usize| q[l.u(PointRef { yarn, point })];
        let sides: Vec<(usize, f64, usize)> = f
            .contacts
            .iter()
            .enumerate()
            .flat_map(|(c, k)| {
                [(k.front, 2 * c), (k.back, 2 * c + 1)].map(|(p, code)| (p.yarn, u(p.yarn, p.point), code))
            })
            .collect();
        let mut out = Segments {
            segs: Vec::new(),
            yarn: Vec::new(),
            near: Vec::new(),
        };
        for (y, yarn) in f.yarns.iter().enumerate() {
            let real: Vec<usize> = a.real_points(l, y).collect();
            for w in real.windows(2) {
                let (ua, ub) = (u(y, w[0]), u(y, w[1]));
                let (lo, hi) = (ua.min(ub) - radius, ua.max(ub) + radius);
                let mut near: Vec<usize> = sides
                    .iter()
                    .filter(|s| s.0 == y && s.1 >= lo && s.1 <= hi)
                    .map(|s| s.2)
                    .collect();
                near.sort_unstable();
                out.near.push(near);
                out.segs.push([yarn.points[w[0]].node, yarn.points[w[1]].node]);
                out.yarn.push(y);
            }
        }
        out
    }

    /// Near opposite sides of one contact: no barrier in the simulator.
    pub fn joined(&self, i: usize, j: usize) -> bool {
        self.near[i]
            .iter()
            .any(|s| self.near[j].binary_search(&(s ^ 1)).is_ok())
    }

    /// Length of the yarn strictly between segments `i < j` of one yarn,
    /// with nodes at `x`; infinite for segments of different yarns.
    pub fn link(&self, i: usize, j: usize, x: impl Fn(usize) -> Vec3) -> f64 {
        if self.yarn[i] != self.yarn[j] {
            return f64::INFINITY;
        }
        self.segs[i + 1..j].iter().map(|s| (x(s[1]) - x(s[0])).norm()).sum()
    }
}

pub fn node_positions(sim: &Simulation, q: &[f64]) -> Vec<Vec3> {
    (0..sim.layout().n_nodes).map(|i| sim.layout().node_x(q, i)).collect()
}

pub fn potential(sim: &Simulation) -> f64 {
    sim.problem(None).expect("problem").energy(sim.q())
}

/// What a run measured.
pub struct Run {
    pub steps: usize,
    pub crossings: usize,
    /// The first few crossings: step and the two segments' nodes.
    pub examples: Vec<String>,
    /// Smallest distance over every checked pair and every frame.
    pub min_separation: f64,
    pub thickness: f64,
    pub energy: (f64, f64),
    pub residual: (f64, f64),
    pub finite: bool,
    /// Why the run stopped early, if it did.
    pub error: Option<String>,
    /// The final state, for scene-specific checks.
    pub sim: Simulation,
}

fn trace() -> bool {
    std::env::var_os("TIGHT_TRACE").is_some()
}

/// `steps` quasi-static steps with the settings of `RelaxOptions::default()`
/// (pseudo time step from 1 ms up to 100 s, 20 Newton iterations a step,
/// relative tolerance 1e-6), checking every accepted step. `before(sim, k)`
/// runs before step `k` (a press moves its plate there). Set `TIGHT_TRACE`
/// for a line per step.
pub fn run(fabric: Fabric, p: SimParams, steps: usize, before: &mut dyn FnMut(&mut Simulation, usize)) -> Run {
    let cp = p.contact.clone().expect("contact settings");
    let thickness = cp.thickness_for(p.rod.radius);
    let exclusion = cp.eol_exclusion * thickness;
    let mut sim = Simulation::new(fabric, p, LinearSolver::direct(), 1e-3);
    let schedule = sim.schedule_mut();
    schedule.newton.max_iterations = 20;
    schedule.newton.rel_residual_tol = 1e-6;
    schedule.h_min = 1e-7;
    schedule.h_max = 1e2;
    let energy0 = potential(&sim);
    let residual0 = sim.static_residual().expect("residual");
    let mut out = Run {
        steps: 0,
        crossings: 0,
        examples: Vec::new(),
        min_separation: f64::INFINITY,
        thickness,
        energy: (energy0, energy0),
        residual: (residual0, residual0),
        finite: true,
        error: None,
        sim,
    };
    let sim = &mut out.sim;
    // A root of the triple product counts only where the segments touch:
    // the knot test's tolerance, a thousandth of the yarn radius.
    let touch = 1e-3 * 0.5 * thickness;
    for k in 0..steps {
        before(sim, k);
        let (q0, a0) = (sim.q().to_vec(), sim.assignment().clone());
        if let Err(e) = sim.step(false, None, &mut |_, _| {}) {
            // `step` re-assigned and transferred before it failed, so
            // `sim` holds the start it could not solve from.
            let mut why = format!("step {} failed: {e}", k + 1);
            why += &touching_at_start(sim, exclusion, touch);
            out.error = Some(why);
            break;
        }
        out.steps += 1;
        if !sim.q().iter().all(|v| v.is_finite()) {
            out.finite = false;
            break;
        }
        let a1 = sim.assignment();
        let mut start = q0;
        transfer(sim.fabric(), sim.layout(), &a0, a1, &mut start);
        let segs = Segments::new(sim, a1, &start, exclusion);
        let x0 = node_positions(sim, &start);
        let x1 = node_positions(sim, sim.q());
        let found: Vec<(usize, usize, f64)> = crossing_pairs(&x0, &x1, &segs.segs, touch, |i, j| segs.joined(i, j))
            .into_iter()
            .filter(|&(i, j, t)| segs.link(i, j, |n| x0[n] + (x1[n] - x0[n]) * t) >= touch)
            .collect();
        for &(i, j, t) in found.iter().take(5 - out.examples.len().min(5)) {
            out.examples.push(format!(
                "step {}: segments {:?} (yarn {}) and {:?} (yarn {}) at t = {t:.3}",
                k + 1,
                segs.segs[i],
                segs.yarn[i],
                segs.segs[j],
                segs.yarn[j]
            ));
        }
        let sep = min_separation_where(&x1, &segs.segs, |i, j| {
            segs.joined(i, j) || segs.link(i, j, |n| x1[n]) < touch
        });
        if trace() {
            eprintln!(
                "  step {}: {} segments, {} EIL, crossings {}, min separation {:.3} h",
                k + 1,
                segs.segs.len(),
                a1.eil_count(),
                found.len(),
                sep / thickness
            );
        }
        out.crossings += found.len();
        out.min_separation = out.min_separation.min(sep);
    }
    out.energy.1 = potential(&out.sim);
    out.residual.1 = out.sim.static_residual().unwrap_or(f64::NAN);
    out.finite &= out.energy.1.is_finite() && out.residual.1.is_finite();
    out
}

/// Pairs the simulator keeps a barrier for that touch in its current state
/// (an infinite barrier): what a step that cannot start ran into.
fn touching_at_start(sim: &Simulation, exclusion: f64, touch: f64) -> String {
    let segs = Segments::new(sim, sim.assignment(), sim.q(), exclusion);
    let x = node_positions(sim, sim.q());
    let mut out = String::new();
    for (i, a) in segs.segs.iter().enumerate() {
        for (j, b) in segs.segs.iter().enumerate().skip(i + 1) {
            if a.iter().any(|n| b.contains(n)) || segs.joined(i, j) {
                continue;
            }
            let d = crate::contact_support::segment_distance(&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]);
            if d < touch {
                out += &format!(
                    "\n  at its start segments {a:?} and {b:?} of yarn {} are {d:.1e} m apart, \
                     {:.1e} m of yarn between them",
                    segs.yarn[i],
                    segs.link(i, j, |n| x[n])
                );
            }
        }
    }
    out
}

pub fn report(name: &str, r: &Run, seconds: f64) {
    eprintln!(
        "{name}: {} steps, crossings {}, min separation {:.3e} m ({:.3} h), energy {:.4e} -> {:.4e} J, \
         residual {:.2e} -> {:.2e}, {seconds:.1} s",
        r.steps,
        r.crossings,
        r.min_separation,
        r.min_separation / r.thickness,
        r.energy.0,
        r.energy.1,
        r.residual.0,
        r.residual.1,
    );
    if let Some(e) = &r.error {
        eprintln!("  {e}");
    }
    for e in &r.examples {
        eprintln!("  crossing, {e}");
    }
}
