//! The port against nalgebra itself, bit for bit: random matrices at every
//! stencil size with rows of very different scales, the degenerate shapes
//! that take the rarer branches (zero columns, decoupled blocks, repeated
//! and zero eigenvalues), real bending Hessians, capped iteration counts,
//! and the interleaved pair against the single decomposition.

use super::*;
use crate::rod::bending::Bending;
use nalgebra::{DMatrix, SVector, SymmetricEigen};

fn nalgebra<const N: usize>(m: &[[f64; N]; N], max_niter: usize) -> Decomposition<N> {
    let d = DMatrix::from_fn(N, N, |i, j| m[j][i]);
    let se = SymmetricEigen::try_new(d, f64::EPSILON, max_niter)?;
    Some((
        std::array::from_fn(|i| se.eigenvalues[i]),
        std::array::from_fn(|j| std::array::from_fn(|i| se.eigenvectors[(i, j)])),
    ))
}

fn bits<const N: usize>(d: &Decomposition<N>) -> Option<Vec<u64>> {
    d.as_ref()
        .map(|(e, v)| e.iter().chain(v.iter().flatten()).map(|x| x.to_bits()).collect())
}

/// Asserts the port, single and paired with `other`, equals nalgebra.
fn assert_same<const N: usize>(m: &[[f64; N]; N], other: &[[f64; N]; N], max_niter: usize, what: &str) {
    let want = bits(&nalgebra(m, max_niter));
    assert_eq!(
        bits(&eigen(m, f64::EPSILON, max_niter)),
        want,
        "{what}: single, N = {N}"
    );
    let [first, _] = eigen_pair(m, other, f64::EPSILON, max_niter);
    assert_eq!(bits(&first), want, "{what}: first of a pair, N = {N}");
    let [_, second] = eigen_pair(other, m, f64::EPSILON, max_niter);
    assert_eq!(bits(&second), want, "{what}: second of a pair, N = {N}");
}

struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// Symmetric, indefinite in general; row/column scales from 1e-6 to 1e6
    /// as in a stencil Hessian with stiff and soft coordinates.
    fn symmetric<const N: usize>(&mut self) -> [[f64; N]; N] {
        let scale: [f64; N] = std::array::from_fn(|_| 10f64.powf(6.0 * self.next()));
        let mut m = [[0.0; N]; N];
        for j in 0..N {
            for i in j..N {
                let v = self.next() * (scale[i] * scale[j]).sqrt();
                m[j][i] = v;
                m[i][j] = v;
            }
        }
        m
    }
}

fn random_matrices_at<const N: usize>(rng: &mut Lcg, count: usize) {
    let mut other = rng.symmetric::<N>();
    for k in 0..count {
        let m = rng.symmetric::<N>();
        assert_same(&m, &other, 100 * N, &format!("random matrix {k}"));
        other = m;
    }
}

#[test]
fn random_matrices_match_nalgebra_at_every_stencil_size() {
    let mut rng = Lcg(17);
    random_matrices_at::<2>(&mut rng, 300);
    random_matrices_at::<3>(&mut rng, 300);
    random_matrices_at::<4>(&mut rng, 300);
    random_matrices_at::<5>(&mut rng, 300);
    random_matrices_at::<7>(&mut rng, 300);
    random_matrices_at::<8>(&mut rng, 600);
    random_matrices_at::<9>(&mut rng, 600);
    random_matrices_at::<12>(&mut rng, 200);
    random_matrices_at::<18>(&mut rng, 100);
}

fn degenerate<const N: usize>() -> Vec<(&'static str, [[f64; N]; N])> {
    let mut cases = Vec::new();
    cases.push(("zero", [[0.0; N]; N]));
    cases.push(("negative zeros", [[-0.0; N]; N]));
    cases.push(("identity", identity()));
    let mut d = [[0.0; N]; N];
    for (i, col) in d.iter_mut().enumerate() {
        col[i] = [2.0, -1.0, 2.0, 0.0][i % 4];
    }
    cases.push(("diagonal with repeats", d));
    let v: [f64; N] = std::array::from_fn(|i| (i as f64 + 1.0) * if i % 2 == 0 { 1.0 } else { -0.5 });
    cases.push((
        "rank one",
        std::array::from_fn(|j| std::array::from_fn(|i| v[i] * v[j])),
    ));
    // A zero first column: its Householder factor is zero (no reflection).
    let z: [[f64; N]; N] =
        std::array::from_fn(|j| std::array::from_fn(|i| if i * j == 0 { 0.0 } else { 1.0 / (1.0 + (i + j) as f64) }));
    cases.push(("zero first column", z));
    // Two decoupled blocks: the QR splits the problem and meets 2x2 blocks.
    let b: [[f64; N]; N] = std::array::from_fn(|j| {
        std::array::from_fn(|i| match ((i < 2) == (j < 2), i == j) {
            (false, _) => 0.0,
            (true, true) => 3.0 + i as f64,
            (true, false) => 0.5,
        })
    });
    cases.push(("decoupled blocks", b));
    let tiny: [[f64; N]; N] = std::array::from_fn(|j| std::array::from_fn(|i| 1e-300 * (1.0 + (i * j) as f64)));
    cases.push(("tiny", tiny));
    let huge: [[f64; N]; N] = std::array::from_fn(|j| std::array::from_fn(|i| 1e300 / (1.0 + (i + j) as f64)));
    cases.push(("huge", huge));
    cases
}

fn degenerate_at<const N: usize>() {
    let cases = degenerate::<N>();
    for (k, (what, m)) in cases.iter().enumerate() {
        let other = &cases[(k + 1) % cases.len()].1;
        assert_same(m, other, 100 * N, what);
    }
}

#[test]
fn degenerate_matrices_match_nalgebra() {
    degenerate_at::<2>();
    degenerate_at::<3>();
    degenerate_at::<8>();
    degenerate_at::<9>();
    degenerate_at::<18>();
}

/// The reduced 8x8 block the bending projection decomposes.
fn bending_block(b: &Bending, q: &SVector<f64, 12>) -> [[f64; 8]; 8] {
    const KEPT: [usize; 8] = [4, 5, 6, 7, 8, 9, 10, 11];
    let (_, _, h) = b.evaluate(q);
    std::array::from_fn(|l| std::array::from_fn(|k| 0.5 * (h[(KEPT[k], KEPT[l])] + h[(KEPT[l], KEPT[k])])))
}

#[test]
fn bending_hessians_match_nalgebra_from_straight_to_folded() {
    let mut rng = Lcg(5);
    let b = Bending::with_rest_angle(1e-6, 0.2);
    let mut other = [[0.0; 8]; 8];
    for k in 0..2000 {
        // Turning angles from 1e-6 to pi - 1e-6 rad, edges of 0.1 to 2 mm.
        let t = k as f64 / 1999.0;
        let theta = 1e-6 + t * (std::f64::consts::PI - 2e-6);
        let (l1, l2) = (1e-3 * (1.05 + rng.next()), 1e-3 * (1.05 + rng.next()));
        let mut q = SVector::<f64, 12>::zeros();
        q[4] = l1;
        q[8] = l1 + l2 * theta.cos();
        q[9] = l2 * theta.sin();
        q[10] = 1e-4 * rng.next();
        q[7] = 1e-3 * (1.5 + rng.next());
        q[11] = 3e-3 * (1.5 + rng.next());
        let m = bending_block(&b, &q);
        assert_same(&m, &other, 800, &format!("bend {k} at {theta:.3e} rad"));
        other = m;
    }
}

#[test]
fn capped_iterations_fail_exactly_where_nalgebra_does() {
    let mut rng = Lcg(9);
    let (mut failed, mut passed) = (0, 0);
    for _ in 0..200 {
        let (m, other) = (rng.symmetric::<8>(), rng.symmetric::<8>());
        for cap in 1..12 {
            assert_same(&m, &other, cap, &format!("cap {cap}"));
            match nalgebra(&m, cap) {
                Some(_) => passed += 1,
                None => failed += 1,
            }
        }
    }
    // Both outcomes were exercised.
    assert!(failed > 100 && passed > 100, "{failed} failed, {passed} passed");
}

#[test]
fn non_finite_input_is_left_to_the_caller() {
    let mut m = Lcg(3).symmetric::<8>();
    let good = m;
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        m[3][5] = bad;
        assert!(eigen(&m, f64::EPSILON, 800).is_none());
        let [first, second] = eigen_pair(&m, &good, f64::EPSILON, 800);
        assert!(first.is_none());
        assert_eq!(bits(&second), bits(&nalgebra(&good, 800)));
    }
}
