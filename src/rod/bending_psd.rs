//! PSD projection of the bending Hessian, split by the bend's mirror symmetry.
//!
//! Why: the general projection (`energy::psd::project_psd_reduced`, an 8x8
//! symmetric eigen-decomposition per node triple) was about 20% of all CPU
//! time of a 40x40 linen-stitch relaxation (`perf record`, session 19), more
//! than any other single piece but the sparse factorization.
//!
//! Bending reads its local vector only through `r1 = x1 - x0`,
//! `r2 = x2 - x0` and `D = u2 - u0` (`u1` does not enter). Reflecting `r1`
//! and `r2` through the plane they span changes no angle, so the energy is
//! even in their out-of-plane components. Write the reduced Hessian in an
//! orthonormal frame `(p, q, n)` of that plane: the in-plane coordinates
//! `(p.r1, q.r1, p.r2, q.r2, D)` and the out-of-plane ones
//! `(n.r1, n.r2)` do not couple (a mixed second derivative of an even
//! function vanishes on its mirror plane). The frame change is orthogonal,
//! so the eigenvalues of the reduced Hessian are those of a 5x5 and a 2x2
//! block, and clamping them block by block is *exactly* the general
//! projection, in exact arithmetic: the same matrix for Newton, computed
//! with a 5x5 eigen-decomposition and a closed-form 2x2.
//!
//! Near a straight or folded bend the plane is ill-defined; wherever the
//! coupling entries are not rounding-small the general projection runs
//! instead ([`project_bending`] returns `None`).

use crate::energy::psd::{expand_reduced, project_psd5};
use nalgebra::{Matrix5, SMatrix, Vector3};

/// Reduced coordinates in the local vector `[x0, u0, x1, u1, x2, u2]`:
/// `r1` (x1), `r2` (x2), `D` (u2), each relative to its anchor (x0, u0).
const KEPT: [usize; 7] = [4, 5, 6, 8, 9, 10, 11];
const ANCHOR: [usize; 7] = [0, 1, 2, 0, 1, 2, 3];

/// Coupling between the two blocks, relative to the largest entry, above
/// which the frame is not trusted (a near-straight or folded bend).
const COUPLING_TOL: f64 = 1e-11;

/// The PSD projection of the bending Hessian `h` at edges `r1 = x1 - x0`,
/// `r2 = x2 - x0`, or `None` where the bend plane is not well defined.
pub fn project_bending(h: &SMatrix<f64, 12, 12>, r1: &Vector3<f64>, r2: &Vector3<f64>) -> Option<SMatrix<f64, 12, 12>> {
    let normal = r1.cross(r2);
    let (l1, nl) = (r1.norm(), normal.norm());
    if !(nl > 0.0 && l1 > 0.0 && nl.is_finite()) {
        return None;
    }
    let p = r1 / l1;
    let n = normal / nl;
    let q = n.cross(&p);
    // Rows of the frame change `y = F z`, z = (r1, r2, D):
    // y = (p.r1, q.r1, p.r2, q.r2, D | n.r1, n.r2).
    let mut f = SMatrix::<f64, 7, 7>::zeros();
    for k in 0..3 {
        f[(0, k)] = p[k];
        f[(1, k)] = q[k];
        f[(2, 3 + k)] = p[k];
        f[(3, 3 + k)] = q[k];
        f[(5, k)] = n[k];
        f[(6, 3 + k)] = n[k];
    }
    f[(4, 6)] = 1.0;
    let hr = SMatrix::<f64, 7, 7>::from_fn(|a, b| 0.5 * (h[(KEPT[a], KEPT[b])] + h[(KEPT[b], KEPT[a])]));
    let hy = f * hr * f.transpose();
    let scale = hy.amax();
    if !scale.is_finite() {
        return None;
    }
    if scale == 0.0 {
        return Some(SMatrix::zeros());
    }
    let coupling = (0..5)
        .flat_map(|i| (5..7).map(move |j| (i, j)))
        .fold(0.0f64, |m, (i, j)| m.max(hy[(i, j)].abs()));
    if coupling > COUPLING_TOL * scale {
        return None;
    }
    let in_plane = project_psd5(&Matrix5::from_fn(|i, j| hy[(i, j)]));
    let (a, b, c) = project_psd2(hy[(5, 5)], 0.5 * (hy[(5, 6)] + hy[(6, 5)]), hy[(6, 6)]);
    let mut py = SMatrix::<f64, 7, 7>::zeros();
    py.fixed_view_mut::<5, 5>(0, 0).copy_from(&in_plane);
    py[(5, 5)] = a;
    py[(5, 6)] = b;
    py[(6, 5)] = b;
    py[(6, 6)] = c;
    Some(expand_reduced(&(f.transpose() * py * f), &KEPT, &ANCHOR))
}

/// The PSD projection of the symmetric 2x2 `[[a, b], [b, c]]`, in closed form.
fn project_psd2(a: f64, b: f64, c: f64) -> (f64, f64, f64) {
    let mean = 0.5 * (a + c);
    let radius = (0.5 * (a - c)).hypot(b);
    let (hi, lo) = (mean + radius, mean - radius);
    if lo >= 0.0 {
        return (a, b, c);
    }
    if hi <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    // Eigenvector of `hi`: (hi - c, b) or (b, hi - a), whichever is longer
    // (both solve the eigen equation; the longer one has no cancellation).
    let (v0, v1) = if a >= c { (hi - c, b) } else { (b, hi - a) };
    let s = hi / (v0 * v0 + v1 * v1);
    (s * v0 * v0, s * v0 * v1, s * v1 * v1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::psd::{project_psd_reduced, sym_eigen};
    use crate::energy::Stencil;
    use crate::rod::bending::Bending;
    use crate::rod::testutil::{put3, Rng};
    use nalgebra::{Matrix2, SVector};
    use std::f64::consts::{FRAC_PI_2, PI};

    fn bent(rng: &mut Rng, theta: f64, l1: f64, l2: f64, du: f64) -> SVector<f64, 12> {
        let t = rng.vec3(1.0).normalize();
        let n = rng.orthogonal_unit(&t);
        let x1 = rng.vec3(0.1);
        let x0 = x1 - t * l1;
        let x2 = x1 + (t * theta.cos() + n * theta.sin()) * l2;
        let mut q = SVector::<f64, 12>::zeros();
        let u0 = rng.range(-1.0, 1.0);
        for (k, (x, u)) in [(x0, u0), (x1, u0 + du * l1), (x2, u0 + du * (l1 + l2))]
            .iter()
            .enumerate()
        {
            put3(&mut q, 4 * k, x);
            q[4 * k + 3] = *u;
        }
        q
    }

    fn edges(q: &SVector<f64, 12>) -> (Vector3<f64>, Vector3<f64>) {
        let x0 = q.fixed_rows::<3>(0);
        (q.fixed_rows::<3>(4) - x0, q.fixed_rows::<3>(8) - x0)
    }

    #[test]
    fn the_blocks_give_the_general_projection() {
        // Bends from nearly straight to nearly folded, stretched or slack
        // (du), with and without a rest angle (which makes them indefinite).
        let mut rng = Rng::new(19);
        let stencils = [
            Bending::new(2.0),
            Bending::with_rest_angle(2.0, 0.7),
            Bending::new(1e-7),
        ];
        let (mut split, mut indefinite) = (0, 0);
        for k in 0..600 {
            let theta = [1e-3, 0.05, 0.4, 1.2, FRAC_PI_2, 2.5, 3.1, PI - 1e-3][k % 8];
            let (l1, l2) = (rng.range(1e-3, 2.0), rng.range(1e-3, 2.0));
            let du = rng.range(0.3, 2.0);
            let q = bent(&mut rng, theta, l1, l2, du);
            let (r1, r2) = edges(&q);
            for b in &stencils {
                let h = b.hessian(&q);
                let general = project_psd_reduced(&h, &[4, 5, 6, 7, 8, 9, 10, 11], &[0, 1, 2, 3, 0, 1, 2, 3]);
                let Some(blocks) = project_bending(&h, &r1, &r2) else {
                    continue;
                };
                split += 1;
                indefinite += usize::from((general - h).norm() > 1e-9 * h.norm());
                assert!(
                    (blocks - general).norm() <= 1e-9 * h.norm(),
                    "theta {theta}: {:e} of {:e}",
                    (blocks - general).norm(),
                    h.norm()
                );
            }
        }
        // The fast path is the common one, and it is exercised on
        // Hessians the projection really changes.
        assert!(split >= 1500, "{split}");
        assert!(indefinite >= 300, "{indefinite}");
    }

    #[test]
    fn an_undefined_plane_falls_back() {
        let b = Bending::new(2.0);
        let mut rng = Rng::new(3);
        // Exactly straight, exactly folded, coincident nodes: no plane.
        for theta in [0.0, PI] {
            let q = bent(&mut rng, theta, 1.0, 1.0, 1.0);
            let (r1, _) = edges(&q);
            // The exact mirror image of r1 has no normal at all.
            let r2 = if theta == 0.0 { r1 * 2.0 } else { Vector3::zeros() };
            assert!(project_bending(&b.hessian(&q), &r1, &r2).is_none());
        }
        let q = bent(&mut rng, 1.0, 1.0, 1.0, 1.0);
        assert!(project_bending(&b.hessian(&q), &Vector3::zeros(), &Vector3::x()).is_none());
        // A Hessian with a non-finite entry is left to the general path.
        let mut h = b.hessian(&q);
        h[(5, 5)] = f64::NAN;
        let (r1, r2) = edges(&q);
        assert!(project_bending(&h, &r1, &r2).is_none());
    }

    #[test]
    fn the_closed_form_2x2_matches_an_eigen_decomposition() {
        let mut rng = Rng::new(7);
        for k in 0..400 {
            let s = [1.0, 1e-8, 1e8][k % 3];
            let (a, b, c) = (
                rng.range(-1.0, 1.0) * s,
                rng.range(-1.0, 1.0) * s,
                rng.range(-1.0, 1.0) * s,
            );
            let b = if k % 5 == 0 { 0.0 } else { b };
            let (pa, pb, pc) = project_psd2(a, b, c);
            let (ev, v) = sym_eigen(&Matrix2::new(a, b, b, c));
            let mut expect = Matrix2::zeros();
            for (i, e) in ev.iter().enumerate() {
                expect += v.column(i) * v.column(i).transpose() * e.max(0.0);
            }
            let got = Matrix2::new(pa, pb, pb, pc);
            assert!((got - expect).norm() <= 1e-12 * s, "{a} {b} {c}: {got} vs {expect}");
        }
    }
}
