//! Projection of a local Hessian onto the positive semi-definite cone.
//!
//! Newton needs a descent direction; a stencil's exact Hessian can be
//! indefinite (bending past straight, a stretched spring's transverse modes,
//! barriers). Clamping each stencil's negative eigenvalues to zero keeps the
//! assembled matrix PSD at the cost of a slightly worse model. A Cholesky
//! test lets the many stencils that are already PSD skip the
//! eigen-decomposition; the others go through nalgebra's
//! [`SymmetricEigen`], with the cyclic Jacobi [`sym_eigen`] as the fallback
//! where it does not converge (non-finite input) and as an independent
//! check in tests.
use nalgebra::{DMatrix, SMatrix, SymmetricEigen};

/// Symmetric eigen-decomposition by cyclic Jacobi: returns (eigenvalues, eigenvectors as columns).
pub fn sym_eigen<const N: usize>(m: &SMatrix<f64, N, N>) -> ([f64; N], SMatrix<f64, N, N>) {
    let mut a = (m + m.transpose()) * 0.5;
    let mut v = SMatrix::<f64, N, N>::identity();
    let scale = a.norm().max(f64::MIN_POSITIVE);
    for _sweep in 0..60 {
        let mut off = 0.0;
        for p in 0..N {
            for q in p + 1..N {
                off += a[(p, q)] * a[(p, q)];
            }
        }
        if off.sqrt() <= 1e-15 * scale {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                let apq = a[(p, q)];
                if apq.abs() <= 1e-300 {
                    continue;
                }
                let theta = (a[(q, q)] - a[(p, p)]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..N {
                    let akp = a[(k, p)];
                    let akq = a[(k, q)];
                    a[(k, p)] = c * akp - s * akq;
                    a[(k, q)] = s * akp + c * akq;
                }
                for k in 0..N {
                    let apk = a[(p, k)];
                    let aqk = a[(q, k)];
                    a[(p, k)] = c * apk - s * aqk;
                    a[(q, k)] = s * apk + c * aqk;
                }
                for k in 0..N {
                    let vkp = v[(k, p)];
                    let vkq = v[(k, q)];
                    v[(k, p)] = c * vkp - s * vkq;
                    v[(k, q)] = s * vkp + c * vkq;
                }
            }
        }
    }
    let mut ev = [0.0; N];
    for (i, e) in ev.iter_mut().enumerate() {
        *e = a[(i, i)];
    }
    (ev, v)
}

/// True when `m + shift I` has a Cholesky factor, `shift` a tiny fraction
/// of the diagonal: `m` is then PSD up to rounding. Costs `N^3/6` flops,
/// against hundreds of Jacobi rotations, and most stencils near
/// equilibrium pass it, so the eigen-decomposition only runs for the
/// genuinely indefinite ones.
fn is_numerically_psd<const N: usize>(m: &SMatrix<f64, N, N>) -> bool {
    let diag_max = (0..N).fold(0.0f64, |a, i| a.max(m[(i, i)].abs()));
    if diag_max == 0.0 {
        return m.iter().all(|&v| v == 0.0);
    }
    let shift = 1e-12 * diag_max;
    let mut l = SMatrix::<f64, N, N>::zeros();
    for j in 0..N {
        let mut d = m[(j, j)] + shift;
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        l[(j, j)] = d;
        for i in j + 1..N {
            let mut s = 0.5 * (m[(i, j)] + m[(j, i)]);
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = s / d;
        }
    }
    true
}

/// Returns the nearest PSD matrix (negative eigenvalues clamped to zero).
/// A matrix that is already PSD up to a relative `1e-12` comes back
/// symmetrised but otherwise unchanged.
pub fn project_psd<const N: usize>(m: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    let sym = symmetrised(m);
    if is_numerically_psd(m) {
        return sym;
    }
    project_indefinite(m, sym)
}

/// The projection of `m`, whose symmetric part is `sym`, once the PSD test
/// has failed.
fn project_indefinite<const N: usize>(m: &SMatrix<f64, N, N>, sym: SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    let (ev, v) = eigen(m, &sym);
    clamped(sym, &ev, &v)
}

fn symmetrised<const N: usize>(m: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    (m + m.transpose()) * 0.5
}

/// Eigenvalues and eigenvectors (as columns) of `sym`, the symmetric part
/// of `m`: nalgebra's [`SymmetricEigen`], or the capped Jacobi sweeps of
/// `m` where that does not converge (non-finite entries).
///
/// `SymmetricEigen` needs a dimension it can subtract 1 from, which a
/// generic const `N` is not; the stencil sizes are therefore matched to
/// their fixed-size type (stack storage), and any other size goes through
/// a heap copy.
fn eigen<const N: usize>(m: &SMatrix<f64, N, N>, sym: &SMatrix<f64, N, N>) -> ([f64; N], [[f64; N]; N]) {
    macro_rules! fixed_sizes {
        ($($n:literal),*) => {
            match N {
                $($n => SymmetricEigen::try_new(SMatrix::<f64, $n, $n>::from_fn(|i, j| sym[(i, j)]), f64::EPSILON, 100 * N)
                    .map(|se| unpack(se.eigenvalues.as_slice(), |i, j| se.eigenvectors[(i, j)])),)*
                _ => SymmetricEigen::try_new(DMatrix::from_fn(N, N, |i, j| sym[(i, j)]), f64::EPSILON, 100 * N)
                    .map(|se| unpack(se.eigenvalues.as_slice(), |i, j| se.eigenvectors[(i, j)])),
            }
        };
    }
    fixed_sizes!(2, 3, 4, 6, 8, 9, 12, 18).unwrap_or_else(|| {
        let (ev, v) = sym_eigen(m);
        (ev, v.data.0)
    })
}

/// Eigenvalues and column-major eigenvectors as arrays.
fn unpack<const N: usize>(values: &[f64], vectors: impl Fn(usize, usize) -> f64) -> ([f64; N], [[f64; N]; N]) {
    (
        std::array::from_fn(|i| values[i]),
        std::array::from_fn(|j| std::array::from_fn(|i| vectors(i, j))),
    )
}

/// `sum_i max(e_i, 0) v_i v_i^T` from eigenpairs (vectors as columns), or
/// `sym` itself when no eigenvalue is negative. Formed on the lower
/// triangle and mirrored, so the result is exactly symmetric.
fn clamped<const N: usize>(sym: SMatrix<f64, N, N>, ev: &[f64; N], v: &[[f64; N]; N]) -> SMatrix<f64, N, N> {
    if ev.iter().all(|&e| e >= 0.0) {
        return sym;
    }
    let mut out = [[0.0; N]; N];
    for (e, c) in ev.iter().zip(v) {
        if *e > 0.0 {
            for s in 0..N {
                for r in s..N {
                    out[s][r] += c[r] * c[s] * e;
                }
            }
        }
    }
    for s in 1..N {
        let (left, right) = out.split_at_mut(s);
        for (r, col) in left.iter().enumerate() {
            right[0][r] = col[s];
        }
    }
    SMatrix::from_data(nalgebra::ArrayStorage(out))
}

/// PSD projection of a translation-invariant stencil's Hessian, done in
/// the reduced space of differences, where it is `(N-R)^3` times cheaper
/// and loses nothing.
///
/// The energy must depend on the local vector only through the differences
/// `r_k = x[kept[k]] - x[anchor[k]]` (a rod stencil is unchanged when all
/// its nodes translate, or all its `u` shift together). Then the Hessian in
/// `r` is exactly the `kept x kept` block of the full one, the full one is
/// `J^T H_r J` with `J` the difference map, and projecting `H_r` gives a
/// PSD full matrix (`J^T P J` is PSD whenever `P` is). The null space the
/// translation invariance creates is exact, not clamped.
pub fn project_psd_reduced<const N: usize, const R: usize>(
    h: &SMatrix<f64, N, N>,
    kept: &[usize; R],
    anchor: &[usize; R],
) -> SMatrix<f64, N, N> {
    project_psd_block(&SMatrix::from_fn(|k, l| h[(kept[k], kept[l])]), kept, anchor)
}

/// [`project_psd_reduced`] from the `kept x kept` block of the Hessian
/// alone (`block[(k, l)] = h[(kept[k], kept[l])]`), for a stencil that
/// computes only that block.
pub fn project_psd_block<const N: usize, const R: usize>(
    block: &SMatrix<f64, R, R>,
    kept: &[usize; R],
    anchor: &[usize; R],
) -> SMatrix<f64, N, N> {
    expand(&project_psd(&symmetrized(block)), kept, anchor)
}

fn symmetrized<const R: usize>(b: &SMatrix<f64, R, R>) -> SMatrix<f64, R, R> {
    SMatrix::from_fn(|k, l| 0.5 * (b[(k, l)] + b[(l, k)]))
}

/// `J^T P J` for the difference map `J`.
fn expand<const N: usize, const R: usize>(
    p: &SMatrix<f64, R, R>,
    kept: &[usize; R],
    anchor: &[usize; R],
) -> SMatrix<f64, N, N> {
    let mut out = SMatrix::<f64, N, N>::zeros();
    for k in 0..R {
        for l in 0..R {
            let v = p[(k, l)];
            out[(kept[k], kept[l])] += v;
            out[(anchor[k], kept[l])] -= v;
            out[(kept[k], anchor[l])] -= v;
            out[(anchor[k], anchor[l])] += v;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    #[test]
    fn reconstructs_and_clamps() {
        let m = Matrix3::new(2.0, 1.0, 0.0, 1.0, -3.0, 0.5, 0.0, 0.5, 1.0);
        let (ev, v) = sym_eigen(&m);
        let d = Matrix3::from_diagonal(&nalgebra::Vector3::from(ev));
        assert!((v * d * v.transpose() - m).norm() < 1e-12);
        let p = project_psd(&m);
        let (evp, _) = sym_eigen(&p);
        assert!(evp.iter().all(|&e| e > -1e-12));
        // Compare to nalgebra's own eigen-solver: the projection keeps positive modes.
        let se = m.symmetric_eigen();
        let mut expect = Matrix3::zeros();
        for i in 0..3 {
            if se.eigenvalues[i] > 0.0 {
                let c = se.eigenvectors.column(i);
                expect += c * c.transpose() * se.eigenvalues[i];
            }
        }
        assert!((p - expect).norm() < 1e-10);
    }

    #[test]
    fn psd_shortcut_keeps_singular_psd_and_catches_small_negative_modes() {
        let v = nalgebra::Vector3::new(1.0, -2.0, 0.5);
        let rank_one = v * v.transpose();
        assert!(is_numerically_psd(&rank_one));
        assert!((project_psd(&rank_one) - rank_one).norm() < 1e-14);
        assert!(is_numerically_psd(&Matrix3::zeros()));
        // A negative mode 1e-6 of the scale is not rounding: it must be clamped.
        let u = nalgebra::Vector3::new(0.0, 0.6, 0.8);
        let m = Matrix3::identity() - u * u.transpose() * (1.0 + 1e-6);
        assert!(!is_numerically_psd(&m));
        let (ev, _) = sym_eigen(&project_psd(&m));
        assert!(ev.iter().all(|&e| e > -1e-14));
    }

    #[test]
    fn reduced_projection_matches_full_projection_for_invariant_energies() {
        // E(a, b) = f(b - a) with f indefinite: the full Hessian is
        // [[F, -F], [-F, F]], whose projection is [[P, -P], [-P, P]].
        let f = Matrix3::new(2.0, 1.0, 0.0, 1.0, -3.0, 0.5, 0.0, 0.5, 1.0);
        let mut h = nalgebra::SMatrix::<f64, 6, 6>::zeros();
        for i in 0..3 {
            for j in 0..3 {
                h[(i, j)] = f[(i, j)];
                h[(i + 3, j + 3)] = f[(i, j)];
                h[(i, j + 3)] = -f[(i, j)];
                h[(i + 3, j)] = -f[(i, j)];
            }
        }
        let reduced = project_psd_reduced(&h, &[3, 4, 5], &[0, 1, 2]);
        assert!((reduced - project_psd(&h)).norm() < 1e-10);
    }

    /// Jacobi reference projection.
    fn jacobi_projection<const N: usize>(m: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
        let (ev, v) = sym_eigen(m);
        let mut out = SMatrix::<f64, N, N>::zeros();
        for (i, &e) in ev.iter().enumerate() {
            if e > 0.0 {
                out += v.column(i) * v.column(i).transpose() * e;
            }
        }
        out
    }

    fn check_against_jacobi<const N: usize>(seed: u64) {
        // Deterministic pseudo-random symmetric matrix, indefinite in general,
        // with a spread of scales like a stencil Hessian (stiff and soft rows).
        let mut state = seed;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut m = SMatrix::<f64, N, N>::zeros();
        for i in 0..N {
            for j in 0..=i {
                let v = next() * if i % 3 == 0 { 1e4 } else { 1.0 };
                m[(i, j)] = v;
                m[(j, i)] = v;
            }
        }
        let p = project_psd(&m);
        let r = jacobi_projection(&m);
        assert!((p - r).norm() <= 1e-9 * m.norm(), "N = {N}: {:e}", (p - r).norm());
        let (ev, _) = sym_eigen(&p);
        assert!(ev.iter().all(|&e| e >= -1e-9 * m.norm()));
    }

    #[test]
    fn qr_projection_agrees_with_jacobi_at_stencil_sizes() {
        for seed in 1..20 {
            check_against_jacobi::<4>(seed);
            check_against_jacobi::<9>(seed);
            check_against_jacobi::<12>(seed);
            check_against_jacobi::<18>(seed);
        }
    }

    /// Asserts what a projection must give: a symmetric PSD matrix that
    /// keeps every eigenpair of `m` with a positive eigenvalue (so it is
    /// `m` itself when `m` is PSD), within `tol` of `|m|`.
    fn assert_projection<const N: usize>(m: &SMatrix<f64, N, N>, tol: f64, what: &str) {
        let p = project_psd(m);
        let scale = m.norm().max(f64::MIN_POSITIVE);
        assert!(p.iter().all(|v| v.is_finite()), "{what}: non-finite projection");
        assert!((p - p.transpose()).norm() == 0.0, "{what}: not symmetric");
        let (ev, v) = sym_eigen(m);
        let (evp, _) = sym_eigen(&p);
        assert!(evp.iter().all(|&e| e >= -tol * scale), "{what}: {evp:?}");
        let mut want = SMatrix::<f64, N, N>::zeros();
        for (i, &e) in ev.iter().enumerate() {
            if e > 0.0 {
                want += v.column(i) * v.column(i).transpose() * e;
            }
        }
        assert!(
            (p - want).norm() <= tol * scale,
            "{what}: off by {:e}",
            (p - want).norm() / scale
        );
        if ev.iter().all(|&e| e >= 0.0) {
            assert!((p - m).norm() <= tol * scale, "{what}: a PSD matrix moved");
        }
    }

    /// Symmetric matrices that stress an eigen-solver: repeated, zero and
    /// rank-one spectra, decoupled blocks, and extreme scales.
    fn degenerate<const N: usize>() -> Vec<(&'static str, SMatrix<f64, N, N>)> {
        let v = SMatrix::<f64, N, 1>::from_fn(|i, _| (i as f64 + 1.0) * if i % 2 == 0 { 1.0 } else { -0.5 });
        vec![
            ("zero", SMatrix::zeros()),
            ("identity", SMatrix::identity()),
            (
                "diagonal with repeats",
                SMatrix::from_fn(|i, j| if i == j { [2.0, -1.0, 2.0, 0.0][i % 4] } else { 0.0 }),
            ),
            ("rank one", v * v.transpose()),
            ("negative rank one", -(v * v.transpose())),
            (
                "zero first column",
                SMatrix::from_fn(|i, j| {
                    if i * j == 0 {
                        0.0
                    } else {
                        1.0 / (1.0 + (i + j) as f64) - 0.3
                    }
                }),
            ),
            (
                "decoupled blocks",
                SMatrix::from_fn(|i, j| match ((i < 2) == (j < 2), i == j) {
                    (false, _) => 0.0,
                    (true, true) => 3.0 - 2.0 * i as f64,
                    (true, false) => 0.5,
                }),
            ),
            (
                "tiny",
                SMatrix::from_fn(|i, j| 1e-150 * (1.0 + (i * j) as f64) * if i == j { -1.0 } else { 1.0 }),
            ),
            ("huge", SMatrix::from_fn(|i, j| 1e150 / (1.0 + (i + j) as f64))),
        ]
    }

    #[test]
    fn projections_are_psd_and_keep_the_positive_modes() {
        fn at<const N: usize>(rng: &mut crate::rod::testutil::Rng) {
            for (what, m) in degenerate::<N>() {
                assert_projection(&m, 1e-12, what);
            }
            for k in 0..100 {
                let a = SMatrix::<f64, N, N>::from_fn(|_, _| rng.range(-1.0, 1.0));
                let m = a + a.transpose();
                assert_projection(&m, 1e-12, "random");
                // PSD inputs come back as they are.
                assert_projection(&(a * a.transpose()), 1e-12, "random PSD");
                // Scaled rows, like a stencil's stiff and soft unknowns.
                let d = SMatrix::<f64, N, N>::from_fn(|i, j| if i == j { [1e3, 1.0, 1e-2][(i + k) % 3] } else { 0.0 });
                assert_projection(&(d * m * d), 1e-11, "badly scaled");
            }
        }
        let mut rng = crate::rod::testutil::Rng::new(5);
        at::<2>(&mut rng);
        at::<3>(&mut rng);
        at::<8>(&mut rng);
        at::<9>(&mut rng);
        at::<12>(&mut rng);
        at::<18>(&mut rng);
    }

    #[test]
    fn bending_blocks_from_straight_to_folded_project_to_psd() {
        use crate::energy::Stencil;
        use crate::rod::bending::Bending;
        let b = Bending::with_rest_angle(1e-6, 0.2);
        let mut rng = crate::rod::testutil::Rng::new(7);
        for k in 0..500 {
            // Turning angles from 1e-6 to pi - 1e-6 rad, edges of 0.1 to 2 mm.
            let theta = 1e-6 + k as f64 / 499.0 * (std::f64::consts::PI - 2e-6);
            let (l1, l2) = (1e-3 * rng.range(1.05, 2.05), 1e-3 * rng.range(1.05, 2.05));
            let mut q = nalgebra::SVector::<f64, 12>::zeros();
            q[4] = l1;
            q[8] = l1 + l2 * theta.cos();
            q[9] = l2 * theta.sin();
            q[10] = 1e-4 * rng.range(0.0, 1.0);
            q[7] = 1e-3 * rng.range(1.5, 2.5);
            q[11] = 3e-3 * rng.range(1.5, 2.5);
            let h = b.hessian(&q);
            const KEPT: [usize; 8] = [4, 5, 6, 7, 8, 9, 10, 11];
            let block = SMatrix::<f64, 8, 8>::from_fn(|i, j| 0.5 * (h[(KEPT[i], KEPT[j])] + h[(KEPT[j], KEPT[i])]));
            assert_projection(&block, 1e-10, &format!("bend at {theta:.3e} rad"));
        }
    }

    #[test]
    fn a_non_finite_hessian_comes_back_without_hanging() {
        let mut m = Matrix3::new(2.0, 1.0, 0.0, 1.0, -3.0, 0.5, 0.0, 0.5, 1.0);
        m[(1, 1)] = f64::NAN;
        let p = project_psd(&m);
        assert_eq!(p.shape(), (3, 3));
    }
}
