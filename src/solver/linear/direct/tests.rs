use super::*;
use crate::sparse::dot;
use nalgebra::{DMatrix, DVector};

/// 2D 5-point Laplacian on an `m x m` grid plus `shift` on the diagonal.
fn grid_laplacian(m: usize, shift: f64) -> CsrMatrix {
    let idx = |i: usize, j: usize| (i * m + j) as u32;
    let mut e = Vec::new();
    for i in 0..m {
        for j in 0..m {
            e.push((idx(i, j), idx(i, j)));
            if i + 1 < m {
                e.push((idx(i, j), idx(i + 1, j)));
                e.push((idx(i + 1, j), idx(i, j)));
            }
            if j + 1 < m {
                e.push((idx(i, j), idx(i, j + 1)));
                e.push((idx(i, j + 1), idx(i, j)));
            }
        }
    }
    let mut a = CsrMatrix::from_pattern(m * m, e);
    for r in 0..a.n {
        let deg = (a.row_ptr[r + 1] - a.row_ptr[r] - 1) as f64;
        for k in a.row_ptr[r]..a.row_ptr[r + 1] {
            a.values[k] = if a.col_idx[k] as usize == r { deg + shift } else { -1.0 };
        }
    }
    a
}

fn dense(a: &CsrMatrix) -> DMatrix<f64> {
    DMatrix::from_fn(a.n, a.n, |r, c| a.find(r, c).map_or(0.0, |k| a.values[k]))
}

fn max_err(x: &[f64], y: &DVector<f64>) -> f64 {
    x.iter().zip(y.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
}

#[test]
fn matches_dense_solve_and_reuses_symbolic() {
    let mut a = grid_laplacian(9, 0.3);
    let b: Vec<f64> = (0..a.n).map(|i| ((i * 31) % 17) as f64 - 8.0).collect();
    let mut s = DirectSolver::default();
    let mut x = vec![0.0; a.n];
    assert_eq!(s.solve(&a, &b, &mut x).unwrap(), FactorKind::Llt);
    let exact = dense(&a).lu().solve(&DVector::from_vec(b.clone())).unwrap();
    assert!(max_err(&x, &exact) < 1e-10);

    // New values, same pattern: numeric refactorization only.
    for (k, v) in a.values.iter_mut().enumerate() {
        *v *= 1.0 + 0.1 * (k % 3) as f64;
    }
    // Keep symmetry: rebuild from the upper triangle.
    let d = dense(&a);
    for r in 0..a.n {
        for k in a.row_ptr[r]..a.row_ptr[r + 1] {
            let c = a.col_idx[k] as usize;
            a.values[k] = if r <= c { d[(r, c)] } else { d[(c, r)] };
        }
    }
    s.solve(&a, &b, &mut x).unwrap();
    assert_eq!(s.symbolic_count(), 1);
    let exact = dense(&a).lu().solve(&DVector::from_vec(b.clone())).unwrap();
    assert!(max_err(&x, &exact) < 1e-10);

    // A different pattern triggers a new analysis.
    let a2 = grid_laplacian(7, 1.0);
    let b2 = vec![1.0; a2.n];
    let mut x2 = vec![0.0; a2.n];
    s.solve(&a2, &b2, &mut x2).unwrap();
    assert_eq!(s.symbolic_count(), 2);
    let exact2 = dense(&a2).lu().solve(&DVector::from_vec(b2)).unwrap();
    assert!(max_err(&x2, &exact2) < 1e-10);
}

#[test]
fn singular_psd_falls_back_to_shift() {
    // Pure Neumann Laplacian: PSD with the constant vector in its kernel.
    let a = grid_laplacian(6, 0.0);
    let b: Vec<f64> = (0..a.n).map(|i| if i % 2 == 0 { 1.0 } else { -1.0 }).collect();
    let mut s = DirectSolver::default();
    let mut x = vec![0.0; a.n];
    let kind = s.solve(&a, &b, &mut x).unwrap();
    let FactorKind::ShiftedLlt { shift } = kind else {
        panic!("expected a shifted LLT, got {kind:?}")
    };
    // The returned x solves the shifted (positive definite) system.
    let ad = dense(&a) + DMatrix::identity(a.n, a.n) * shift;
    let r = &ad * DVector::from_vec(x.clone()) - DVector::from_vec(b.clone());
    assert!(r.norm() < 1e-6 * DVector::from_vec(b).norm());
}

#[test]
fn a_badly_scaled_positive_definite_matrix_passes_the_plain_factor() {
    // D A D with one pair of unknowns scaled by 1e11 (diagonal 1e22 against
    // ~4, like a yarn segment closing within a step): positive definite and
    // well conditioned once scaled back, so plain LLT must be kept and the
    // solve must be accurate in every component. The last assert checks
    // that the unscaled relative residual, which the probe used to test,
    // is above its tolerance here.
    let mut a = grid_laplacian(12, 0.5);
    let big = [17usize, 18];
    let d = |i: usize| if big.contains(&i) { 1e11 } else { 1.0 };
    for r in 0..a.n {
        for k in a.row_ptr[r]..a.row_ptr[r + 1] {
            a.values[k] *= d(r) * d(a.col_idx[k] as usize);
        }
    }
    let b: Vec<f64> = (0..a.n).map(|i| 1.0 + (i % 5) as f64).collect();
    let mut s = DirectSolver::default();
    let mut x = vec![0.0; a.n];
    assert_eq!(s.solve(&a, &b, &mut x).unwrap(), FactorKind::Llt);
    let exact = dense(&a).lu().solve(&DVector::from_vec(b.clone())).unwrap();
    for i in 0..a.n {
        assert!(
            (x[i] - exact[i]).abs() <= 1e-9 * exact[i].abs(),
            "{i}: {} vs {}",
            x[i],
            exact[i]
        );
    }
    let mut r = vec![0.0; a.n];
    a.residual(&x, &b, &mut r);
    let unscaled = dot(&r, &r).sqrt() / dot(&b, &b).sqrt();
    assert!(
        unscaled > s.params.max_rel_residual,
        "the case must defeat an unscaled probe: {unscaled:e}"
    );
}

#[test]
fn indefinite_uses_ldlt_when_shifts_disabled() {
    let mut a = grid_laplacian(5, 4.5);
    // Flip the sign of a few diagonal entries: symmetric, nonsingular, indefinite.
    for r in [0, 7, 13] {
        let k = a.find(r, r).unwrap();
        a.values[k] = -a.values[k];
    }
    let b: Vec<f64> = (0..a.n).map(|i| (i as f64).sin()).collect();
    let mut s = DirectSolver::new(DirectParams {
        shift_tries: 0,
        ..Default::default()
    });
    let mut x = vec![0.0; a.n];
    assert_eq!(s.solve(&a, &b, &mut x).unwrap(), FactorKind::Ldlt);
    let exact = dense(&a).lu().solve(&DVector::from_vec(b)).unwrap();
    assert!(max_err(&x, &exact) < 1e-9);
}

#[test]
fn the_rayon_pool_and_the_sequential_path_solve_the_same_system() {
    // Large enough for supernodes, so the pool actually splits work.
    let a = grid_laplacian(60, 0.1);
    let b: Vec<f64> = (0..a.n).map(|i| (0.37 * i as f64).cos()).collect();
    let mut seq = DirectSolver::default();
    assert!(!seq.params.parallel);
    let mut par = DirectSolver::new(DirectParams {
        parallel: true,
        ..Default::default()
    });
    let (mut xs, mut xp) = (vec![0.0; a.n], vec![0.0; a.n]);
    assert_eq!(seq.solve(&a, &b, &mut xs).unwrap(), FactorKind::Llt);
    assert_eq!(par.solve(&a, &b, &mut xp).unwrap(), FactorKind::Llt);
    let scale = xs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = xs.iter().zip(&xp).fold(0.0f64, |m, (s, p)| m.max((s - p).abs()));
    assert!(diff <= 1e-12 * scale, "diff {diff:e}, scale {scale:e}");
    let mut r = vec![0.0; a.n];
    a.residual(&xs, &b, &mut r);
    assert!(dot(&r, &r).sqrt() <= 1e-10 * dot(&b, &b).sqrt());
}

#[test]
fn every_ordering_rule_solves_the_same_system_and_reports_its_choice() {
    // Unknowns in groups of 3 interleaved across the grid, as a node's x
    // and u are in a yarn model's numbering.
    let a = grid_laplacian(12, 0.2);
    let groups: Vec<u32> = (0..a.n).map(|i| (i % (a.n / 3)) as u32).collect();
    let b: Vec<f64> = (0..a.n).map(|i| ((i * 13) % 7) as f64 - 3.0).collect();
    let exact = dense(&a).lu().solve(&DVector::from_vec(b.clone())).unwrap();
    let mut sizes = Vec::new();
    for ordering in [Some(Ordering::Scalar), Some(Ordering::Grouped), None] {
        let mut s = DirectSolver::new(DirectParams {
            ordering,
            ..DirectParams::default()
        });
        s.set_ordering_groups(&groups);
        let mut x = vec![0.0; a.n];
        s.solve(&a, &b, &mut x).unwrap();
        assert!(max_err(&x, &exact) < 1e-10, "{ordering:?}");
        match ordering {
            Some(o) => {
                assert_eq!(s.ordering(), Some(o));
                sizes.push(s.factor_len().unwrap());
            }
            // The default keeps the smaller factor of the two.
            None => assert_eq!(s.factor_len().unwrap(), sizes[0].min(sizes[1])),
        }
    }
    // Without groups the grouped rule falls back to scalar AMD.
    let mut s = DirectSolver::new(DirectParams {
        ordering: Some(Ordering::Grouped),
        ..DirectParams::default()
    });
    let mut x = vec![0.0; a.n];
    s.solve(&a, &b, &mut x).unwrap();
    assert_eq!(s.ordering(), Some(Ordering::Scalar));
}

#[test]
fn new_groups_drop_the_analysis() {
    let a = grid_laplacian(6, 0.5);
    let mut s = DirectSolver::default();
    assert!(s.analyze(&a).unwrap());
    assert!(!s.analyze(&a).unwrap());
    s.set_ordering_groups(&(0..a.n as u32).map(|i| i / 2).collect::<Vec<_>>());
    assert!(s.analyze(&a).unwrap());
    s.set_ordering_groups(&(0..a.n as u32).map(|i| i / 2).collect::<Vec<_>>());
    assert!(!s.analyze(&a).unwrap());
}

/// `solve` runs each attempt's residual probe beside the solve (on two or
/// more threads); the answer must be the bits of factorizing first and
/// solving after, also when the first attempts fail (the singular case).
#[test]
fn solve_with_the_probe_alongside_gives_the_bits_of_factorize_then_solve() {
    for a in [grid_laplacian(12, 0.3), grid_laplacian(6, 0.0)] {
        let b: Vec<f64> = (0..a.n).map(|i| (0.7 * i as f64).cos()).collect();
        let mut s = DirectSolver::default();
        let mut x = vec![0.0; a.n];
        let kind = s.solve(&a, &b, &mut x).unwrap();
        let mut t = DirectSolver::default();
        assert_eq!(t.factorize(&a).unwrap(), kind);
        let mut y = b.clone();
        t.solve_in_place(&mut y).unwrap();
        assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()), "{kind:?}");
    }
}

/// Rows cancelled to identity (as the assembly cancels EIL and pinned
/// coordinates) leave the factor without their couplings; a later matrix
/// of the same pattern that couples them again gets a new analysis, and
/// both solves match the dense ones. (An analysis of a matrix without
/// identity rows stays valid for one with them, only less lean.)
#[test]
fn cancelled_rows_leave_the_factor_and_come_back_when_coupled_again() {
    let full = grid_laplacian(8, 0.4);
    let mut a = full.clone();
    let cancelled = [3usize, 17, 18, 40];
    for r in 0..a.n {
        for k in a.row_ptr[r]..a.row_ptr[r + 1] {
            let c = a.col_idx[k] as usize;
            if cancelled.contains(&r) || cancelled.contains(&c) {
                a.values[k] = if r == c { 1.0 } else { 0.0 };
            }
        }
    }
    let b: Vec<f64> = (0..a.n).map(|i| 1.0 + (i % 5) as f64).collect();
    let mut t = DirectSolver::default();
    t.analyze(&full).unwrap();
    let mut s = DirectSolver::default();
    let mut x = vec![0.0; a.n];
    s.solve(&a, &b, &mut x).unwrap();
    assert!(s.factor_len().unwrap() < t.factor_len().unwrap());
    let exact = dense(&a).lu().solve(&DVector::from_vec(b.clone())).unwrap();
    assert!(max_err(&x, &exact) < 1e-10);
    assert_eq!(s.symbolic_count(), 1);
    // Same cancellation: the analysis is reused.
    s.solve(&a, &b, &mut x).unwrap();
    assert_eq!(s.symbolic_count(), 1);
    // Coupled again (same pattern): analysed anew, and still exact.
    s.solve(&full, &b, &mut x).unwrap();
    assert_eq!(s.symbolic_count(), 2);
    let exact = dense(&full).lu().solve(&DVector::from_vec(b)).unwrap();
    assert!(max_err(&x, &exact) < 1e-10);
}

/// A 7-point Laplacian on a `k^3` grid with seeded jitter on every entry,
/// made diagonally dominant (SPD): big enough for a supernodal factor.
fn jittered_grid(k: usize, seed: u64) -> CsrMatrix {
    let id = |x: usize, y: usize, z: usize| ((x * k + y) * k + z) as u32;
    let mut entries = Vec::new();
    for x in 0..k {
        for y in 0..k {
            for z in 0..k {
                entries.push((id(x, y, z), id(x, y, z)));
                for (dx, dy, dz) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                    if x + dx < k && y + dy < k && z + dz < k {
                        let j = id(x + dx, y + dy, z + dz);
                        entries.extend([(id(x, y, z), j), (j, id(x, y, z))]);
                    }
                }
            }
        }
    }
    let mut a = CsrMatrix::from_pattern(k * k * k, entries);
    let mut state = 0x2545_f491_4f6c_dd1du64 ^ seed;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for r in 0..a.n {
        for p in a.row_ptr[r]..a.row_ptr[r + 1] {
            let c = a.col_idx[p] as usize;
            if c > r {
                let v = -0.5 - next();
                a.values[p] = v;
                let q = a.find(c, r).expect("symmetric pattern");
                a.values[q] = v;
            }
        }
    }
    for r in 0..a.n {
        let off: f64 = (a.row_ptr[r]..a.row_ptr[r + 1])
            .filter(|&p| a.col_idx[p] as usize != r)
            .map(|p| a.values[p].abs())
            .sum();
        let d = a.find(r, r).expect("diagonal");
        a.values[d] = off + 1e-3;
    }
    a
}

/// Two dense blocks joined by a few couplings: supernodes wide enough that
/// one updates another over more than 512 columns.
fn two_cliques(a: usize, b: usize) -> CsrMatrix {
    let mut entries: Vec<(u32, u32)> = Vec::new();
    for block in [0..a, a..a + b] {
        for i in block.clone() {
            for j in block.clone() {
                entries.push((i as u32, j as u32));
            }
        }
    }
    for i in 0..a.min(b) / 10 {
        let (r, c) = ((10 * i) as u32, (a + 10 * i) as u32);
        entries.extend([(r, c), (c, r)]);
    }
    let mut m = CsrMatrix::from_pattern(a + b, entries);
    for r in 0..m.n {
        for p in m.row_ptr[r]..m.row_ptr[r + 1] {
            let c = m.col_idx[p] as usize;
            // Symmetric in (r, c): the solver reads both triangles.
            let w = (((r + c) * 7 + (r * c) % 13) % 17) as f64 / 17.0;
            m.values[p] = if r == c { (a + b) as f64 } else { -0.5 - w / 2.0 };
        }
    }
    m
}

fn relative_residual(a: &CsrMatrix, x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; a.n];
    a.mul_vec(x, &mut ax);
    let r: Vec<f64> = ax.iter().zip(b).map(|(p, q)| p - q).collect();
    (dot(&r, &r) / dot(b, b)).sqrt()
}

#[test]
fn supernodal_factors_solve_to_a_small_residual_on_every_refactorization() {
    for parallel in [false, true] {
        let mut s = DirectSolver::new(DirectParams {
            parallel,
            ..DirectParams::default()
        });
        // New values on the same pattern, as in a Newton loop.
        for seed in 0..3 {
            let a = jittered_grid(12, seed);
            let b: Vec<f64> = (0..a.n).map(|i| ((i * 31) % 17) as f64 - 8.0).collect();
            let mut x = vec![0.0; a.n];
            assert_eq!(s.solve(&a, &b, &mut x).unwrap(), FactorKind::Llt);
            let rel = relative_residual(&a, &x, &b);
            assert!(rel < 1e-10, "parallel {parallel}, seed {seed}: {rel:e}");
        }
        assert_eq!(s.symbolic_count(), 1);
        let a = two_cliques(1100, 700);
        let b: Vec<f64> = (0..a.n).map(|i| 1.0 + (i % 5) as f64).collect();
        let mut x = vec![0.0; a.n];
        assert_eq!(s.solve(&a, &b, &mut x).unwrap(), FactorKind::Llt);
        let rel = relative_residual(&a, &x, &b);
        assert!(rel < 1e-10, "parallel {parallel}, two cliques: {rel:e}");
    }
}

#[test]
fn an_indefinite_matrix_is_not_passed_off_as_a_plain_factor() {
    // Shifting every diagonal far down makes the matrix indefinite: plain
    // LLT must fail, and whatever factor passes must still solve it.
    let mut a = jittered_grid(10, 7);
    for r in 0..a.n {
        let d = a.find(r, r).expect("diagonal");
        a.values[d] -= 20.0;
    }
    let b = vec![1.0; a.n];
    let mut x = vec![0.0; a.n];
    match DirectSolver::default().solve(&a, &b, &mut x) {
        Ok(kind) => {
            assert_ne!(kind, FactorKind::Llt);
            if kind == FactorKind::Ldlt {
                assert!(relative_residual(&a, &x, &b) < 1e-6);
            }
        }
        Err(DirectError::NotFactorizable { .. }) => {}
        Err(e) => panic!("{e}"),
    }
}
