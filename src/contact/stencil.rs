//! Edge-edge contact energies as 12-coordinate stencils on
//! `[x0, x1 (edge A), x2, x3 (edge B)]`.
//!
//! Both are a scalar function of the segment distance `d(x)`, so by the chain
//! rule `grad = f'(d) grad d` and `hess = f''(d) grad d grad d^T + f'(d) hess d`
//! with the exact distance derivatives of [`super::distance`]. The Hessian is
//! returned unprojected (it is indefinite: `f' < 0` times the distance's own
//! curvature); the assembler projects it to PSD.
//!
//! - [`EdgeEdgeBarrier`]: `kappa b(d, a, eta)` (docs/MODEL.md, "Thickness contact") with the
//!   per-stencil `(a, eta)` chosen by the filter.
//! - [`EdgeEdgePenalty`]: `k/2 (h - d)^2` for `d < h`, the stiff penalty of
//!   the older yarn models (penalties for external contact); it
//!   lets yarns interpenetrate under load, which is what the comparison shows.

use super::barrier::BarrierShape;
use super::distance::{edge_edge_derivs, edge_edge_distance_sq, points, DistanceDerivs};
use crate::energy::Stencil;
use nalgebra::{SMatrix, SVector, Vector3};

/// Composes a scalar `f(d)` (value, f', f'') with the segment distance.
fn compose(dist: &DistanceDerivs<12>, f1: f64, f2: f64) -> (SVector<f64, 12>, SMatrix<f64, 12, 12>) {
    let g = dist.gradient * f1;
    let h = dist.gradient * dist.gradient.transpose() * f2 + dist.hessian * f1;
    (g, h)
}

fn distance(x: &SVector<f64, 12>) -> f64 {
    let [a0, a1, b0, b1]: [Vector3<f64>; 4] = points(x);
    edge_edge_distance_sq(&a0, &a1, &b0, &b1).sqrt()
}

/// `kappa * b(d, a, eta)` on an edge-edge pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeEdgeBarrier {
    pub stiffness: f64,
    pub shape: BarrierShape,
}

impl EdgeEdgeBarrier {
    /// Gap floor used for derivatives inside the core (`d <= eta`), where
    /// the energy is infinite: CCD keeps iterates out, but if a caller
    /// evaluates there anyway it gets a huge finite push outwards, not NaN.
    fn clamped(&self, d: f64) -> f64 {
        let floor = self.shape.core + 1e-12 * (self.shape.activation - self.shape.core);
        d.max(floor)
    }
}

impl Stencil<12> for EdgeEdgeBarrier {
    fn value(&self, x: &SVector<f64, 12>) -> f64 {
        let d = distance(x);
        if d >= self.shape.activation {
            return 0.0;
        }
        self.stiffness * self.shape.value(d)
    }

    fn gradient(&self, x: &SVector<f64, 12>) -> SVector<f64, 12> {
        self.derivs(x).0
    }

    fn hessian(&self, x: &SVector<f64, 12>) -> SMatrix<f64, 12, 12> {
        self.derivs(x).1
    }
}

impl EdgeEdgeBarrier {
    /// Gradient and Hessian together (the distance is evaluated once).
    pub fn derivs(&self, x: &SVector<f64, 12>) -> (SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        let dsq = edge_edge_derivs(x);
        if dsq.value >= self.shape.activation * self.shape.activation || dsq.value <= 0.0 {
            return (SVector::zeros(), SMatrix::zeros());
        }
        let dist = dsq.sqrt();
        let d = self.clamped(dist.value);
        compose(
            &dist,
            self.stiffness * self.shape.d1(d),
            self.stiffness * self.shape.d2(d),
        )
    }
}

/// `k/2 (h - d)^2` for `d < h` on an edge-edge pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeEdgePenalty {
    pub stiffness: f64,
    pub thickness: f64,
}

impl EdgeEdgePenalty {
    pub fn derivs(&self, x: &SVector<f64, 12>) -> (SVector<f64, 12>, SMatrix<f64, 12, 12>) {
        let dsq = edge_edge_derivs(x);
        if dsq.value >= self.thickness * self.thickness || dsq.value <= 0.0 {
            return (SVector::zeros(), SMatrix::zeros());
        }
        let dist = dsq.sqrt();
        compose(&dist, -self.stiffness * (self.thickness - dist.value), self.stiffness)
    }
}

impl Stencil<12> for EdgeEdgePenalty {
    fn value(&self, x: &SVector<f64, 12>) -> f64 {
        let overlap = (self.thickness - distance(x)).max(0.0);
        0.5 * self.stiffness * overlap * overlap
    }

    fn gradient(&self, x: &SVector<f64, 12>) -> SVector<f64, 12> {
        self.derivs(x).0
    }

    fn hessian(&self, x: &SVector<f64, 12>) -> SMatrix<f64, 12, 12> {
        self.derivs(x).1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::barrier::barrier;
    use crate::energy::fd::check_derivatives;

    fn ee(p: [[f64; 3]; 4]) -> SVector<f64, 12> {
        SVector::<f64, 12>::from_iterator(p.iter().flatten().copied())
    }

    /// Configurations of the main distance types, at distance ~0.2-0.3.
    fn configs() -> Vec<SVector<f64, 12>> {
        vec![
            ee([[0.0, 0.0, 0.0], [1.0, 0.1, 0.0], [0.4, -0.5, 0.2], [0.6, 0.5, 0.25]]),
            ee([[0.0, 0.0, 0.0], [-1.0, 0.1, 0.0], [0.1, 0.1, 0.2], [1.0, 0.5, 0.4]]),
            ee([[0.0, 0.1, 0.2], [-1.0, 0.3, 0.5], [-0.5, 0.0, 0.0], [0.5, 0.1, 0.0]]),
            // Near-parallel neighbours, like two yarns lying side by side.
            ee([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.1, -1e-3, 0.25], [1.1, 1e-3, 0.25]]),
        ]
    }

    #[test]
    fn barrier_stencil_exact_derivatives() {
        for core in [0.0, 0.1] {
            let s = EdgeEdgeBarrier {
                stiffness: 7.0,
                shape: BarrierShape::biphasic(0.3, core),
            };
            for x in configs() {
                let d = distance(&x);
                assert!(d < 0.3 && d > core, "config outside the active range: {d}");
                assert!((s.value(&x) - 7.0 * barrier(d - core, 0.3 - core)).abs() < 1e-14);
                check_derivatives(&s, &x, 1e-7, 1e-6);
            }
        }
    }

    #[test]
    fn barrier_stencil_inactive_and_inside_core() {
        let s = EdgeEdgeBarrier {
            stiffness: 1.0,
            shape: BarrierShape::biphasic(0.1, 0.05),
        };
        let far = ee([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, -1.0, 0.2], [0.5, 1.0, 0.2]]);
        assert_eq!(s.value(&far), 0.0);
        assert_eq!(s.gradient(&far), SVector::<f64, 12>::zeros());
        let inside = ee([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, -1.0, 0.01], [0.5, 1.0, 0.01]]);
        assert_eq!(s.value(&inside), f64::INFINITY);
        let g = s.gradient(&inside);
        assert!(g.iter().all(|v| v.is_finite()));
        // The push separates the edges: edge B (z > 0) is pushed up.
        assert!(g[8] < 0.0 && g[11] < 0.0);
    }

    #[test]
    fn penalty_stencil_exact_derivatives() {
        let s = EdgeEdgePenalty {
            stiffness: 1e3,
            thickness: 0.35,
        };
        for x in configs() {
            let d = distance(&x);
            assert!((s.value(&x) - 500.0 * (0.35 - d).powi(2)).abs() < 1e-12);
            check_derivatives(&s, &x, 1e-7, 1e-6);
        }
    }
}
