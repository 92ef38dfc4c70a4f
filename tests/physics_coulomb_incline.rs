//! The friction validation of *Robust Eulerian-on-Lagrangian Rods*: a yarn patch lying on a fixed patch with
//! `mu = 1` stays put on a 40 degree incline and slides on a 50 degree one
//! (Coulomb: slide iff `tan(theta) > mu`).
//!
//! Scene: three parallel yarns along x (the free patch) cross nine fixed
//! yarns along y (the fixed patch) at persistent EoL contacts, one shared
//! node per crossing. The fixed yarns are pinned at their ends and their
//! contact points have fixed `u`, so only the free yarns' material can
//! slide through the crossings. The incline is a tilted gravity vector,
//! `g (sin theta, 0, -cos theta)`, so downhill is +x.
//!
//! The reference outside the code is the Coulomb block on an incline:
//! sticking for `tan theta < mu`, and for `tan theta > mu` a uniform
//! acceleration `a = g (sin theta - mu cos theta)`, so a slide of
//! `a t^2 / 2` after time `t`. The free yarns are straight and lie on the
//! fixed ones, so every contact carries the weight of the yarn around it
//! and the block law holds per contact.

mod common;

use knitsim::sim::{SimParams, Simulation, Terms};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::{Contact, ContactKind, Fabric, Node, PointRef, Vec3};

const G: f64 = 9.81;
const XS: [f64; 9] = [-0.020, -0.015, -0.010, -0.005, 0.0, 0.005, 0.010, 0.015, 0.020];
const YS: [f64; 3] = [-0.0015, 0.0, 0.0015];
/// Free yarns run from -TAIL to +TAIL: 3 mm of tail beyond the outer
/// crossings, room to slide without a contact reaching a yarn end.
const TAIL: f64 = 0.023;

/// The two patches; returns the fabric and the contact point refs of the
/// free yarns (yarn, point) for measuring the slide.
fn scene() -> (Fabric, Vec<PointRef>) {
    let mut f = common::empty_fabric(0.25e-3);
    for &x in &XS {
        for &y in &YS {
            f.nodes.push(Node {
                x: Vec3::new(x, y, 0.0),
                pinned: false,
            });
        }
    }
    let node = |i: usize, j: usize| i * YS.len() + j;
    let mut free_points = Vec::new();
    let mut free_yarns = Vec::new();
    for (j, &y) in YS.iter().enumerate() {
        let mut pts = vec![Vec3::new(-TAIL, y, 0.0)];
        let mut at = vec![None];
        for (i, &x) in XS.iter().enumerate() {
            pts.push(Vec3::new(x, y, 0.0));
            at.push(Some(node(i, j)));
        }
        pts.push(Vec3::new(TAIL, y, 0.0));
        at.push(None);
        let yarn = common::add_yarn(&mut f, &pts, &at);
        free_yarns.push(yarn);
        free_points.extend((1..=XS.len()).map(|point| PointRef { yarn, point }));
    }
    for (i, &x) in XS.iter().enumerate() {
        let half = 0.004;
        let mut pts = vec![Vec3::new(x, -half, 0.0)];
        let mut at = vec![None];
        for (j, &y) in YS.iter().enumerate() {
            pts.push(Vec3::new(x, y, 0.0));
            at.push(Some(node(i, j)));
        }
        pts.push(Vec3::new(x, half, 0.0));
        at.push(None);
        let yarn = common::add_yarn(&mut f, &pts, &at);
        let n = f.yarns[yarn].points.len();
        for k in 0..n {
            // The fixed patch: material does not slide, ends pinned.
            f.yarns[yarn].points[k].fixed_u = true;
        }
        for k in [0, n - 1] {
            let nd = f.yarns[yarn].points[k].node;
            f.nodes[nd].pinned = true;
        }
        for (j, _) in YS.iter().enumerate() {
            f.contacts.push(Contact {
                node: node(i, j),
                front: PointRef {
                    yarn: free_yarns[j],
                    point: 1 + i,
                },
                back: PointRef { yarn, point: 1 + j },
                kind: ContactKind::Layer,
                partner: None,
            });
        }
    }
    (f, free_points)
}

/// Mean slide (m) of the free yarns' material downhill after each of `steps`
/// implicit Euler steps of `h`: material moving +x lowers `u` at a fixed
/// crossing.
fn slide(theta_deg: f64, steps: usize, h: f64) -> Vec<f64> {
    let (f, points) = scene();
    let theta = theta_deg.to_radians();
    let mut p = SimParams {
        terms: Terms {
            gravity: true,
            friction: true,
            wrapping: false,
            parallel: false,
            ..Terms::default()
        },
        ..SimParams::default()
    };
    p.rod.mu = 1.0;
    // The crossing shear at the crossings carries part of the downhill
    // load, so the slide depends on it: at 50 degrees it is 5% above the
    // block's at 3e-5 J/rad^2 (the default yarn's), 10% above at 1.8e-5
    // and 17% above without shear. Held at the default yarn's value.
    p.rod.ksh_factor = 3e-5 * p.rod.diameter() / p.rod.kb;
    p.rod.gravity = Vec3::new(theta.sin(), 0.0, -theta.cos()) * G;
    let mut sim = Simulation::new(f, p, LinearSolver::direct(), h);
    let u0: Vec<f64> = points.iter().map(|&pr| sim.q()[sim.layout().u(pr)]).collect();
    let mean_slide = |sim: &Simulation| {
        let moved: f64 = points
            .iter()
            .zip(&u0)
            .map(|(&pr, u0)| u0 - sim.q()[sim.layout().u(pr)])
            .sum();
        moved / points.len() as f64
    };
    let mut trace = Vec::with_capacity(steps);
    for k in 0..steps {
        let r = sim
            .step(true, None, &mut |_, _| {})
            .unwrap_or_else(|e| panic!("{theta_deg} deg, step {k}: {e}"));
        assert!(r.converged, "{theta_deg} deg, step {k}: Newton did not converge");
        assert_eq!(r.h, h, "the step had to shrink");
        assert!(sim.q().iter().all(|v| v.is_finite()));
        trace.push(mean_slide(&sim));
    }
    trace
}

/// Slide of a Coulomb block, `g (sin - mu cos) t^2 / 2` (zero when it sticks).
fn block_slide(theta_deg: f64, mu: f64, t: f64) -> f64 {
    let th = theta_deg.to_radians();
    (G * (th.sin() - mu * th.cos())).max(0.0) * t * t / 2.0
}

#[test]
fn patch_sticks_at_40_degrees_and_slides_at_50_with_mu_1() {
    let (steps, h) = (30, 1e-3);
    let t = steps as f64 * h;
    let mut rows = Vec::new();
    for theta in [40.0, 50.0, 60.0] {
        let trace = slide(theta, steps, h);
        let s = *trace.last().unwrap();
        let late = s - trace[steps - 11];
        let expect = block_slide(theta, 1.0, t);
        eprintln!(
            "theta {theta:4.1} deg: slide {s:.4e} m after {t} s (last 10 steps {late:.2e} m), Coulomb block {expect:.4e} m"
        );
        rows.push((theta, s, late, expect));
    }
    // 40 degrees: static friction holds. What moves is the settling of the
    // first steps (the fixed yarns take up the load, the friction springs
    // their elastic stick); after that the patch is at rest.
    let (_, s40, late40, _) = rows[0];
    assert!(s40.abs() < 1e-5, "40 deg: slid {s40:.3e} m");
    assert!(
        late40.abs() < 1e-9,
        "40 deg: still creeping, {late40:.3e} m in the last 10 steps"
    );
    // 50 and 60 degrees: the patch slides, at the Coulomb block's rate.
    for &(theta, s, _, expect) in &rows[1..] {
        let rel = (s - expect).abs() / expect;
        assert!(
            rel < 0.1,
            "{theta} deg: slide {s:.4e} m vs Coulomb {expect:.4e} m ({rel:.2})"
        );
    }
}
