//! A PSD Hessian of the bending energy in closed form, without an
//! eigen-decomposition.
//!
//! Why: the general projection (`energy::psd::project_psd_reduced`, an 8x8
//! symmetric eigen-decomposition per node triple) was 28 of the 60 ms that
//! one Newton assembly of a 40x40 linen stitch took on two threads
//! (`examples/assembly_costs.rs`, docs/RELAX.md, "Bending Hessian"): more than
//! every other term together. Almost every bend is indefinite, so the
//! cheap "already PSD" test in front of it rarely helps.
//!
//! The energy is `V = phi(theta, D)` with `phi = k (theta - rest)^2 / D`,
//! `theta` the turning angle between the edges `e1 = x1 - x0`, `e2 = x2 - x1`
//! and `D = u2 - u0`. Its Hessian splits in two:
//!
//! ```text
//! hess V = J^T hess(phi) J + phi_theta hess(theta)
//! ```
//!
//! - `phi` is the perspective of a convex quadratic, jointly convex in
//!   `(theta, D)` for `D > 0`, and its Hessian is rank one:
//!   `J^T hess(phi) J = (2k/D) w w^T` with `w = grad(theta) - (theta - rest)/D grad(D)`.
//!   PSD as it stands (the Gauss-Newton part).
//! - `hess(theta)` has a closed-form eigensystem. In the bend plane
//!   `theta = phi2 - phi1`, the difference of the edges' polar angles, so
//!   its in-plane block is that of two polar angles: on `e1`,
//!   `(t1 m1^T + m1 t1^T) / l1^2` (eigenvalues `+-1/l1^2`, eigenvectors
//!   `(t1 +- m1)/sqrt 2`), likewise on `e2`, where `t` is an edge's unit
//!   tangent and `m` the in-plane unit normal towards the other edge. The
//!   bend is even in the edges' out-of-plane components (a mirror through
//!   the plane changes no angle), so in-plane and out-of-plane do not mix,
//!   and out of the plane, from `cos theta` to second order,
//!   `[[cot/l1^2, -1/(sin l1 l2)], [-1/(sin l1 l2), cot/l2^2]]`: a 2x2 of
//!   negative determinant, one eigenvalue of each sign.
//!
//! The PSD Hessian used is the Gauss-Newton part plus the positive
//! eigenpairs of `phi_theta hess(theta)`: four rank-one terms, a few
//! hundred flops. It is not the nearest PSD matrix to `hess V` (which the
//! eigen-decomposition gave) but another PSD model of it, one that never
//! softens a direction below the true Hessian (it exceeds `hess V` by
//! exactly the clamped negative part), the split that analytic-eigensystem
//! bending solvers use. A test rebuilds the exact Hessian from all six
//! eigenpairs and the Gauss-Newton term, against the stencil's own
//! (finite-difference checked) Hessian.
//!
//! Opt-in (`SimParams::bending_hessian = split`, `knitsim relax
//! --bending-hessian split`): a different PSD model is a different Newton
//! path. Measured (docs/RELAX.md, "Bending Hessian"), it makes an iteration 20 to
//! 30% cheaper and relaxations deeper and more repeatable, but float
//! patterns take two to three times as many iterations to the test, so
//! the default stays the eigen-decomposition.
//!
//! Where the bend plane is undefined (`sin theta` below [`MIN_SIN`], a
//! straight or folded bend), a zero edge or `D <= 0`, [`split`] returns
//! `None` and the stencil falls back to the general projection.

use nalgebra::{SMatrix, SVector, Vector3};

/// Below this `sin theta` the frame is not trusted (the general projection runs).
pub const MIN_SIN: f64 = 1e-6;

/// A rank-one term `a a^T` in the reduced coordinates `(e1, e2, D)`.
pub type Reduced = SVector<f64, 7>;

/// The pieces of the bending Hessian in `(e1, e2, D)`: the Gauss-Newton
/// vector `g` (`hess V = g g^T + sum lambda v v^T`) and the six eigenpairs
/// `(lambda, v)` of `phi_theta hess(theta)`, `v` unit. `None` where the
/// bend plane is undefined (see the module docs).
pub fn split(
    k: f64,
    rest: f64,
    e1: &Vector3<f64>,
    e2: &Vector3<f64>,
    d: f64,
) -> Option<(Reduced, [(f64, Reduced); 6])> {
    let (l1, l2) = (e1.norm(), e2.norm());
    if !(l1 > 0.0 && l2 > 0.0 && d > 0.0 && l1.is_finite() && l2.is_finite() && d.is_finite()) {
        return None;
    }
    let (t1, t2) = (e1 / l1, e2 / l2);
    let cross = t1.cross(&t2);
    let sin = cross.norm();
    if sin.is_nan() || sin < MIN_SIN {
        return None;
    }
    let cos = t1.dot(&t2);
    let theta = sin.atan2(cos);
    let n = cross / sin;
    // In-plane normals: m1 towards t2, m2 towards t1.
    let (m1, m2) = (n.cross(&t1), t2.cross(&n));
    let dev = theta - rest;
    let c = 2.0 * k * dev / d;
    let pack = |a: &Vector3<f64>, b: &Vector3<f64>, dd: f64| {
        let mut v = Reduced::zeros();
        v.fixed_rows_mut::<3>(0).copy_from(a);
        v.fixed_rows_mut::<3>(3).copy_from(b);
        v[6] = dd;
        v
    };
    let zero = Vector3::zeros();
    let gn = pack(&(-m1 / l1), &(-m2 / l2), -dev / d) * (2.0 * k / d).sqrt();
    let r = std::f64::consts::FRAC_1_SQRT_2;
    // c (t m^T + m t^T) / l^2 on one edge: c/l^2 along (t + m), -c/l^2 along (t - m).
    let plane1 = [
        (c / (l1 * l1), pack(&((t1 + m1) * r), &zero, 0.0)),
        (-c / (l1 * l1), pack(&((t1 - m1) * r), &zero, 0.0)),
    ];
    let plane2 = [
        (c / (l2 * l2), pack(&zero, &((t2 + m2) * r), 0.0)),
        (-c / (l2 * l2), pack(&zero, &((t2 - m2) * r), 0.0)),
    ];
    // Out of the plane: c [[cot/l1^2, -1/(sin l1 l2)], [., cot/l2^2]].
    let cot = cos / sin;
    let (a, b, cc) = (c * cot / (l1 * l1), -c / (sin * l1 * l2), c * cot / (l2 * l2));
    let [(hi, (p, q)), (lo, (p2, q2))] = eigen2(a, b, cc);
    let out = [
        (hi, pack(&(n * p), &(n * q), 0.0)),
        (lo, pack(&(n * p2), &(n * q2), 0.0)),
    ];
    let pairs = [plane1[0], plane1[1], plane2[0], plane2[1], out[0], out[1]];
    let finite = gn.iter().all(|v| v.is_finite())
        && pairs
            .iter()
            .all(|(l, v)| l.is_finite() && v.iter().all(|x| x.is_finite()));
    finite.then_some((gn, pairs))
}

/// Eigenpairs of the symmetric 2x2 `[[a, b], [b, c]]`, larger first, with
/// unit eigenvectors `(p, q)`.
fn eigen2(a: f64, b: f64, c: f64) -> [(f64, (f64, f64)); 2] {
    let mean = 0.5 * (a + c);
    let radius = (0.5 * (a - c)).hypot(b);
    let (hi, lo) = (mean + radius, mean - radius);
    // Eigenvector of `hi`: (hi - c, b) or (b, hi - a), whichever is longer
    // (both solve the eigen equation; the longer one has no cancellation).
    let (p, q) = if a >= c { (hi - c, b) } else { (b, hi - a) };
    let norm = p.hypot(q);
    let (p, q) = if norm > 0.0 { (p / norm, q / norm) } else { (1.0, 0.0) };
    [(hi, (p, q)), (lo, (-q, p))]
}

/// The 12-vector `S^T a` of a reduced vector: `e1 = x1 - x0`, `e2 = x2 -
/// x1`, `D = u2 - u0` on `[x0, u0, x1, u1, x2, u2]`.
fn expand(a: &Reduced) -> SVector<f64, 12> {
    let mut v = SVector::<f64, 12>::zeros();
    for k in 0..3 {
        v[k] = -a[k];
        v[4 + k] = a[k] - a[3 + k];
        v[8 + k] = a[3 + k];
    }
    v[3] = -a[6];
    v[11] = a[6];
    v
}

/// The PSD bending Hessian on `[x0, u0, x1, u1, x2, u2]` (module docs), or
/// `None` where [`split`] is.
pub fn projected_hessian(
    k: f64,
    rest: f64,
    e1: &Vector3<f64>,
    e2: &Vector3<f64>,
    d: f64,
) -> Option<SMatrix<f64, 12, 12>> {
    let (gn, pairs) = split(k, rest, e1, e2, d)?;
    let mut h = {
        let v = expand(&gn);
        v * v.transpose()
    };
    for (lambda, v) in pairs {
        if lambda > 0.0 {
            let v = expand(&(v * lambda.sqrt()));
            h += v * v.transpose();
        }
    }
    Some(h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::psd::sym_eigen;
    use crate::energy::Stencil;
    use crate::rod::bending::Bending;
    use crate::rod::testutil::{put3, Rng};
    use std::f64::consts::{FRAC_PI_2, PI};

    /// A bend of turning angle `theta` with edges `l1`, `l2` and material
    /// spacing `du` per metre, in a random orientation.
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

    fn parts(q: &SVector<f64, 12>) -> (Vector3<f64>, Vector3<f64>, f64) {
        let x = |k: usize| Vector3::new(q[4 * k], q[4 * k + 1], q[4 * k + 2]);
        (x(1) - x(0), x(2) - x(1), q[11] - q[3])
    }

    const ANGLES: [f64; 8] = [1e-4, 0.05, 0.4, 1.2, FRAC_PI_2, 2.5, 3.1, PI - 1e-4];

    #[test]
    fn the_pieces_rebuild_the_exact_hessian() {
        // Gauss-Newton term plus all six eigenpairs, negative ones too,
        // against the stencil's own Hessian (finite-difference checked in
        // `bending.rs`), from nearly straight to nearly folded, with and
        // without a rest angle, at a spread of edge lengths.
        let mut rng = Rng::new(16);
        let mut checked = 0;
        for i in 0..800 {
            let theta = ANGLES[i % ANGLES.len()];
            let (l1, l2) = (rng.range(1e-4, 2.0), rng.range(1e-4, 2.0));
            let du = rng.range(0.3, 2.0);
            let q = bent(&mut rng, theta, l1, l2, du);
            let (e1, e2, d) = parts(&q);
            for b in [Bending::new(2.0), Bending::with_rest_angle(1e-7, 0.7)] {
                let Some((gn, pairs)) = split(b.kb, b.rest_angle, &e1, &e2, d) else {
                    continue;
                };
                let mut h = expand(&gn) * expand(&gn).transpose();
                for (lambda, v) in pairs {
                    h += expand(&v) * expand(&v).transpose() * lambda;
                }
                let exact = b.hessian(&q);
                let err = (h - exact).norm();
                assert!(
                    err <= 1e-7 * exact.norm(),
                    "theta {theta}: {err:e} of {:e}",
                    exact.norm()
                );
                checked += 1;
            }
        }
        assert!(checked >= 1500, "{checked}");
    }

    #[test]
    fn the_eigenpairs_are_orthonormal_and_the_model_bounds_the_hessian() {
        let mut rng = Rng::new(5);
        for i in 0..400 {
            let theta = ANGLES[i % ANGLES.len()];
            let (l1, l2) = (rng.range(1e-3, 1.0), rng.range(1e-3, 1.0));
            let q = bent(&mut rng, theta, l1, l2, 1.0);
            let (e1, e2, d) = parts(&q);
            let b = Bending::with_rest_angle(1.0, [0.0, 0.3][i % 2]);
            let (_, pairs) = split(b.kb, b.rest_angle, &e1, &e2, d).expect("a defined plane");
            for (a, (_, u)) in pairs.iter().enumerate() {
                for (c, (_, v)) in pairs.iter().enumerate() {
                    let expect = if a == c { 1.0 } else { 0.0 };
                    assert!((u.dot(v) - expect).abs() < 1e-12, "pairs {a} {c}");
                }
            }
            // PSD, and above the exact Hessian by a PSD amount.
            let h = projected_hessian(b.kb, b.rest_angle, &e1, &e2, d).unwrap();
            let exact = b.hessian(&q);
            let scale = exact.norm();
            let (ev, _) = sym_eigen(&h);
            assert!(ev.iter().all(|&e| e >= -1e-10 * scale), "theta {theta}: {ev:?}");
            let (ev, _) = sym_eigen(&(h - exact));
            assert!(ev.iter().all(|&e| e >= -1e-10 * scale), "theta {theta}: {ev:?}");
        }
    }

    #[test]
    fn undefined_planes_and_degenerate_edges_give_none() {
        let mut rng = Rng::new(3);
        let q = bent(&mut rng, 0.0, 1.0, 1.0, 1.0);
        let (e1, e2, d) = parts(&q);
        assert!(split(1.0, 0.0, &e1, &e2, d).is_none(), "straight");
        assert!(split(1.0, 0.0, &e1, &(-e1), d).is_none(), "folded");
        assert!(split(1.0, 0.0, &Vector3::zeros(), &e2, d).is_none(), "zero edge");
        let q = bent(&mut rng, 1.0, 1.0, 1.0, 1.0);
        let (e1, e2, _) = parts(&q);
        assert!(split(1.0, 0.0, &e1, &e2, 0.0).is_none(), "D = 0");
        assert!(split(1.0, 0.0, &e1, &e2, f64::NAN).is_none(), "D NaN");
        assert!(split(1.0, 0.0, &e1, &e2, 1.0).is_some());
    }
}
