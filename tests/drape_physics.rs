//! Implicit dynamics against references outside the code: free fall,
//! a compound pendulum, Coulomb friction on an incline, and a patch
//! dropped on a plane that comes to rest without any yarn passing through
//! another.
//!
//! The fabric is a small woven patch (yarns crossing at persistent EoL
//! contacts, material sliding through them), whose implicit steps converge
//! at millisecond time steps; a knitted swatch's do not yet (docs/MODEL.md,
//! "Dynamics").
//!
//! Release mode: `cargo test --release --test drape_physics -- --nocapture`
//! prints the measured figures.

mod contact_support;
mod drape_support;
mod fabric_frames;

use contact_support::crossing_pairs;
use drape_support::woven_patch;
use fabric_frames::{node_positions, Segments};
use knitsim::scene::Shape;
use knitsim::sim::discretization::transfer::transfer;
use knitsim::sim::dynamics::{centre_of_mass, dynamic_params, pin_nodes, run_dynamics, schedule};
use knitsim::sim::{ContactParams, DynamicsParams, SimParams, Simulation, Terms};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::{Fabric, Vec3};

const G: f64 = 9.81;

fn lowest_z(f: &Fabric) -> f64 {
    f.nodes.iter().map(|n| n.x.z).fold(f64::INFINITY, f64::min)
}

/// The patch's radius, no thickness contact, no wrapping (there are no
/// stitches), with `dynamics`.
fn params(f: &Fabric, dynamics: DynamicsParams) -> SimParams {
    let mut p = knitsim::scene::params_for(f, None).unwrap();
    p.contact = None;
    p.terms.wrapping = false;
    p.dynamics = dynamics;
    dynamic_params(p)
}

/// Before it touches anything, the patch's centre of mass falls by
/// `g t^2 / 2`. Backward Euler's discrete fall is `g t (t + h) / 2`, so
/// the test compares at `t >= 0.08 s` with `h = 0.5 ms` (0.6% or less).
#[test]
fn free_fall_follows_g_t_squared_over_two() {
    let f = woven_patch();
    let d = DynamicsParams {
        dt: 5e-4,
        duration: 0.1,
        rest_time: 0.0,
        ..DynamicsParams::default()
    };
    let p = params(&f, d);
    let mut sim = Simulation::new(f, p, LinearSolver::direct(), 5e-4);
    let z0 = centre_of_mass(&sim)[2];
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    run_dynamics(&mut sim, &[], None, &mut |sim, row| {
        if row.time >= 0.08 - 1e-9 {
            let fall = z0 - centre_of_mass(sim)[2];
            let expect = 0.5 * G * row.time * row.time;
            worst = worst.max((fall / expect - 1.0).abs());
            checked += 1;
        }
        true
    })
    .unwrap();
    eprintln!("free fall: worst relative error {worst:.2e} over {checked} steps");
    assert!(checked >= 10, "only {checked} steps checked");
    assert!(worst < 0.01, "free fall off by {:.2}%", 100.0 * worst);
}

/// A stiff yarn of length `L` pinned at its top end swings as a rigid rod
/// about that end: a compound pendulum of period `2 pi sqrt(2 L / (3 g))`
/// at small amplitude. It applies because (1) the pinned node fixes the
/// position but not the direction of the first segment (bending acts
/// between segments only), so the end is a frictionless hinge; (2) the
/// bending stiffness (`kb = 1e-3 N m^2`) keeps the yarn straight to about
/// 1e-3 rad under its own weight and the stretch stiffness keeps its length
/// to 1e-6; (3) the consistent segment mass integrates the kinetic energy
/// of a linear velocity field exactly, so the rod's moment of inertia is
/// exactly `rho L^3 / 3`; and (4) at 0.1 rad the amplitude correction
/// (`theta^2 / 16`) is 6e-4. Backward Euler shifts the period only by
/// `O((omega h)^2)`, 1e-4 at `h = 1 ms`; the period is measured between
/// zero crossings of the tip's horizontal position. It damps the swing:
/// per step the amplitude of an oscillator of frequency `omega` is divided
/// by `sqrt(1 + (omega h)^2)`, so it decays as `exp(-omega^2 h t / 2)`,
/// which the test checks too (docs/MODEL.md, "Dynamics").
#[test]
fn stiff_yarn_swings_as_a_compound_pendulum() {
    let l = 0.1;
    let theta: f64 = 0.1;
    let mut f =
        drape_support::common::yarn_fabric(l, 10, |s| Vec3::new(s * l * theta.sin(), 0.0, -s * l * theta.cos()));
    pin_nodes(&mut f, &[vec![0]]);
    let mut p = SimParams {
        terms: Terms {
            friction: false,
            ..Terms::default()
        },
        dynamics: DynamicsParams {
            dt: 1e-3,
            duration: 1.3,
            rest_time: 0.0,
            ..DynamicsParams::default()
        },
        ..SimParams::default()
    };
    p.rod.kb = 1e-3;
    let p = dynamic_params(p);
    let tip = 10;
    let mut sim = Simulation::new(f, p, LinearSolver::direct(), 1e-3);
    let mut last = (0.0, sim.q()[sim.layout().x(tip)]);
    let mut crossings: Vec<f64> = Vec::new();
    // Largest |x| of the tip in each half swing: (time, amplitude).
    let mut peaks: Vec<(f64, f64)> = vec![(0.0, last.1.abs())];
    run_dynamics(&mut sim, &[vec![0]], None, &mut |sim, row| {
        let x = sim.q()[sim.layout().x(tip)];
        if last.1 > 0.0 && x <= 0.0 || last.1 < 0.0 && x >= 0.0 {
            crossings.push(last.0 + (row.time - last.0) * last.1 / (last.1 - x));
            peaks.push((row.time, 0.0));
        }
        let p = peaks.last_mut().unwrap();
        if x.abs() > p.1 {
            *p = (row.time, x.abs());
        }
        last = (row.time, x);
        true
    })
    .unwrap();
    assert!(crossings.len() >= 4, "{crossings:?}");
    // Half periods between successive zero crossings.
    let n = crossings.len() - 1;
    let measured = 2.0 * (crossings[n] - crossings[0]) / n as f64;
    let expect = 2.0 * std::f64::consts::PI * (2.0 * l / (3.0 * G)).sqrt();
    eprintln!("pendulum: period {measured:.5} s, compound pendulum {expect:.5} s, {n} half periods");
    assert!(
        (measured / expect - 1.0).abs() < 0.02,
        "period {measured} s against {expect} s"
    );
    // Amplitude decay between the first and the last complete half swing.
    let (first, last) = (peaks[0], peaks[peaks.len() - 2]);
    let omega = 2.0 * std::f64::consts::PI / expect;
    let decay = last.1 / first.1;
    let predicted = (-omega * omega * 1e-3 * (last.0 - first.0) / 2.0).exp();
    eprintln!(
        "pendulum: amplitude ratio {decay:.4} over {:.3} s, backward Euler predicts {predicted:.4}",
        last.0 - first.0
    );
    assert!((decay - predicted).abs() < 0.02, "decay {decay} against {predicted}");
}

/// The patch resting on the plane `z = 0` with gravity tilted by `angle`
/// from the normal; returns its centre of mass's downhill (x) travel after
/// 0.1 s and the block-on-incline prediction `g (sin - mu cos) t^2 / 2`.
fn incline_travel(f: &Fabric, angle_deg: f64, mu: f64) -> (f64, f64) {
    let a = angle_deg.to_radians();
    let mut f = f.clone();
    let r = knitsim::scene::fabric_radius(&f).unwrap();
    let dz = r - lowest_z(&f);
    for n in &mut f.nodes {
        n.x.z += dz;
    }
    let d = DynamicsParams {
        gravity: [G * a.sin(), 0.0, -G * a.cos()],
        obstacle_mu: mu,
        dt: 1e-3,
        duration: 0.1,
        rest_time: 0.0,
        ..DynamicsParams::default()
    };
    let mut p = params(&f, d);
    p.obstacles = vec![Shape::Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
    }];
    let mut sim = Simulation::new(f, p, LinearSolver::direct(), 1e-3);
    let x0 = centre_of_mass(&sim)[0];
    let rep = run_dynamics(&mut sim, &[], None, &mut |_, _| true).unwrap();
    let t = rep.time;
    let block = 0.5 * G * (a.sin() - mu * a.cos()).max(0.0) * t * t;
    (centre_of_mass(&sim)[0] - x0, block)
}

/// Coulomb: with `mu = 0.5` (`atan mu = 26.6 deg`) the patch sticks at
/// 15 degrees and slides at 40 degrees, as a block would.
#[test]
fn a_patch_sticks_below_atan_mu_and_slides_above() {
    let f = woven_patch();
    let mu = 0.5;
    let (stick, _) = incline_travel(&f, 15.0, mu);
    let (slide, block) = incline_travel(&f, 40.0, mu);
    let frictionless = 0.5 * G * 15f64.to_radians().sin() * 0.01;
    eprintln!(
        "incline: 15 deg travel {:.3} mm (frictionless {:.1} mm); 40 deg travel {:.3} mm, block {:.3} mm",
        stick * 1e3,
        frictionless * 1e3,
        slide * 1e3,
        block * 1e3
    );
    assert!(stick.abs() < 0.02 * frictionless, "slid {stick} m at 15 degrees");
    assert!(
        slide > 0.8 * block && slide < 1.2 * block,
        "slid {slide} m at 40 degrees, a block slides {block} m"
    );
}

/// A patch dropped 5 mm onto a plane with thickness contact on comes to
/// rest, and the independent frame-to-frame check finds no yarn passing
/// through another over any step.
#[test]
fn a_patch_dropped_on_a_plane_comes_to_rest_without_crossings() {
    let f = woven_patch();
    let r = knitsim::scene::fabric_radius(&f).unwrap();
    let d = DynamicsParams {
        obstacle_mu: 0.3,
        dt: 1e-3,
        max_dt: Some(4e-3),
        duration: 1.0,
        ..DynamicsParams::default()
    };
    let mut p = knitsim::scene::params_for(&f, None).unwrap();
    p.terms.wrapping = false;
    p.dynamics = d;
    let p = dynamic_params(p);
    let plane_z = lowest_z(&f) - 5e-3;
    let mut p = p;
    p.obstacles = vec![Shape::Plane {
        point: [0.0, 0.0, plane_z],
        normal: [0.0, 0.0, 1.0],
    }];
    let cp: ContactParams = p.contact.clone().unwrap();
    let thickness = cp.thickness_for(r);
    let exclusion = cp.eol_exclusion * thickness;
    let touch = 1e-3 * 0.5 * thickness;
    let mut sim = Simulation::new(f, p.clone(), LinearSolver::direct(), 1e-3);
    let mut sched = schedule(&sim, &p.dynamics);
    let (mut crossings, mut steps, mut rest_for, mut t_rest) = (0, 0, 0.0, None);
    while sim.time() < p.dynamics.duration {
        let (q0, a0) = (sim.q().to_vec(), sim.assignment().clone());
        let s = sim.step_with(&mut sched, true, None, &mut |_, _| {}).unwrap();
        assert!(s.converged);
        steps += 1;
        let a1 = sim.assignment();
        let mut start = q0;
        transfer(sim.fabric(), sim.layout(), &a0, a1, &mut start);
        let segs = Segments::new(&sim, a1, &start, exclusion);
        let x0 = node_positions(&sim, &start);
        let x1 = node_positions(&sim, sim.q());
        crossings += crossing_pairs(&x0, &x1, &segs.segs, touch, |i, j| segs.joined(i, j))
            .into_iter()
            .filter(|&(i, j, t)| segs.link(i, j, |n| x0[n] + (x1[n] - x0[n]) * t) >= touch)
            .count();
        let speed = knitsim::sim::dynamics::max_speed(&sim);
        rest_for = if speed < p.dynamics.rest_speed {
            rest_for + s.h
        } else {
            0.0
        };
        if rest_for >= p.dynamics.rest_time {
            t_rest = Some(sim.time());
            break;
        }
    }
    let low = node_positions(&sim, sim.q())
        .iter()
        .map(|x| x.z)
        .fold(f64::INFINITY, f64::min);
    eprintln!(
        "plane drop: {steps} steps, at rest at {t_rest:?} s, {crossings} crossings, lowest node {:.3} radii above the plane",
        (low - plane_z) / r
    );
    assert!(t_rest.is_some(), "not at rest after {} s", sim.time());
    assert_eq!(crossings, 0);
    assert!(low - plane_z > 0.5 * r, "a node sank into the plane");
}

/// The shipped form (`examples/scenes/form.obj`) read by this test alone:
/// its face planes as (point, outward normal), scaled and moved.
fn form_planes(scale: f64, offset: Vec3) -> Vec<(Vec3, Vec3)> {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/scenes/form.obj")).unwrap();
    let mut v: Vec<Vec3> = Vec::new();
    let mut planes = Vec::new();
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first() {
            Some(&"v") => {
                v.push(Vec3::new(w[1].parse().unwrap(), w[2].parse().unwrap(), w[3].parse().unwrap()) * scale + offset)
            }
            Some(&"f") => {
                let k: Vec<usize> = w[1..].iter().map(|s| s.parse::<usize>().unwrap() - 1).collect();
                let n = (v[k[1]] - v[k[0]]).cross(&(v[k[2]] - v[k[0]])).normalize();
                planes.push((v[k[0]], n));
            }
            _ => {}
        }
    }
    planes
}

/// A patch dropped onto the shipped OBJ form (a convex ellipsoid, scaled to
/// 8 x 8 x 6 mm) drapes over it, and no node is ever inside it: the
/// check is the convex polyhedron's half-space test on the OBJ faces,
/// independent of the simulator's distance field.
#[test]
fn a_patch_drapes_over_an_obj_form_and_no_node_ends_inside() {
    let f = woven_patch();
    let r = knitsim::scene::fabric_radius(&f).unwrap();
    let scale = 0.2;
    let top = 0.015 * scale;
    let offset = Vec3::new(0.0, 0.0, lowest_z(&f) - 2.0 * r - top);
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/scenes/form.obj")).unwrap();
    let mesh = knitsim::rod::trimesh::TriMesh::from_obj(&text, scale, offset).unwrap();
    let d = DynamicsParams {
        obstacle_mu: 0.3,
        dt: 1e-3,
        max_dt: Some(2e-3),
        duration: 0.3,
        rest_time: 0.0,
        ..DynamicsParams::default()
    };
    let mut p = params(&f, d);
    // A limp yarn (bending length 6 mm), so the 10 mm patch can drape.
    p.rod.kb = 1e-9;
    p.obstacles = vec![Shape::Mesh {
        path: "form.obj".into(),
        scale,
        translate: [offset.x, offset.y, offset.z],
        mesh: std::sync::Arc::new(mesh),
    }];
    let planes = form_planes(scale, offset);
    let mut sim = Simulation::new(f, p, LinearSolver::direct(), 1e-3);
    let mut inside = 0;
    let z0 = centre_of_mass(&sim)[2];
    let rep = run_dynamics(&mut sim, &[], None, &mut |sim, _| {
        for x in node_positions(sim, sim.q()) {
            if planes.iter().all(|(p, n)| n.dot(&(x - p)) < 0.0) {
                inside += 1;
            }
        }
        true
    })
    .unwrap();
    let xs = node_positions(&sim, sim.q());
    let form_top = offset.z + top;
    // The overhang: nodes outside the form's 8 x 8 mm footprint. They start
    // two yarn radii above the form's top; resting on the form, the patch
    // bends its overhang down past the top.
    let half = 0.02 * scale;
    let overhang: Vec<f64> = xs
        .iter()
        .filter(|x| (x.x - offset.x).abs().max((x.y - offset.y).abs()) > half)
        .map(|x| form_top - x.z)
        .collect();
    let lowest_edge = overhang.iter().copied().fold(f64::INFINITY, f64::min);
    eprintln!(
        "mesh form: {} steps, {inside} nodes inside over all steps, centre of mass fell {:.2} mm; {} overhanging nodes, the highest {:.2} mm below the form's top",
        rep.steps,
        (z0 - centre_of_mass(&sim)[2]) * 1e3,
        overhang.len(),
        lowest_edge * 1e3
    );
    assert_eq!(inside, 0);
    assert!(overhang.len() >= 4, "{} overhanging nodes", overhang.len());
    assert!(
        lowest_edge > 0.0,
        "an overhanging node {} m above the form's top",
        -lowest_edge
    );
}
