//! Which pair of features (vertex or interior) realises a distance.
//!
//! The classification follows ipc-toolkit's distance types so that every
//! type has a smooth closed form (point-point, point-line, line-line) and
//! the fixtures can compare types one to one. Two deliberate differences,
//! both for degenerate input that ipctk's docs call "should not happen":
//! - a zero-length edge is treated as a point and classified against the
//!   other edge (ipctk maps it to a point-*line* type even when the point
//!   projects outside the other segment, which underestimates the distance);
//! - "nearly parallel" is judged with a relative tolerance on
//!   `sin^2(angle)` ([`PARALLEL_SIN2`]) instead of ipctk's `1e-20`, because
//!   the line-line closed form loses accuracy in its derivatives (its 2x2
//!   system has determinant `|u x v|^2`) long before `1e-20`.

use nalgebra::Vector3;

/// Below this `|u x v|^2 / (|u|^2 |v|^2)` two edges count as parallel and
/// their distance is taken between an endpoint and the other edge. For
/// exactly parallel segments that is exact; for an angle `theta` below the
/// threshold the error is at most `theta^2 L^2 / (2 d)` (about `5e-11 L^2/d`),
/// far below any contact tolerance, and the line-line Hessian, whose size
/// grows like `1 / sin^2(theta)`, is never evaluated in the bad regime.
pub const PARALLEL_SIN2: f64 = 1e-10;

/// Closest features of a point and an edge `(e0, e1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PointEdgeType {
    /// The point is closest to `e0`.
    E0,
    /// The point is closest to `e1`.
    E1,
    /// The point is closest to the interior of the edge (point-line).
    Interior,
}

/// Closest features of edges A `(ea0, ea1)` and B `(eb0, eb1)`. `A0`
/// means vertex `ea0`, `A` the interior of edge A, and so on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EdgeEdgeType {
    A0B0,
    A0B1,
    A1B0,
    A1B1,
    /// Interior of A and vertex `eb0`.
    AB0,
    AB1,
    /// Vertex `ea0` and interior of B.
    A0B,
    A1B,
    /// Both interiors (line-line).
    AB,
}

impl PointEdgeType {
    /// ipc-toolkit's name of the type.
    pub fn ipctk_name(self) -> &'static str {
        match self {
            Self::E0 => "P_E0",
            Self::E1 => "P_E1",
            Self::Interior => "P_E",
        }
    }
}

impl EdgeEdgeType {
    /// ipc-toolkit's name of the type.
    pub fn ipctk_name(self) -> &'static str {
        match self {
            Self::A0B0 => "EA0_EB0",
            Self::A0B1 => "EA0_EB1",
            Self::A1B0 => "EA1_EB0",
            Self::A1B1 => "EA1_EB1",
            Self::AB0 => "EA_EB0",
            Self::AB1 => "EA_EB1",
            Self::A0B => "EA0_EB",
            Self::A1B => "EA1_EB",
            Self::AB => "EA_EB",
        }
    }

    /// The type where vertex `vertex_a` of A meets feature `pe` of B.
    fn vertex_a(vertex_a: usize, pe: PointEdgeType) -> Self {
        match (vertex_a, pe) {
            (0, PointEdgeType::E0) => Self::A0B0,
            (0, PointEdgeType::E1) => Self::A0B1,
            (0, PointEdgeType::Interior) => Self::A0B,
            (_, PointEdgeType::E0) => Self::A1B0,
            (_, PointEdgeType::E1) => Self::A1B1,
            (_, PointEdgeType::Interior) => Self::A1B,
        }
    }

    /// The type where vertex `vertex_b` of B meets feature `pe` of A.
    fn vertex_b(vertex_b: usize, pe: PointEdgeType) -> Self {
        match (vertex_b, pe) {
            (0, PointEdgeType::E0) => Self::A0B0,
            (0, PointEdgeType::E1) => Self::A1B0,
            (0, PointEdgeType::Interior) => Self::AB0,
            (_, PointEdgeType::E0) => Self::A0B1,
            (_, PointEdgeType::E1) => Self::A1B1,
            (_, PointEdgeType::Interior) => Self::AB1,
        }
    }
}

/// Classifies a point against an edge by the clamped projection parameter.
pub fn point_edge_type(p: &Vector3<f64>, e0: &Vector3<f64>, e1: &Vector3<f64>) -> PointEdgeType {
    let e = e1 - e0;
    let len2 = e.norm_squared();
    if len2 == 0.0 {
        return PointEdgeType::E0;
    }
    let t = e.dot(&(p - e0)) / len2;
    if t <= 0.0 {
        PointEdgeType::E0
    } else if t >= 1.0 {
        PointEdgeType::E1
    } else {
        PointEdgeType::Interior
    }
}

fn point_edge_sq(p: &Vector3<f64>, e0: &Vector3<f64>, e1: &Vector3<f64>) -> f64 {
    let e = e1 - e0;
    let len2 = e.norm_squared();
    let t = if len2 > 0.0 {
        (e.dot(&(p - e0)) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - e0 - e * t).norm_squared()
}

/// For (nearly) parallel edges: the closest of the four endpoint-to-edge pairs.
pub fn edge_edge_parallel_type(
    ea0: &Vector3<f64>,
    ea1: &Vector3<f64>,
    eb0: &Vector3<f64>,
    eb1: &Vector3<f64>,
) -> EdgeEdgeType {
    // B's endpoints first: with exact ties this picks the same type as ipctk.
    let candidates = [
        (
            point_edge_sq(eb0, ea0, ea1),
            EdgeEdgeType::vertex_b(0, point_edge_type(eb0, ea0, ea1)),
        ),
        (
            point_edge_sq(eb1, ea0, ea1),
            EdgeEdgeType::vertex_b(1, point_edge_type(eb1, ea0, ea1)),
        ),
        (
            point_edge_sq(ea0, eb0, eb1),
            EdgeEdgeType::vertex_a(0, point_edge_type(ea0, eb0, eb1)),
        ),
        (
            point_edge_sq(ea1, eb0, eb1),
            EdgeEdgeType::vertex_a(1, point_edge_type(ea1, eb0, eb1)),
        ),
    ];
    // First minimum wins: a deterministic choice among ties, whose distances agree.
    let mut best = candidates[0];
    for c in &candidates[1..] {
        if c.0 < best.0 {
            best = *c;
        }
    }
    best.1
}

/// Classifies two edges: the clamped closest-point parameters of the two
/// supporting lines (Lagrange-identity forms, accurate for small angles),
/// with a parallel fallback and zero-length edges treated as points.
pub fn edge_edge_type(ea0: &Vector3<f64>, ea1: &Vector3<f64>, eb0: &Vector3<f64>, eb1: &Vector3<f64>) -> EdgeEdgeType {
    let u = ea1 - ea0;
    let v = eb1 - eb0;
    let w = ea0 - eb0;
    let a = u.norm_squared();
    let c = v.norm_squared();
    if a == 0.0 && c == 0.0 {
        return EdgeEdgeType::A0B0;
    }
    if a == 0.0 {
        return EdgeEdgeType::vertex_a(0, point_edge_type(ea0, eb0, eb1));
    }
    if c == 0.0 {
        return EdgeEdgeType::vertex_b(0, point_edge_type(eb0, ea0, ea1));
    }
    let n = u.cross(&v);
    let det = n.norm_squared();
    if det < PARALLEL_SIN2 * a * c {
        return edge_edge_parallel_type(ea0, ea1, eb0, eb1);
    }
    let b = u.dot(&v);
    let d = u.dot(&w);
    let e = v.dot(&w);
    // Line parameters s = s_num / det on A and t = t_num / det on B.
    let s_num = n.dot(&v.cross(&w));
    // Clamp s first; t is then the best parameter on B for that s.
    let (a_side, t_num, t_den) = if s_num <= 0.0 {
        (Some(0), e, c)
    } else if s_num >= det {
        (Some(1), e + b, c)
    } else {
        (None, n.dot(&u.cross(&w)), det)
    };
    // If t leaves [0, 1], clamp it and re-project that vertex of B onto A.
    let b_vertex = if t_num <= 0.0 {
        Some((0, -d))
    } else if t_num >= t_den {
        Some((1, b - d))
    } else {
        None
    };
    match (b_vertex, a_side) {
        (Some((vb, s_on_a)), _) => {
            let pe = if s_on_a <= 0.0 {
                PointEdgeType::E0
            } else if s_on_a >= a {
                PointEdgeType::E1
            } else {
                PointEdgeType::Interior
            };
            EdgeEdgeType::vertex_b(vb, pe)
        }
        (None, Some(va)) => EdgeEdgeType::vertex_a(va, PointEdgeType::Interior),
        (None, None) => EdgeEdgeType::AB,
    }
}
