//! Builders for small hand-made fabrics used by the physics tests.
#![allow(dead_code)]

use knitsim::pattern::{Construction, Gauge, Meta, YarnSpec};
use knitsim::topology::{Fabric, Node, Vec3, Yarn, YarnPoint};

pub fn meta(radius: f64) -> Meta {
    Meta {
        name: "test".into(),
        gauge: Gauge {
            stitches_per_10cm: 20.0,
            rows_per_10cm: 28.0,
        },
        yarns: vec![YarnSpec {
            name: "a".into(),
            color: [180, 40, 40],
            radius,
            material: None,
        }],
        construction: Construction::Flat,
        width: 1,
        height: 1,
        looseness: 1.0,
    }
}

/// A yarn of rest length `len` with `n` segments, points at `pos(s)` for
/// `s` in [0, 1]; all `u` fixed (a plain Lagrangian rod).
pub fn yarn_fabric(len: f64, n: usize, pos: impl Fn(f64) -> Vec3) -> Fabric {
    let nodes: Vec<Node> = (0..=n)
        .map(|i| Node {
            x: pos(i as f64 / n as f64),
            pinned: false,
        })
        .collect();
    let points = (0..=n)
        .map(|i| YarnPoint {
            node: i,
            u: len * i as f64 / n as f64,
            fixed_u: true,
            eil: false,
        })
        .collect();
    Fabric {
        meta: meta(5e-4),
        nodes,
        yarns: vec![Yarn {
            spec: 0,
            rest_length: len,
            points,
        }],
        contacts: vec![],
        sim: None,
    }
}
