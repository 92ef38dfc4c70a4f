//! *Robust Eulerian-on-Lagrangian Rods*, Fig. 2-c/d: two yarns slide along a third until their contacts
//! cross. With EIL nodes the run completes with finite energy and a bounded
//! number of Newton iterations per step; with EIL disabled the segment
//! between the two contacts degenerates (`du -> 0`, stiffness `ks/du -> inf`)
//! and the same scene fails or needs ever smaller steps.

mod common;

use knitsim::sim::{SimParams, Simulation, Terms};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::{Contact, ContactKind, Fabric, PointRef, Vec3};

/// Rail yarn C along x; yarns A and B along y cross it at x = -d and +d.
fn scene() -> (Fabric, [usize; 2], [usize; 2]) {
    let mut f = common::empty_fabric(5e-4);
    let (half, d, arm) = (0.02, 0.004, 0.01);
    // Contact nodes first, so both yarns can reference them.
    f.nodes.push(knitsim::topology::Node {
        x: Vec3::new(-d, 0.0, 0.0),
        pinned: false,
    });
    f.nodes.push(knitsim::topology::Node {
        x: Vec3::new(d, 0.0, 0.0),
        pinned: false,
    });
    let c = common::add_yarn(
        &mut f,
        &[
            Vec3::new(-half, 0.0, 0.0),
            Vec3::new(-d, 0.0, 0.0),
            Vec3::new(d, 0.0, 0.0),
            Vec3::new(half, 0.0, 0.0),
        ],
        &[None, Some(0), Some(1), None],
    );
    let mut ends_a = [0; 2];
    let mut ends_b = [0; 2];
    for (k, (x, ends)) in [(-d, &mut ends_a), (d, &mut ends_b)].into_iter().enumerate() {
        let y = common::add_yarn(
            &mut f,
            &[
                Vec3::new(x, -arm, 0.001),
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x, arm, 0.001),
            ],
            &[None, Some(k), None],
        );
        let pts = &f.yarns[y].points;
        *ends = [pts[0].node, pts[2].node];
        f.contacts.push(Contact {
            node: k,
            front: PointRef { yarn: y, point: 1 },
            back: PointRef { yarn: c, point: 1 + k },
            kind: ContactKind::Float,
            partner: None,
        });
    }
    for n in [f.yarns[c].points[0].node, f.yarns[c].points[3].node]
        .into_iter()
        .chain(ends_a)
        .chain(ends_b)
    {
        f.nodes[n].pinned = true;
    }
    (f, ends_a, ends_b)
}

struct Outcome {
    completed: bool,
    max_iters_per_step: usize,
    min_h: f64,
    crossed: bool,
    max_eil: usize,
}

fn run(enable_eil: bool) -> Outcome {
    let (f, ends_a, ends_b) = scene();
    let mut p = SimParams::default();
    p.assign.enable_eil = enable_eil;
    p.terms = Terms {
        friction: false,
        shear: false,
        wrapping: false,
        parallel: false,
        ..Terms::default()
    };
    let h = 1e-3;
    let mut sim = Simulation::new(f, p, LinearSolver::direct(), h);
    sim.schedule_mut().h_min = h / 64.0;
    let (steps, travel) = (80, 0.012);
    let mut out = Outcome {
        completed: true,
        max_iters_per_step: 0,
        min_h: h,
        crossed: false,
        max_eil: 0,
    };
    for _ in 0..steps {
        // Prescribed motion: A's ends move +x, B's ends -x.
        for (ends, sign) in [(ends_a, 1.0), (ends_b, -1.0)] {
            for n in ends {
                sim.q_mut()[3 * n] += sign * travel / steps as f64;
            }
        }
        match sim.step(true, None, &mut |_, _| {}) {
            Ok(r) => {
                out.max_iters_per_step = out.max_iters_per_step.max(r.newton_iterations);
                out.min_h = out.min_h.min(r.h);
                out.max_eil = out.max_eil.max(r.eil_count);
                assert!(sim.q().iter().all(|v| v.is_finite()));
            }
            Err(_) => {
                out.completed = false;
                break;
            }
        }
    }
    let e = sim
        .problem(None)
        .unwrap()
        .breakdown(sim.q())
        .iter()
        .map(|(_, e)| e)
        .sum::<f64>();
    let l = sim.layout();
    let (u1, u2) = (
        sim.q()[l.u(PointRef { yarn: 0, point: 1 })],
        sim.q()[l.u(PointRef { yarn: 0, point: 2 })],
    );
    out.crossed = u1 > u2;
    if out.completed {
        assert!(e.is_finite(), "energy {e}");
    }
    out
}

#[test]
fn eil_lets_sliding_contacts_cross_and_plain_eol_does_not() {
    let with = run(true);
    assert!(with.completed, "EIL run failed");
    assert!(with.crossed, "contacts should have crossed on the rail");
    assert!(with.max_eil >= 1, "an EIL node must have been used");
    assert!(
        with.max_iters_per_step <= 60,
        "Newton iterations per step unbounded: {}",
        with.max_iters_per_step
    );
    let without = run(false);
    eprintln!(
        "EIL: completed {} crossed {} max iters {} min h {:.2e}; plain EoL: completed {} crossed {} max iters {} min h {:.2e}",
        with.completed, with.crossed, with.max_iters_per_step, with.min_h,
        without.completed, without.crossed, without.max_iters_per_step, without.min_h
    );
    assert!(
        !without.completed || !without.crossed || without.min_h < with.min_h / 4.0,
        "plain EoL should fail, stall or need much smaller steps"
    );
}
