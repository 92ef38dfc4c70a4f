//! Small synthetic fabrics for the unit tests of the writers.

use crate::pattern::{Construction, Gauge, Meta, YarnSpec};
use crate::topology::{Contact, ContactKind, Fabric, Node, PointRef, Vec3, Yarn, YarnPoint};

pub(crate) fn meta(specs: &[([u8; 3], f64)]) -> Meta {
    Meta {
        name: "fixture".into(),
        gauge: Gauge {
            stitches_per_10cm: 20.0,
            rows_per_10cm: 28.0,
        },
        yarns: specs
            .iter()
            .enumerate()
            .map(|(i, &(color, radius))| YarnSpec {
                name: format!("yarn {i}"),
                color,
                radius,
                material: None,
            })
            .collect(),
        construction: Construction::Flat,
        width: 1,
        height: 1,
        looseness: 1.0,
    }
}

/// Appends a yarn through `xs` with fresh Lagrangian nodes; `u` is the
/// polyline arc length.
pub(crate) fn push_yarn(fabric: &mut Fabric, spec: usize, xs: &[Vec3]) -> usize {
    let mut u = 0.0;
    let mut points = Vec::new();
    for (i, x) in xs.iter().enumerate() {
        if i > 0 {
            u += (x - xs[i - 1]).norm();
        }
        fabric.nodes.push(Node { x: *x, pinned: false });
        points.push(YarnPoint {
            node: fabric.nodes.len() - 1,
            u,
            fixed_u: i == 0 || i + 1 == xs.len(),
            eil: false,
        });
    }
    fabric.yarns.push(Yarn {
        layer: 0,
        spec,
        rest_length: u,
        points,
    });
    fabric.yarns.len() - 1
}

/// Two straight yarns crossing at one shared contact node, plus an EIL point
/// on the first: kinds Lagrangian, EoL and EIL all occur.
///
/// Yarn 0 (red): (0,0,0) -> EIL at (1,0,0) -> contact (2,0,0) -> (4,0,0), mm.
/// Yarn 1 (blue): (2,-2,0) -> contact -> (2,2,0).
pub(crate) fn crossing() -> Fabric {
    let mm = 1e-3;
    let mut f = Fabric {
        meta: meta(&[([200, 30, 30], 0.4 * mm), ([30, 60, 200], 0.3 * mm)]),
        nodes: vec![],
        yarns: vec![],
        contacts: vec![],
        sim: None,
    };
    let p = |x: f64, y: f64| Vec3::new(x * mm, y * mm, 0.0);
    push_yarn(&mut f, 0, &[p(0.0, 0.0), p(1.0, 0.0), p(2.0, 0.0), p(4.0, 0.0)]);
    push_yarn(&mut f, 1, &[p(2.0, -2.0), p(2.0, 0.0), p(2.0, 2.0)]);
    // Share yarn 0's node 2 with yarn 1's middle point.
    let shared = f.yarns[0].points[2].node;
    f.yarns[1].points[1].node = shared;
    f.yarns[0].points[1].eil = true;
    f.contacts.push(Contact {
        node: shared,
        front: PointRef { yarn: 0, point: 2 },
        back: PointRef { yarn: 1, point: 1 },
        kind: ContactKind::Float,
        partner: None,
    });
    f
}
