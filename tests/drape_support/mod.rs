//! The woven patch of the drape tests: yarns crossing at persistent EoL
//! contacts, whose implicit steps converge at millisecond time steps.
#![allow(dead_code)]

pub use crate::contact_support::common;
use knitsim::topology::{Contact, ContactKind, Fabric, Node, PointRef, Vec3};

/// Crossing pitch of the woven patch (m).
const PITCH: f64 = 2e-3;
/// Yarns per direction.
const N: usize = 5;

/// A woven patch in the plane `z = 0`: `N` yarns along x, whose material
/// slides through the crossings (free `u`), over `N` yarns along y with
/// fixed `u`, joined at `N x N` persistent EoL contacts; 1 mm tails past
/// the outer crossings. Yarn radius 0.25 mm.
pub fn woven_patch() -> Fabric {
    let mut f = common::empty_fabric(0.25e-3);
    let at = |i: usize| (i as f64 - (N - 1) as f64 / 2.0) * PITCH;
    let tail = (N - 1) as f64 / 2.0 * PITCH + 1e-3;
    for i in 0..N {
        for j in 0..N {
            f.nodes.push(Node {
                x: Vec3::new(at(i), at(j), 0.0),
                pinned: false,
            });
        }
    }
    let node = |i: usize, j: usize| i * N + j;
    let mut along_x = Vec::new();
    for j in 0..N {
        let mut pts = vec![Vec3::new(-tail, at(j), 0.0)];
        let mut on = vec![None];
        for i in 0..N {
            pts.push(Vec3::new(at(i), at(j), 0.0));
            on.push(Some(node(i, j)));
        }
        pts.push(Vec3::new(tail, at(j), 0.0));
        on.push(None);
        along_x.push(common::add_yarn(&mut f, &pts, &on));
    }
    for i in 0..N {
        let mut pts = vec![Vec3::new(at(i), -tail, 0.0)];
        let mut on = vec![None];
        for j in 0..N {
            pts.push(Vec3::new(at(i), at(j), 0.0));
            on.push(Some(node(i, j)));
        }
        pts.push(Vec3::new(at(i), tail, 0.0));
        on.push(None);
        let yarn = common::add_yarn(&mut f, &pts, &on);
        for p in &mut f.yarns[yarn].points {
            p.fixed_u = true;
        }
        for (j, &front) in along_x.iter().enumerate() {
            f.contacts.push(Contact {
                node: node(i, j),
                front: PointRef {
                    yarn: front,
                    point: 1 + i,
                },
                back: PointRef { yarn, point: 1 + j },
                kind: ContactKind::Float,
                partner: None,
            });
        }
    }
    f
}
