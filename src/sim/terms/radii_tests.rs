//! Per-yarn radii (`SimParams::radii`): the distances the rod model keeps
//! between yarns of different thickness are sums of the radii actually
//! there, and one radius for all is still the default of a `SimParams`
//! built in code.

use super::obstacle_contact::obstacle_terms;
use super::parallel_yarns::parallel_terms;
use crate::io::fixtures::meta;
use crate::rod::obstacle::Shape;
use crate::sim::discretization::assignment::{assign, rest_segment_lengths};
use crate::sim::discretization::dofs::DofLayout;
use crate::sim::discretization::Discretization;
use crate::sim::params::AssignParams;
use crate::sim::params::{SimParams, YarnRadii};
use crate::sim::terms::end_stops::end_stops;
use crate::topology::{Contact, ContactKind, Fabric, Node, PointRef, Vec3, Yarn, YarnPoint};

const MM: f64 = 1e-3;
/// Radii of yarn specs 0, 1, 2.
const RADII: [f64; 3] = [0.5 * MM, 1.0 * MM, 0.3 * MM];

/// Yarn 0 (spec 0) runs along x from 0 to 12 mm. Yarns 1 and 2 (specs 1
/// and 2) cross behind it at x = 5 and 6 mm, running along y from -5 to
/// 5 mm: two consecutive contacts on yarn 0 with the crossing yarns on the
/// same side, which the parallel-contact rule (docs/MODEL.md, "Parallel-yarn contact") keeps
/// apart.
fn two_crossings() -> Fabric {
    let v = |x: f64, y: f64, z: f64| Vec3::new(x * MM, y * MM, z * MM);
    let xs = [
        v(5.0, 0.0, 0.0),
        v(6.0, 0.0, 0.0),
        v(0.0, 0.0, 0.0),
        v(12.0, 0.0, 0.0),
        v(5.0, -5.0, -0.5),
        v(5.0, 5.0, -0.5),
        v(6.0, -5.0, -0.5),
        v(6.0, 5.0, -0.5),
    ];
    let point = |node: usize, u: f64, fixed_u: bool| YarnPoint {
        node,
        u: u * MM,
        fixed_u,
        eil: false,
    };
    let crossing = |spec: usize, start: usize| Yarn {
        layer: 0,
        spec,
        rest_length: 10.05 * MM,
        points: vec![
            point(start, 0.0, true),
            point(spec - 1, 5.025, false),
            point(start + 1, 10.05, true),
        ],
    };
    let contact = |node: usize, point: usize, yarn: usize| Contact {
        node,
        front: PointRef { yarn: 0, point },
        back: PointRef { yarn, point: 1 },
        kind: ContactKind::Float,
        partner: None,
    };
    Fabric {
        meta: meta(&[([0; 3], RADII[0]), ([0; 3], RADII[1]), ([0; 3], RADII[2])]),
        nodes: xs.iter().map(|&x| Node { x, pinned: false }).collect(),
        yarns: vec![
            Yarn {
                layer: 0,
                spec: 0,
                rest_length: 12.0 * MM,
                points: vec![
                    point(2, 0.0, true),
                    point(0, 5.0, false),
                    point(1, 6.0, false),
                    point(3, 12.0, true),
                ],
            },
            crossing(1, 4),
            crossing(2, 6),
        ],
        contacts: vec![contact(0, 1, 1), contact(1, 2, 2)],
        sim: None,
    }
}

fn params(radii: YarnRadii) -> SimParams {
    SimParams {
        radii,
        obstacles: vec![Shape::Plane {
            point: [0.0, 0.0, -0.01],
            normal: [0.0, 0.0, 1.0],
        }],
        ..SimParams::default()
    }
}

#[test]
fn uniform_is_the_default_and_pattern_reads_each_yarns_spec() {
    let f = two_crossings();
    let p = SimParams::default();
    assert_eq!(p.radii, YarnRadii::Uniform);
    assert_eq!(p.yarn_radii(&f), vec![p.rod.radius; 3]);
    assert_eq!(params(YarnRadii::Pattern).yarn_radii(&f), RADII.to_vec());
    // A spec without a usable radius falls back to `rod.radius`.
    let mut bad = two_crossings();
    bad.meta.yarns[2].radius = f64::NAN;
    let p = params(YarnRadii::Pattern);
    assert_eq!(p.yarn_radii(&bad), vec![RADII[0], RADII[1], p.rod.radius]);
}

#[test]
fn parallel_contact_ends_and_obstacles_use_the_radii_there() {
    let f = two_crossings();
    let l = DofLayout::new(&f);
    let q = l.gather(&f);
    let a = assign(&f, &l, &q, &rest_segment_lengths(&f), AssignParams::default());
    let disc = Discretization::new(&f, &l, &a);
    for (mode, expect) in [(YarnRadii::Pattern, RADII), (YarnRadii::Uniform, [0.75 * MM; 3])] {
        let p = params(mode);
        let radii = p.yarn_radii(&f);
        assert_eq!(radii, expect.to_vec());
        // Yarns 1 and 2 cross yarn 0 side by side: their centre lines stay
        // r1 + r2 apart along it.
        let (t, d) = parallel_terms(&disc, &q, &p, &radii);
        assert_eq!(t.len(), 1, "{mode:?}");
        let u = |yarn, point| l.u(PointRef { yarn, point }) as u32;
        assert_eq!(d[0], [u(0, 1), u(0, 2)]);
        assert!((t[0].diameter - (expect[1] + expect[2])).abs() < 1e-15, "{mode:?}");
        // Each yarn's tail stop is its own diameter (every tail here is
        // longer than two diameters).
        // `end_stops` lists each yarn's start, then its end, yarn by yarn.
        let (t, _) = end_stops(&disc, &p, &radii);
        assert_eq!(t.len(), 6);
        for (k, s) in t.iter().enumerate() {
            let yarn = k / 2;
            assert!((s.diameter - 2.0 * expect[yarn]).abs() < 1e-15, "{mode:?} yarn {yarn}");
        }
        // A node's clearance over an obstacle is its thickest yarn's radius:
        // the contact nodes carry yarn 0 and a crossing yarn.
        let (t, d) = obstacle_terms(&disc, &p, &radii);
        assert_eq!(t.len(), f.nodes.len());
        let clearance = |node: usize| t[d.iter().position(|x| x[0] == l.x(node) as u32).unwrap()].thickness;
        assert_eq!(clearance(0), expect[0].max(expect[1]));
        assert_eq!(clearance(1), expect[0].max(expect[2]));
        assert_eq!(clearance(2), expect[0]);
        assert_eq!(clearance(4), expect[1]);
        assert_eq!(clearance(6), expect[2]);
    }
}
