use crate::sim::discretization::assignment::tests::crossing_fabric;
use crate::sim::events::RemovalCause;
use crate::sim::params::SeparationParams;
use crate::sim::{SimParams, Simulation};
use crate::solver::linear::LinearSolver;
use crate::topology::{ContactKind, Fabric};

/// Two straight yarns 40 mm long crossing at their middles, at the origin:
/// yarn 0 (front) along x, yarn 1 (back) along y, one `Layer` contact on
/// node 0. Every other point is a fixed-`u` point 10 mm from the next; the
/// four yarn ends are pinned.
fn two_layers() -> Fabric {
    let mut nodes = vec![[0.0, 0.0, 0.0]];
    let mut yarns: [Vec<(usize, f64, bool)>; 2] = [vec![], vec![]];
    for (y, pts) in yarns.iter_mut().enumerate() {
        for i in 0..5 {
            let s = 0.01 * i as f64 - 0.02;
            if i == 2 {
                pts.push((0, 0.02, false));
            } else {
                pts.push((nodes.len(), 0.01 * i as f64, true));
                nodes.push(if y == 0 { [s, 0.0, 0.0] } else { [0.0, s, 0.0] });
            }
        }
    }
    let mut f = crossing_fabric(&nodes, [&yarns[0], &yarns[1]], 0.04, 2, 2);
    f.contacts[0].kind = ContactKind::Layer;
    for y in &f.yarns {
        for end in [0, 4] {
            f.nodes[y.points[end].node].pinned = true;
        }
    }
    f
}

/// Moves the front yarn's pinned ends by `dz` along z, then takes `steps`
/// quasi-static steps (the move is applied before the first).
fn move_front_ends(separation: Option<SeparationParams>, dz: f64, steps: usize) -> Simulation {
    let mut p = SimParams::default();
    p.terms.friction = false;
    p.terms.secured_ends = false;
    p.separation = separation;
    let mut sim = Simulation::new(two_layers(), p, LinearSolver::direct(), 1e-2);
    for end in [0, 4] {
        let node = sim.fabric().yarns[0].points[end].node;
        let z = sim.layout().x(node) + 2;
        sim.q_mut()[z] += dz;
    }
    for _ in 0..steps {
        sim.step(false, None, &mut |_, _| {}).expect("step");
    }
    sim
}

fn node_z(sim: &Simulation, yarn: usize, point: usize) -> f64 {
    sim.layout()
        .node_x(sim.q(), sim.fabric().yarns[yarn].points[point].node)
        .z
}

#[test]
fn the_normal_starts_from_the_front_on_the_plus_z_side() {
    let sim = move_front_ends(Some(SeparationParams::default()), 0.0, 0);
    assert_eq!(sim.contact_normals().len(), 1);
    assert!((sim.contact_normals()[0] - crate::topology::Vec3::z()).norm() < 1e-12);
    // Nothing loads the contact yet: its normal force is zero, not negative.
    let n = sim.contact_normal_forces()[0].expect("a layer contact is tested");
    assert!(n.abs() < 1e-9, "{n}");
}

#[test]
fn a_front_yarn_lifted_off_its_layer_separates() {
    // Lifted 1 mm: the first step ends with the node pulled between the
    // two yarns, so the contact pulls and is split right there.
    let sim = move_front_ends(Some(SeparationParams::default()), 0.001, 1);
    assert!(sim.fabric().contacts.is_empty());
    assert_eq!(sim.removed().len(), 1);
    assert!(matches!(sim.removed()[0].cause, RemovalCause::Pulling { normal_force } if normal_force < 0.0));
    let (front, back) = (&sim.fabric().yarns[0].points[2], &sim.fabric().yarns[1].points[2]);
    assert_ne!(front.node, back.node);
    assert!(front.fixed_u && back.fixed_u);
    assert_eq!(sim.fabric().nodes.len(), 10);
    // The copy starts where the shared node was.
    assert_eq!(node_z(&sim, 0, 2), node_z(&sim, 1, 2));

    // The yarns then relax apart: each lies straight between its own pins
    // (to 2% of the lift: the last, bending-dominated sag relaxes slowly;
    // 6e-6 m after 6 steps).
    let sim = move_front_ends(Some(SeparationParams::default()), 0.001, 6);
    assert_eq!(sim.removed().len(), 1);
    for pi in 0..5 {
        assert!(
            (node_z(&sim, 0, pi) - 0.001).abs() < 2e-5,
            "front point {pi}: {}",
            node_z(&sim, 0, pi)
        );
        assert!(
            node_z(&sim, 1, pi).abs() < 2e-5,
            "back point {pi}: {}",
            node_z(&sim, 1, pi)
        );
    }
    assert!(sim.q().iter().all(|v| v.is_finite()));
}

#[test]
fn without_separation_a_lifted_layer_stays_stuck_and_its_contact_pulls() {
    // What the sign test prevents: the back yarn held up by a contact that
    // pulls, the pair tented between their pins.
    let mut sim = move_front_ends(None, 0.001, 3);
    assert_eq!(sim.fabric().contacts.len(), 1);
    assert!(sim.contact_normals().is_empty());
    let z = node_z(&sim, 1, 2);
    assert!(z > 1e-5 && z < 0.001 - 1e-5, "shared node at z = {z}");
    sim.params_mut().separation = Some(SeparationParams::default());
    sim.update_contact_normals();
    let n = sim.contact_normal_forces()[0].expect("tested");
    assert!(n < 0.0, "normal force {n} N");
}

#[test]
fn a_front_yarn_pressed_into_its_layer_stays_in_contact() {
    // Pressed 1 mm: the contact pushes, and both yarns bend together.
    let sim = move_front_ends(Some(SeparationParams::default()), -0.001, 3);
    assert_eq!(sim.fabric().contacts.len(), 1);
    assert!(sim.removed().is_empty());
    let n = sim.contact_normal_forces()[0].expect("tested");
    assert!(n > 0.0, "normal force {n} N");
    let z = node_z(&sim, 0, 2);
    assert!(z < -1e-5 && z > -0.001 + 1e-5, "shared node at z = {z}");
}

/// The lifted pair after one step without separation, then with the
/// default separation settings switched on.
fn stuck_pair() -> Simulation {
    let mut sim = move_front_ends(None, 0.001, 1);
    sim.params_mut().separation = Some(SeparationParams::default());
    sim.update_contact_normals();
    sim
}

#[test]
fn only_the_listed_kinds_are_tested() {
    let mut sim = stuck_pair();
    sim.state_mut().fabric.contacts[0].kind = ContactKind::Stitch;
    assert_eq!(sim.contact_normal_forces(), vec![None]);
    assert_eq!(sim.separate_pulling(), 0);
    let stitches = SeparationParams {
        kinds: vec![ContactKind::Float, ContactKind::Stitch],
        min_pull: 0.0,
    };
    sim.params_mut().separation = Some(stitches);
    assert!(sim.contact_normal_forces()[0].is_some_and(|n| n < 0.0));
}

#[test]
fn min_pull_is_a_threshold_in_newtons() {
    let mut sim = stuck_pair();
    let n = sim.contact_normal_forces()[0].expect("tested");
    sim.params_mut().separation.as_mut().expect("on").min_pull = -2.0 * n;
    assert_eq!(sim.separate_pulling(), 0);
    sim.params_mut().separation.as_mut().expect("on").min_pull = -0.5 * n;
    assert_eq!(sim.separate_pulling(), 1);
}

#[test]
fn the_scene_key_parses_with_defaults() {
    let p: SimParams = serde_json::from_str(r#"{"separation": {}}"#).expect("parses");
    assert_eq!(p.separation, Some(SeparationParams::default()));
    let p: SimParams = serde_json::from_str(r#"{"separation": {"kinds": ["Float"], "min_pull": 0.01}}"#).unwrap();
    assert_eq!(p.separation.unwrap().kinds, vec![ContactKind::Float]);
    assert!(serde_json::from_str::<SimParams>(r#"{"separation": {"kind": []}}"#).is_err());
    assert_eq!(SimParams::default().separation, None);
}
