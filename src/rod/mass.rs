//! Mass matrix of an EoL segment (docs/MODEL.md, "Segment mass matrix").
//!
//! On a segment `a-b` with `s in [0, 1]`, a fixed material point moves with
//!
//! ```text
//! v(s) = (1-s) (xdot_a - w udot_a) + s (xdot_b - w udot_b),  w = (x_b - x_a) / (u_b - u_a)
//! ```
//!
//! (a node sliding forward in `u` at fixed `x` means material moving
//! backward along the segment). The kinetic energy
//! `T = 1/2 rho du integral_0^1 |v|^2 ds` is quadratic in
//! `qdot = (xdot_a, udot_a, xdot_b, udot_b)`. Writing `v = sum_i N_i(s) P qdot_i`
//! with `P = [I3 | -w]` (3x4) and the linear shape functions `N_i`, the
//! integral of `N_i N_j` is the familiar `[[1/3, 1/6], [1/6, 1/3]]`, so
//!
//! ```text
//! M_seg = rho du [[1/3, 1/6], [1/6, 1/3]] (x) P^T P,  P^T P = [[I3, -w], [-w^T, w.w]]
//! ```
//!
//! It is PSD with rank 6: a node's `(xdot, udot) = (w, 1) c` (sliding along
//! the segment's own direction at the material speed) moves no material.
//! The solver treats it as constant within a step (evaluated at the start)
//! and sums segments between consecutive non-EIL nodes only; EIL points carry
//! no mass.

use nalgebra::{Matrix4, SMatrix, SVector};

/// The 8x8 mass matrix on `(xdot_a, udot_a, xdot_b, udot_b)` for the local
/// vector `[x_a(3), u_a, x_b(3), u_b]` and linear density `rho` (kg/m).
pub fn segment_mass(rho: f64, q: &SVector<f64, 8>) -> SMatrix<f64, 8, 8> {
    let du = q[7] - q[3];
    let w = (q.fixed_rows::<3>(4) - q.fixed_rows::<3>(0)) / du;
    let mut p = Matrix4::<f64>::identity();
    p.fixed_view_mut::<3, 1>(0, 3).copy_from(&(-w));
    p.fixed_view_mut::<1, 3>(3, 0).copy_from(&(-w.transpose()));
    p[(3, 3)] = w.norm_squared();
    let shape = [[1.0 / 3.0, 1.0 / 6.0], [1.0 / 6.0, 1.0 / 3.0]];
    let mut m = SMatrix::<f64, 8, 8>::zeros();
    for (i, row) in shape.iter().enumerate() {
        for (j, &nij) in row.iter().enumerate() {
            m.fixed_view_mut::<4, 4>(4 * i, 4 * j)
                .copy_from(&(p * (rho * du * nij)));
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::psd::sym_eigen;
    use crate::rod::testutil::Rng;
    use nalgebra::Vector3;

    /// `1/2 rho du integral |v|^2` by composite Simpson (exact for the
    /// quadratic integrand, independent of the Kronecker algebra).
    fn kinetic_by_quadrature(rho: f64, q: &SVector<f64, 8>, qd: &SVector<f64, 8>) -> f64 {
        let du = q[7] - q[3];
        let w = (q.fixed_rows::<3>(4) - q.fixed_rows::<3>(0)) / du;
        let va: Vector3<f64> = qd.fixed_rows::<3>(0) - w * qd[3];
        let vb: Vector3<f64> = qd.fixed_rows::<3>(4) - w * qd[7];
        let n = 10;
        let mut sum = 0.0;
        for k in 0..=n {
            let s = k as f64 / n as f64;
            let weight = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += weight * (va * (1.0 - s) + vb * s).norm_squared();
        }
        0.5 * rho * du * sum / (3.0 * n as f64)
    }

    fn random_segment(rng: &mut Rng) -> SVector<f64, 8> {
        let mut q = rng.vector::<8>(1.0);
        q[7] = q[3] + rng.range(0.1, 2.0);
        q
    }

    #[test]
    fn kinetic_energy_matches_quadrature() {
        let mut rng = Rng::new(41);
        for _ in 0..50 {
            let q = random_segment(&mut rng);
            let qd = rng.vector::<8>(3.0);
            let m = segment_mass(0.7, &q);
            let t = 0.5 * qd.dot(&(m * qd));
            let tq = kinetic_by_quadrature(0.7, &q, &qd);
            assert!((t - tq).abs() <= 1e-12 * tq.max(1.0), "{t} vs {tq}");
        }
    }

    #[test]
    fn symmetric_psd_rank_six() {
        let mut rng = Rng::new(42);
        for _ in 0..20 {
            let m = segment_mass(0.7, &random_segment(&mut rng));
            assert!((m - m.transpose()).norm() < 1e-14);
            let (ev, _) = sym_eigen(&m);
            let scale = m.norm();
            assert!(ev.iter().all(|&e| e > -1e-12 * scale));
            assert_eq!(ev.iter().filter(|&&e| e > 1e-10 * scale).count(), 6);
        }
    }

    #[test]
    fn rigid_translation_carries_the_segment_mass() {
        let mut rng = Rng::new(43);
        let q = random_segment(&mut rng);
        let (rho, du) = (0.7, q[7] - q[3]);
        let m = segment_mass(rho, &q);
        let vel = Vector3::new(1.0, -2.0, 0.5);
        let mut qd = SVector::<f64, 8>::zeros();
        qd.fixed_rows_mut::<3>(0).copy_from(&vel);
        qd.fixed_rows_mut::<3>(4).copy_from(&vel);
        // T = 1/2 (rho du) |v|^2, and the momentum is rho du v split between the nodes.
        let t = 0.5 * qd.dot(&(m * qd));
        assert!((t - 0.5 * rho * du * vel.norm_squared()).abs() < 1e-12);
        let p = m * qd;
        let px = p.fixed_rows::<3>(0) + p.fixed_rows::<3>(4);
        assert!((px - vel * (rho * du)).norm() < 1e-12);
    }
}
