//! Stacked layers (*Robust Eulerian-on-Lagrangian Rods*, sec. 5 and
//! Fig. 7): two woven patches on each other, joined by layer contacts found
//! at the start, on a plane under gravity tilted by 20 degrees. The bottom
//! patch grips the plane (obstacle `mu` 0.8, above `tan 20 = 0.36`). With
//! no friction between the layers the top patch slides down over the
//! bottom one, which stays put; with layer friction above `tan 20` the two
//! move together, as Coulomb's law says a block on a block does.
//!
//! Also: how the layers are built (contacts shared by one yarn of each
//! layer, the upper yarn in front, `u` still increasing along every yarn)
//! and a seam (fixed `u` on both yarns).
//!
//! Release mode: `cargo test --release --test drape_layers -- --nocapture`
//! prints the measured slides.

mod contact_support;
mod drape_support;

use drape_support::woven_patch;
use knitsim::app::drape::layers::build_layers;
use knitsim::scene::Shape;
use knitsim::sim::dynamics::{dynamic_params, pin_nodes, run_dynamics};
use knitsim::sim::dynamics_settings::{Edge, Motion, Stretch};
use knitsim::sim::layers_settings::{PatchPlacement, Seam};
use knitsim::sim::{DynamicsParams, LayersParams, SeparationParams, Simulation};
use knitsim::solver::linear::LinearSolver;
use knitsim::topology::{ContactKind, Fabric, Vec3};

const TILT_DEG: f64 = 20.0;

/// Two copies of the woven patch, the top one half a pitch across in x and
/// y, so that its yarns cross the bottom one's between their own
/// crossings. At the same height: the layers touch where their yarns cross.
fn two_layers(seams: Vec<Seam>) -> LayersParams {
    stiff_top(seams, 1.0)
}

/// [`two_layers`] with the top patch's yarns `stiffness` times stiffer.
fn stiff_top(seams: Vec<Seam>, stiffness: f64) -> LayersParams {
    LayersParams {
        patches: vec![
            PatchPlacement::default(),
            PatchPlacement {
                translate: [1e-3, 1e-3, 0.0],
                rotate_deg: [0.0; 3],
                stiffness,
            },
        ],
        seams,
        gap: Some(0.0),
        ..LayersParams::default()
    }
}

/// The nodes that only `layer`'s yarns use in `f`.
fn own_nodes(f: &Fabric, layer: usize) -> Vec<usize> {
    let mut users = vec![0u32; f.nodes.len()];
    for yarn in &f.yarns {
        for p in &yarn.points {
            users[p.node] |= 1 << yarn.layer;
        }
    }
    (0..f.nodes.len()).filter(|&n| users[n] == 1 << layer).collect()
}

/// Mean position in `f` of the nodes `nodes`.
fn centre(f: &Fabric, nodes: &[usize]) -> Vec3 {
    nodes.iter().map(|&n| f.nodes[n].x).sum::<Vec3>() / nodes.len() as f64
}

#[test]
fn layer_contacts_join_one_yarn_of_each_layer_with_the_upper_yarn_in_front() {
    let base = woven_patch();
    let l = build_layers(&base, &two_layers(Vec::new())).expect("layers");
    let f = &l.fabric;
    let layer_contacts: Vec<_> = f.contacts.iter().filter(|c| c.kind == ContactKind::Layer).collect();
    // Top yarns along x (at y = -3 .. 5 mm, from x = -4 mm) over bottom
    // yarns along y (at x = -4 .. 4 mm, up to y = 5 mm): the crossings at
    // y = 5 mm and at x = -4 mm fall on a yarn's end point, which is no
    // crossing, leaving 4 x 4; the same for top yarns along y.
    assert_eq!(l.layer_contacts, 32, "layer contacts found");
    assert_eq!(layer_contacts.len(), 32);
    assert_eq!(f.contacts.len(), 2 * base.contacts.len() + 32);
    for c in &layer_contacts {
        let (tf, tb) = (f.yarns[c.front.yarn].layer, f.yarns[c.back.yarn].layer);
        assert_eq!((tf, tb), (1, 0), "the upper layer's yarn is in front");
        for p in [c.front, c.back] {
            let pt = &f.yarns[p.yarn].points[p.point];
            assert_eq!(pt.node, c.node, "both points share the contact node");
            assert!(!pt.fixed_u, "a layer contact slides");
        }
    }
    // The yarns' own contacts still point at their own nodes after the insertions.
    for c in &f.contacts {
        assert_eq!(f.yarns[c.front.yarn].points[c.front.point].node, c.node);
        assert_eq!(f.yarns[c.back.yarn].points[c.back.point].node, c.node);
    }
    for y in &f.yarns {
        assert!(
            y.points.windows(2).all(|w| w[1].u > w[0].u),
            "u increases along every yarn"
        );
    }
    // Patches too far apart do not touch.
    let mut far = two_layers(Vec::new());
    far.patches[1].translate[2] = 1e-3;
    assert_eq!(build_layers(&base, &far).expect("layers").layer_contacts, 0);
}

#[test]
fn a_seam_holds_its_yarns_at_fixed_u_and_is_not_a_sliding_contact() {
    let base = woven_patch();
    let seam = Seam {
        top: 1,
        bottom: 0,
        edges: vec![Edge::Left, Edge::Right],
        margin: 1.5e-3,
    };
    let l = build_layers(&base, &two_layers(vec![seam])).expect("layers");
    let f = &l.fabric;
    let seams: Vec<_> = f.contacts.iter().filter(|c| c.kind == ContactKind::Seam).collect();
    assert!(
        l.seam_contacts > 0 && seams.len() == l.seam_contacts,
        "{} seams",
        l.seam_contacts
    );
    for c in &seams {
        for p in [c.front, c.back] {
            let pt = &f.yarns[p.yarn].points[p.point];
            assert_eq!(pt.node, c.node);
            assert!(pt.fixed_u, "a seam does not slide");
        }
        // Only points near the top patch's left and right edges are sewn.
        let x = f.nodes[c.node].x.x - 1e-3;
        assert!(x.abs() > 5e-3 - 1.5e-3 - 1e-3, "seam at x = {x}");
    }
    let bad = LayersParams {
        seams: vec![Seam {
            top: 2,
            bottom: 0,
            edges: vec![Edge::Left],
            margin: 1e-3,
        }],
        ..two_layers(Vec::new())
    };
    let e = build_layers(&base, &bad)
        .err()
        .expect("a seam onto a missing patch is refused");
    assert!(e.to_string().contains("2 patches"), "{e}");
}

/// How the bottom patch is held.
#[derive(Clone, Copy)]
enum Hold {
    /// Every node only the bottom patch uses is pinned; no obstacle.
    Pins,
    /// It lies on a plane with obstacle friction 0.8.
    Plane,
}

/// Slides (m) of the bottom and the top layer's centres along the downhill
/// direction after `duration` seconds, with yarn-yarn friction `mu`, and
/// how many contacts were removed.
fn slides(mu: f64, duration: f64, hold: Hold) -> (f64, f64, usize) {
    let l = build_layers(&woven_patch(), &two_layers(Vec::new())).expect("layers");
    let mut p = knitsim::scene::params_for(&l.fabric, None).unwrap();
    p.contact = None;
    p.terms.wrapping = false;
    p.rod.mu = mu;
    let t = TILT_DEG.to_radians();
    p.dynamics = DynamicsParams {
        gravity: [9.81 * t.sin(), 0.0, -9.81 * t.cos()],
        dt: 1e-3,
        duration,
        rest_time: 0.0,
        ..DynamicsParams::default()
    };
    let f0 = l.fabric.clone();
    let mut fabric = l.fabric;
    match hold {
        Hold::Pins => {
            for n in own_nodes(&fabric, 0) {
                fabric.nodes[n].pinned = true;
            }
        }
        Hold::Plane => {
            p.obstacles = vec![Shape::Plane {
                point: [0.0, 0.0, -0.25e-3],
                normal: [0.0, 0.0, 1.0],
            }];
            p.dynamics.obstacle_mu = 0.8;
        }
    }
    let mut sim = Simulation::new(fabric, dynamic_params(p), LinearSolver::direct(), 1e-3);
    run_dynamics(&mut sim, &[], None, &mut |_, _| true).expect("dynamics");
    let f1 = sim.snapshot();
    // Each layer's own nodes at the start (a removed contact leaves a node
    // to one yarn, which must not join that layer's count).
    let moved = |k| {
        let own = own_nodes(&f0, k);
        (centre(&f1, &own) - centre(&f0, &own)).x
    };
    (moved(0), moved(1), sim.removed().len())
}

/// A frictionless block on a fixed one after `t` seconds of backward Euler
/// steps of 1 ms: `g sin(theta) t (t + h) / 2` (the exact `t^2` law's
/// discrete counterpart, as in the free-fall test of `drape_physics`).
fn free_slide(t: f64) -> f64 {
    0.5 * 9.81 * TILT_DEG.to_radians().sin() * t * (t + 1e-3)
}

/// The top patch on a pinned bottom one: frictionless, it slides downhill
/// as a free block does, its layer contacts passing the bottom patch's own
/// crossings as EIL points (from 1 mm on) and leaving the yarns at their
/// ends; with friction above `tan 20` it stays.
#[test]
fn a_patch_on_a_held_patch_slides_without_friction_and_sticks_above_tan_theta() {
    let duration = 0.05;
    let free = free_slide(duration);
    let (bottom, top, removed) = slides(0.0, duration, Hold::Pins);
    eprintln!(
        "pinned bottom, mu 0: top {:.3} mm (free slide {:.3} mm), {removed} contacts removed",
        top * 1e3,
        free * 1e3
    );
    assert!(bottom.abs() < 1e-9, "the pinned patch moved {:.3} mm", bottom * 1e3);
    assert!(removed > 0, "no layer contact left its yarn");
    assert!(
        (top / free - 1.0).abs() < 0.1,
        "the top layer slid {:.3} mm, a free block {:.3} mm",
        top * 1e3,
        free * 1e3
    );
    let (_, stuck, _) = slides(0.8, duration, Hold::Pins);
    eprintln!("pinned bottom, mu 0.8: top {:.3} mm", stuck * 1e3);
    assert!(
        stuck.abs() < 0.05e-3,
        "the top layer slid {:.3} mm at mu 0.8",
        stuck * 1e3
    );
}

/// Seed Fig. 7 in small: the bottom patch grips a plane tilted by 20
/// degrees. Frictionless, the top patch slides off it as a free block
/// would, and the bottom one stays (it creeps a tenth of a millimetre in
/// the plane's smoothed static friction, below `friction_speed`); with
/// layer friction above `tan 20` the top patch rides on the bottom one
/// (within a tenth of the free slide: the Coulomb limits come from each
/// step's lagged normal forces). The two then creep together: the bottom patch's grip on the plane is
/// that of its own weight only (`sim::terms::obstacle_friction`), against
/// the pull of both.
#[test]
fn on_a_tilted_plane_frictionless_layers_slide_over_each_other_and_the_bottom_one_stays() {
    let duration = 0.05;
    let free = free_slide(duration);
    let (bottom, top, removed) = slides(0.0, duration, Hold::Plane);
    eprintln!(
        "plane, mu 0: bottom {:.3} mm, top {:.3} mm (free slide {:.3} mm), {removed} contacts removed",
        bottom * 1e3,
        top * 1e3,
        free * 1e3
    );
    assert!(bottom.abs() < 0.3e-3, "the bottom layer moved {:.3} mm", bottom * 1e3);
    assert!(
        ((top - bottom) / free - 1.0).abs() < 0.1,
        "the top layer slid {:.3} mm on the bottom one, a free block {:.3} mm",
        (top - bottom) * 1e3,
        free * 1e3
    );
    let (bottom, top, _) = slides(0.8, duration, Hold::Plane);
    eprintln!("plane, mu 0.8: bottom {:.3} mm, top {:.3} mm", bottom * 1e3, top * 1e3);
    assert!(
        (top - bottom).abs() < 0.1 * free,
        "the top layer slid {:.3} mm on the bottom one at mu 0.8",
        (top - bottom) * 1e3
    );
}

/// Seed Fig. 6 in small: a patch 5 times stiffer than the one under it is
/// sewn onto it along its left and right edges, and the bottom patch is
/// pushed together from both sides by 30%. The stiff patch bows out as
/// one arch between its seams while the soft one under it folds in shorter
/// waves, so the layers pull apart and the sign test removes layer
/// contacts; the seams hold. Left alone, the same stack keeps every
/// contact.
#[test]
fn a_stiff_sewn_patch_buckles_off_the_compressed_one_under_it() {
    let (pulled, kinds, seams) = compress(0.7);
    assert!(pulled > 0, "no layer contact was removed by its normal force");
    assert!(
        kinds.iter().all(|k| *k == ContactKind::Layer),
        "removed kinds {kinds:?}"
    );
    assert_eq!(seams.0, seams.1, "a seam came apart");
    let (pulled, _, _) = compress(1.0);
    assert_eq!(pulled, 0, "contacts separated without compression");
}

/// The sewn stack of the test above, its bottom patch's edges moved to
/// `factor` of their distance from the middle: contacts removed by the
/// sign test, the kinds removed, and the seams before and after.
fn compress(factor: f64) -> (usize, Vec<ContactKind>, (usize, usize)) {
    let seams = vec![Seam {
        top: 1,
        bottom: 0,
        edges: vec![Edge::Left, Edge::Right],
        margin: 1.5e-3,
    }];
    let l = build_layers(&woven_patch(), &stiff_top(seams, 5.0)).expect("layers");
    assert!(l.seam_contacts > 0);
    let mut fabric = l.fabric;
    let mut p = knitsim::scene::params_for(&fabric, None).unwrap();
    p.contact = None;
    p.terms.wrapping = false;
    p.layers = Some(stiff_top(Vec::new(), 5.0));
    p.separation = Some(SeparationParams::default());
    // The bottom patch's own nodes beyond 3.5 mm from its middle: its edges.
    let edges: Vec<usize> = own_nodes(&fabric, 0)
        .into_iter()
        .filter(|&n| fabric.nodes[n].x.x.abs() > 3.5e-3)
        .collect();
    pin_nodes(&mut fabric, std::slice::from_ref(&edges));
    p.dynamics = DynamicsParams {
        gravity: [0.0; 3],
        damping: 5.0,
        dt: 1e-3,
        duration: 0.1,
        rest_time: 0.0,
        motions: vec![Motion {
            pins: 0,
            start: 0.0,
            end: 0.05,
            translate: None,
            stretch: Some(Stretch {
                center: [0.0; 3],
                factor: [factor, 1.0, 1.0],
            }),
        }],
        ..DynamicsParams::default()
    };
    let seams_before = fabric.contacts.iter().filter(|c| c.kind == ContactKind::Seam).count();
    let mut sim = Simulation::new(fabric, dynamic_params(p), LinearSolver::direct(), 1e-3);
    run_dynamics(&mut sim, &[edges], None, &mut |_, _| true).expect("dynamics");
    let pulled = sim.removed().iter().filter(|r| !r.cause.is_slid_off()).count();
    let kinds: Vec<ContactKind> = sim.removed().iter().map(|r| r.contact.kind).collect();
    let f = sim.snapshot();
    let seams_after = f.contacts.iter().filter(|c| c.kind == ContactKind::Seam).count();
    eprintln!(
        "edges to {factor}: {} layer contacts, {} seams; removed by the sign test: {pulled}, by sliding off: {}",
        l.layer_contacts,
        seams_before,
        sim.removed().len() - pulled
    );
    (pulled, kinds, (seams_before, seams_after))
}
