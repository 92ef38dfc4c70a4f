use super::*;
use crate::contact::test_util::Rng;
use crate::energy::fd::check_derivatives;
use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector};

/// Squared (or unsquared) edge-edge distance as a stencil, type frozen at
/// the evaluation point so finite differences see one smooth branch.
struct EdgeEdgeSq(bool);

/// Unsquared distance on one fixed type (for configurations where the type
/// flips within a finite-difference step).
struct EdgeEdgeFrozen(EdgeEdgeType);
impl Stencil<12> for EdgeEdgeFrozen {
    fn value(&self, x: &SVector<f64, 12>) -> f64 {
        edge_edge_derivs_typed(x, self.0).sqrt().value
    }
    fn gradient(&self, x: &SVector<f64, 12>) -> SVector<f64, 12> {
        edge_edge_derivs_typed(x, self.0).sqrt().gradient
    }
    fn hessian(&self, x: &SVector<f64, 12>) -> SMatrix<f64, 12, 12> {
        edge_edge_derivs_typed(x, self.0).sqrt().hessian
    }
}

impl Stencil<12> for EdgeEdgeSq {
    fn value(&self, x: &SVector<f64, 12>) -> f64 {
        self.eval(x).value
    }
    fn gradient(&self, x: &SVector<f64, 12>) -> SVector<f64, 12> {
        self.eval(x).gradient
    }
    fn hessian(&self, x: &SVector<f64, 12>) -> SMatrix<f64, 12, 12> {
        self.eval(x).hessian
    }
}
impl EdgeEdgeSq {
    fn eval(&self, x: &SVector<f64, 12>) -> DistanceDerivs<12> {
        let d = edge_edge_derivs(x);
        if self.0 {
            d.sqrt()
        } else {
            d
        }
    }
}

struct PointEdgeSq;
impl Stencil<9> for PointEdgeSq {
    fn value(&self, x: &SVector<f64, 9>) -> f64 {
        point_edge_derivs(x).value
    }
    fn gradient(&self, x: &SVector<f64, 9>) -> SVector<f64, 9> {
        point_edge_derivs(x).gradient
    }
    fn hessian(&self, x: &SVector<f64, 9>) -> SMatrix<f64, 9, 9> {
        point_edge_derivs(x).hessian
    }
}

fn ee(p: [[f64; 3]; 4]) -> SVector<f64, 12> {
    SVector::<f64, 12>::from_iterator(p.iter().flatten().copied())
}

fn ty(x: &SVector<f64, 12>) -> EdgeEdgeType {
    let [a, b, c, d]: [V3; 4] = points(x);
    edge_edge_type(&a, &b, &c, &d)
}

/// Reference segment distance by a different route: the interior critical
/// point of the two lines if it lies inside both segments, else the best of
/// the four endpoint-to-segment distances (which covers every boundary case).
fn brute_force_sq(x: &SVector<f64, 12>) -> f64 {
    let [a0, a1, b0, b1]: [V3; 4] = points(x);
    let mut best = [
        point_edge_distance_sq(&a0, &b0, &b1),
        point_edge_distance_sq(&a1, &b0, &b1),
        point_edge_distance_sq(&b0, &a0, &a1),
        point_edge_distance_sq(&b1, &a0, &a1),
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min);
    let (u, v, w) = (a1 - a0, b1 - b0, a0 - b0);
    let m = nalgebra::Matrix2::new(u.dot(&u), -u.dot(&v), -u.dot(&v), v.dot(&v));
    if let Some(inv) = m.try_inverse() {
        let st = inv * nalgebra::Vector2::new(-u.dot(&w), v.dot(&w));
        if (0.0..=1.0).contains(&st[0]) && (0.0..=1.0).contains(&st[1]) {
            best = best.min((w + u * st[0] - v * st[1]).norm_squared());
        }
    }
    best
}

#[test]
fn every_type_has_exact_derivatives() {
    use EdgeEdgeType::*;
    let cases = [
        (
            AB,
            [[0.0, 0.0, 0.0], [1.0, 0.1, 0.0], [0.4, -0.5, 0.3], [0.6, 0.5, 0.25]],
        ),
        (
            A0B0,
            [[0.0, 0.0, 0.0], [-1.0, 0.1, 0.0], [0.1, 0.2, 0.3], [1.0, 0.5, 0.4]],
        ),
        (
            A1B1,
            [[-1.0, 0.1, 0.0], [0.0, 0.0, 0.0], [1.0, 0.5, 0.4], [0.1, 0.2, 0.3]],
        ),
        (
            A0B,
            [[0.0, 0.2, 0.3], [-1.0, 0.3, 0.5], [-0.5, 0.0, 0.0], [0.5, 0.1, 0.0]],
        ),
        (
            AB1,
            [[-0.5, 0.0, 0.0], [0.5, 0.1, 0.0], [0.9, 0.3, 0.4], [0.0, 0.2, 0.3]],
        ),
        (
            A1B0,
            [[-1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.2, 0.3, 0.1], [1.0, 0.0, 0.6]],
        ),
    ];
    for (expect, p) in cases {
        let x = ee(p);
        assert_eq!(ty(&x), expect, "{p:?}");
        assert!((edge_edge_derivs(&x).value - brute_force_sq(&x)).abs() < 1e-14);
        check_derivatives(&EdgeEdgeSq(false), &x, 1e-6, 1e-6);
        check_derivatives(&EdgeEdgeSq(true), &x, 1e-6, 1e-6);
    }
}

#[test]
fn crossing_nearly_touching_edges() {
    // Perpendicular edges crossing 1e-2 apart: line-line type. The FD step
    // must stay well below d (the third derivative grows like 1 / d^2).
    let x = ee([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.2, -1.0, 1e-2], [0.2, 1.0, 1e-2]]);
    assert_eq!(ty(&x), EdgeEdgeType::AB);
    let d = edge_edge_derivs(&x).sqrt();
    assert!((d.value - 1e-2).abs() < 1e-16);
    check_derivatives(&EdgeEdgeSq(true), &x, 1e-7, 1e-5);
}

#[test]
fn nearly_parallel_edges() {
    // sin^2 = 1e-6: still line-line, large but exact Hessian.
    // B crosses A's direction half-way (in the xy projection), so the
    // closest points are interior to both.
    let tilt = 1e-3;
    let x = ee([
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.1, -tilt / 2.0, 0.3],
        [1.1, tilt / 2.0, 0.3],
    ]);
    assert_eq!(ty(&x), EdgeEdgeType::AB);
    check_derivatives(&EdgeEdgeSq(true), &x, 1e-7, 1e-5);
    assert!((edge_edge_derivs(&x).value - brute_force_sq(&x)).abs() < 1e-13);
    // sin^2 = 1e-14: parallel fallback to an endpoint-edge pair; the error is
    // second order in the angle (< 1e-14 here). The distance is not smooth
    // at this scale (four near-tied candidates), so the chosen closed form
    // is checked with its type frozen.
    let tilt = 1e-7;
    let x = ee([
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.1, -tilt / 2.0, 0.3],
        [1.1, tilt / 2.0, 0.3],
    ]);
    let t = ty(&x);
    assert_ne!(t, EdgeEdgeType::AB);
    assert!((edge_edge_derivs(&x).value - brute_force_sq(&x)).abs() < 1e-14);
    check_derivatives(&EdgeEdgeFrozen(t), &x, 1e-7, 1e-5);
    // Exactly parallel and overlapping: distance 0.3 whatever pair is picked.
    let x = ee([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.1, 0.0, 0.3], [1.1, 0.0, 0.3]]);
    assert!((edge_edge_derivs(&x).value.sqrt() - 0.3).abs() < 1e-15);
    // Antiparallel, not overlapping: closest endpoints.
    let x = ee([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.3], [2.0, 0.0, 0.3]]);
    assert_eq!(ty(&x), EdgeEdgeType::A1B1);
}

#[test]
fn coincident_endpoints_and_degenerate_edges() {
    // Touching at a shared location: squared distance 0 with zero gradient
    // (a kink of the min over features, so no finite differences here).
    let x = ee([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.5, 1.0, 0.2]]);
    let d = edge_edge_derivs(&x);
    assert_eq!(d.value, 0.0);
    assert!(d.gradient.norm() == 0.0);
    // Nearly coincident endpoints (1e-3 apart): point-point, smooth.
    let x = ee([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.001, 0.0, 0.0], [1.5, 1.0, 0.2]]);
    assert_eq!(ty(&x), EdgeEdgeType::A1B0);
    check_derivatives(&EdgeEdgeSq(true), &x, 1e-8, 1e-5);
    // Zero-length A projecting inside B: point-line.
    let x = ee([[0.3, 0.5, 0.0], [0.3, 0.5, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
    assert_eq!(ty(&x), EdgeEdgeType::A0B);
    assert!((edge_edge_derivs(&x).value - 0.25).abs() < 1e-15);
    // Zero-length A beyond the end of B: point-point, the true distance.
    let x = ee([[1.3, 0.4, 0.0], [1.3, 0.4, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
    assert_eq!(ty(&x), EdgeEdgeType::A0B1);
    assert!((edge_edge_derivs(&x).value - 0.25).abs() < 1e-15);
    // Both degenerate.
    let x = ee([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]);
    assert_eq!(ty(&x), EdgeEdgeType::A0B0);
    assert_eq!(edge_edge_derivs(&x).value, 1.0);
    check_derivatives(&EdgeEdgeFrozen(EdgeEdgeType::A0B0), &x, 1e-7, 1e-6);
}

#[test]
fn random_pairs_match_brute_force() {
    let mut rng = Rng(0x9e3779b97f4a7c15);
    for _ in 0..2000 {
        let x = SVector::<f64, 12>::from_fn(|_, _| rng.next() * 2.0 - 1.0);
        let d = edge_edge_derivs(&x).value;
        let r = brute_force_sq(&x);
        assert!((d - r).abs() <= 1e-12 * r.max(1e-3), "{d} vs {r} at {x:?}");
    }
}

#[test]
fn point_edge_types_and_derivatives() {
    let cases = [
        (PointEdgeType::Interior, [0.4, 0.3, 0.2]),
        (PointEdgeType::E0, [-0.4, 0.3, 0.2]),
        (PointEdgeType::E1, [1.4, -0.3, 0.2]),
    ];
    for (expect, p) in cases {
        let x = SVector::<f64, 9>::from_iterator(p.into_iter().chain([0.0, 0.0, 0.0, 1.0, 0.1, 0.0]));
        let [pp, e0, e1]: [V3; 3] = points(&x);
        assert_eq!(point_edge_type(&pp, &e0, &e1), expect);
        check_derivatives(&PointEdgeSq, &x, 1e-6, 1e-6);
    }
    let pp = point_point_derivs(&SVector::<f64, 6>::from_column_slice(&[1.0, 2.0, 3.0, 1.0, 2.0, 5.0]));
    assert_eq!(pp.value, 4.0);
    assert_eq!(pp.gradient[2], -4.0);
    assert_eq!(pp.hessian[(2, 5)], -2.0);
}
