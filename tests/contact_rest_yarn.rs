//! *Unlocking Thickness Modeling for Codimensional Contact Simulation*,
//! Fig. 2: a 5 cm yarn at rest, resolution finer than its
//! thickness, with only elastic and contact forces. The plain barrier sees
//! neighbouring segments inside the thickness and pushes the yarn longer
//! (contact locking); the filtered barrier must exert no force at all and
//! leave the length unchanged.

mod contact_support;

use contact_support::{arc_length, polyline_fabric, positions, simulation, yarn_params};
use knitsim::sim::ContactModeName;
use knitsim::topology::Vec3;

const LENGTH: f64 = 0.05;
const RADIUS: f64 = 0.25e-3; // h = 0.5 mm
const SEGMENTS: usize = 200; // 0.25 mm: two segments per thickness

/// Contact energy at the start, length after relaxing, contact energy after.
fn rest_yarn(mode: ContactModeName) -> (f64, f64, f64) {
    let pts: Vec<Vec3> = (0..=SEGMENTS)
        .map(|i| Vec3::new(LENGTH * i as f64 / SEGMENTS as f64, 0.0, 0.0))
        .collect();
    let mut sim = simulation(polyline_fabric(&pts, RADIUS), yarn_params(RADIUS, mode, 11));
    let contact_energy = |sim: &knitsim::sim::Simulation| {
        let p = sim.problem(None).expect("problem");
        p.breakdown(sim.q())
            .into_iter()
            .filter(|(n, _)| n == "contact")
            .map(|(_, e)| e)
            .sum::<f64>()
    };
    let e0 = contact_energy(&sim);
    for _ in 0..20 {
        sim.step(false, None, &mut |_, _| {}).expect("step");
    }
    (e0, arc_length(&positions(&sim)), contact_energy(&sim))
}

#[test]
fn filtered_rest_yarn_feels_no_contact_and_keeps_its_length() {
    let (e0, len, e1) = rest_yarn(ContactModeName::Filtered);
    eprintln!("filtered: contact energy {e0:e} -> {e1:e}, length {len:.9} m");
    assert_eq!(e0, 0.0, "no filtered stencil may be active at rest");
    assert_eq!(e1, 0.0);
    assert!((len - LENGTH).abs() < 1e-9 * LENGTH, "length changed: {len}");
}

#[test]
fn plain_barrier_rest_yarn_grows() {
    let (e0, len, _) = rest_yarn(ContactModeName::Barrier);
    eprintln!("barrier: contact energy at rest {e0:e}, length {len:.9} m");
    assert!(e0 > 0.0, "neighbours within h must be active for the plain barrier");
    assert!(len > LENGTH * (1.0 + 1e-4), "the locked yarn should expand: {len}");
}
