use super::*;
use crate::solver::test_stencils::{Gravity, Spring};
use nalgebra::DMatrix;

/// Four 3D nodes, five springs (some compressed, so the exact Hessian is
/// indefinite), gravity on every node; node 0 pinned.
fn scene() -> (Vec<Box<dyn AnyStencilSet>>, Vec<f64>, Vec<bool>) {
    let pairs = [(0u32, 1u32), (1, 2), (2, 3), (0, 2), (1, 3)];
    let springs = pairs.iter().map(|_| Spring { k: 5.0, rest: 1.5 }).collect();
    let dofs = pairs
        .iter()
        .map(|&(a, b)| [3 * a, 3 * a + 1, 3 * a + 2, 3 * b, 3 * b + 1, 3 * b + 2])
        .collect();
    let gravity = (0..4).map(|_| Gravity { mg: 0.7 }).collect();
    let gdofs = (0..4u32).map(|a| [3 * a, 3 * a + 1, 3 * a + 2]).collect();
    let sets: Vec<Box<dyn AnyStencilSet>> = vec![
        Box::new(StencilSet::new("springs", springs, dofs)),
        Box::new(StencilSet::new("gravity", gravity, gdofs)),
    ];
    let q = vec![0.0, 0.0, 0.0, 1.0, 0.1, 0.0, 1.1, 0.9, 0.2, 0.2, 1.3, -0.1];
    let mut free = vec![true; 12];
    free[..3].fill(false);
    (sets, q, free)
}

fn dense(h: &CsrMatrix) -> DMatrix<f64> {
    DMatrix::from_fn(h.n, h.n, |r, c| h.find(r, c).map_or(0.0, |k| h.values[k]))
}

fn assembled(sets: &[Box<dyn AnyStencilSet>], q: &[f64], free: &[bool], h: &mut CsrMatrix, psd: bool) -> Vec<f64> {
    let mut g = vec![0.0; q.len()];
    assemble(sets, q, free, &mut g, h, psd).unwrap();
    g
}

#[test]
fn gradient_and_hessian_match_fd_of_summed_energy() {
    let (mut sets, q, free) = scene();
    let mut h = hessian_pattern(q.len(), &sets);
    bind_all(&mut sets, &h).unwrap();
    let g = assembled(&sets, &q, &free, &mut h, false);
    let hd = dense(&h);
    let eps = 1e-6;
    for i in (0..q.len()).filter(|&i| free[i]) {
        let (mut qp, mut qm) = (q.clone(), q.clone());
        qp[i] += eps;
        qm[i] -= eps;
        let fd = (total_energy(&sets, &qp) - total_energy(&sets, &qm)) / (2.0 * eps);
        assert!(
            (fd - g[i]).abs() < 1e-6 * fd.abs().max(1.0),
            "grad[{i}] {} vs fd {fd}",
            g[i]
        );
        let mut scratch = h.clone();
        let gp = assembled(&sets, &qp, &free, &mut scratch, false);
        let gm = assembled(&sets, &qm, &free, &mut scratch, false);
        for j in (0..q.len()).filter(|&j| free[j]) {
            let fd = (gp[j] - gm[j]) / (2.0 * eps);
            assert!((fd - hd[(j, i)]).abs() < 1e-5 * fd.abs().max(1.0), "H[{j},{i}]");
        }
    }
    // The summed gradient is not trivially per-set: gravity contributes too.
    assert!((g[5] - 0.7).abs() > 1e-3);
}

#[test]
fn cancelled_rows_are_identity_with_zero_gradient() {
    let (mut sets, q, free) = scene();
    let mut h = hessian_pattern(q.len(), &sets);
    bind_all(&mut sets, &h).unwrap();
    let g = assembled(&sets, &q, &free, &mut h, true);
    let hd = dense(&h);
    for r in 0..3 {
        assert_eq!(g[r], 0.0);
        for c in 0..q.len() {
            let expect = if r == c { 1.0 } else { 0.0 };
            assert_eq!(hd[(r, c)], expect, "row ({r},{c})");
            assert_eq!(hd[(c, r)], expect, "col ({c},{r})");
        }
    }
    // Node 0 is still coupled to nodes 1 and 2 in the pattern: cancelling
    // writes zeros, it does not change the structure.
    assert!(h.find(0, 3).is_some());
}

#[test]
fn projection_makes_the_assembled_hessian_psd() {
    let (mut sets, q, free) = scene();
    let mut h = hessian_pattern(q.len(), &sets);
    bind_all(&mut sets, &h).unwrap();
    assembled(&sets, &q, &free, &mut h, false);
    let exact_min = dense(&h).symmetric_eigen().eigenvalues.min();
    assert!(exact_min < -1e-3, "scene should be indefinite, min eig {exact_min}");
    assembled(&sets, &q, &free, &mut h, true);
    let projected_min = dense(&h).symmetric_eigen().eigenvalues.min();
    assert!(projected_min > -1e-10, "{projected_min}");
}

#[test]
fn unbound_and_bad_maps_are_errors() {
    let (sets, q, free) = scene();
    let mut h = hessian_pattern(q.len(), &sets);
    let mut g = vec![0.0; q.len()];
    assert!(matches!(
        assemble(&sets, &q, &free, &mut g, &mut h, false),
        Err(AssemblyError::Unbound { .. })
    ));
    let mut bad = StencilSet::new("bad", vec![Gravity { mg: 1.0 }], vec![[0, 1, 99]]);
    assert!(matches!(bad.bind(&h), Err(AssemblyError::OutOfRange { index: 99, .. })));
    // A pattern without the set's couplings is reported, not panicked on.
    let small = CsrMatrix::from_pattern(12, (0..12).map(|i| (i, i)));
    let mut springs = StencilSet::new("s", vec![Spring { k: 1.0, rest: 1.0 }], vec![[0, 1, 2, 3, 4, 5]]);
    assert!(matches!(springs.bind(&small), Err(AssemblyError::MissingEntry { .. })));
}

/// With several sets failing, `bind_all` reports the first in order, as a
/// loop would, however its threads happen to take them; the rest bind.
#[test]
fn bind_all_reports_the_first_failing_set_in_order() {
    let small = CsrMatrix::from_pattern(12, (0..12).map(|i| (i, i)));
    let spring = |name: &str| -> Box<dyn AnyStencilSet> {
        Box::new(StencilSet::new(
            name,
            vec![Spring { k: 1.0, rest: 1.0 }],
            vec![[0, 1, 2, 3, 4, 5]],
        ))
    };
    // A large set that binds, then two that do not.
    let many: Vec<[u32; 3]> = (0..12).map(|i| [i, i, i]).collect();
    let fine: Box<dyn AnyStencilSet> = Box::new(StencilSet::new(
        "fine",
        (0..12).map(|_| Gravity { mg: 1.0 }).collect(),
        many,
    ));
    let mut sets = vec![fine, spring("first"), spring("second")];
    match bind_all(&mut sets, &small) {
        Err(AssemblyError::MissingEntry { set, .. }) => assert_eq!(set, "first"),
        other => panic!("expected the first set's missing entry, got {other:?}"),
    }
    assert!(bind_all(&mut sets[..1], &small).is_ok());
}

/// Parallel evaluation hands results back in stencil order, whatever the
/// thread count and however the blocks fall (sizes around the block edges;
/// `ordered_map`'s own tests cover uneven work and panics).
#[test]
fn blocks_come_back_in_order_for_any_thread_count() {
    let f = |k: usize| (k as f64 * 0.37).sin() / (1.0 + k as f64);
    for n in [0, 1, BLOCK - 1, BLOCK, 2 * BLOCK + 1, 7 * BLOCK + 13] {
        let serial: Vec<f64> = (0..n).map(f).collect();
        for workers in [1, 2, 3, 8] {
            let mut got = Vec::new();
            ordered_map(workers, BLOCK, n, f, |start, block: &[f64]| {
                assert_eq!(start, got.len(), "blocks are emitted in order");
                got.extend_from_slice(block);
            });
            assert_eq!(got, serial, "n = {n}, workers = {workers}");
        }
    }
}

/// A chain of `n_nodes - 1` springs, node `a` to `a + 1`, with stiffness
/// `k0 + (k % km)` and rest length `r0 + 0.1 (k % rm)` for spring `k`.
fn spring_chain(n_nodes: usize, (k0, km): (f64, usize), (r0, rm): (f64, usize)) -> (Vec<Spring>, Vec<[u32; 6]>) {
    let springs = (0..n_nodes - 1)
        .map(|k| Spring {
            k: k0 + (k % km) as f64,
            rest: r0 + 0.1 * (k % rm) as f64,
        })
        .collect();
    let dofs = (0..n_nodes as u32 - 1)
        .map(|a| [3 * a, 3 * a + 1, 3 * a + 2, 3 * a + 3, 3 * a + 4, 3 * a + 5])
        .collect();
    (springs, dofs)
}

/// A set big enough to be split across threads assembles to the same
/// bits as a plain serial loop over its stencils.
#[test]
fn a_split_set_assembles_bit_for_bit_like_a_serial_loop() {
    let n_nodes = 3 * BLOCK;
    let (springs, dofs) = spring_chain(n_nodes, (1.0, 7), (0.5, 3));
    let q: Vec<f64> = (0..3 * n_nodes)
        .map(|i| (i as f64 * 0.61).cos() + (i / 3) as f64)
        .collect();
    let free = vec![true; q.len()];
    let sets: Vec<Box<dyn AnyStencilSet>> = vec![Box::new(StencilSet::new("springs", springs.clone(), dofs.clone()))];
    let mut h = hessian_pattern(q.len(), &sets);
    let mut sets = sets;
    bind_all(&mut sets, &h).unwrap();
    let mut g = vec![0.0; q.len()];
    assemble(&sets, &q, &free, &mut g, &mut h, true).unwrap();
    // Reference: the same sums, one stencil after another.
    let mut g_ref = vec![0.0; q.len()];
    let mut h_ref = h.clone();
    h_ref.values.fill(0.0);
    let mut e_ref = 0.0;
    for (s, d) in springs.iter().zip(&dofs) {
        let x = SVector::<f64, 6>::from_fn(|i, _| q[d[i] as usize]);
        e_ref += s.value(&x);
        let (gl, hl) = s.derivatives(&x, true);
        for i in 0..6 {
            g_ref[d[i] as usize] += gl[i];
            for j in 0..6 {
                let k = h_ref.find(d[i] as usize, d[j] as usize).unwrap();
                h_ref.values[k] += hl[(i, j)];
            }
        }
    }
    assert_eq!(g, g_ref);
    assert_eq!(h.values, h_ref.values);
    assert_eq!(total_energy(&sets, &q).to_bits(), e_ref.to_bits());
}

#[test]
fn the_gradient_alone_matches_the_assembled_gradient_with_fixed_rows_zero() {
    let n_nodes = 2 * BLOCK + 5;
    let (springs, dofs) = spring_chain(n_nodes, (2.0, 5), (0.4, 4));
    let q: Vec<f64> = (0..3 * n_nodes)
        .map(|i| (i as f64 * 0.37).sin() + (i / 3) as f64)
        .collect();
    // Every seventh coordinate fixed.
    let free: Vec<bool> = (0..q.len()).map(|i| i % 7 != 3).collect();
    let mut sets: Vec<Box<dyn AnyStencilSet>> = vec![Box::new(StencilSet::new("springs", springs, dofs))];
    let g_only = gradient(&sets, &q, &free);
    let mut h = hessian_pattern(q.len(), &sets);
    bind_all(&mut sets, &h).unwrap();
    let mut g = vec![0.0; q.len()];
    assemble(&sets, &q, &free, &mut g, &mut h, false).unwrap();
    assert!(g_only.iter().any(|v| *v != 0.0));
    for (i, (a, b)) in g_only.iter().zip(&g).enumerate() {
        assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "row {i}: {a} vs {b}");
        if !free[i] {
            assert_eq!(*a, 0.0);
        }
    }
}

#[test]
fn the_pattern_is_every_pair_within_a_map_plus_the_diagonal() {
    // Two sets of different widths with repeated and overlapping maps.
    let springs: Vec<Spring> = (0..40).map(|_| Spring { k: 1.0, rest: 1.0 }).collect();
    let dofs6: Vec<[u32; 6]> = (0..40u32)
        .map(|k| {
            let (a, b) = ((7 * k) % 25, (3 * k + 5) % 25);
            [3 * a, 3 * a + 1, 3 * a + 2, 3 * b, 3 * b + 1, 3 * b + 2]
        })
        .collect();
    let gravity: Vec<Gravity> = (0..10).map(|_| Gravity { mg: 1.0 }).collect();
    let dofs3: Vec<[u32; 3]> = (0..10u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
    let n = 80; // rows 75..80 are touched by no stencil: diagonal only
    let sets: Vec<Box<dyn AnyStencilSet>> = vec![
        Box::new(StencilSet::new("springs", springs, dofs6.clone())),
        Box::new(StencilSet::new("gravity", gravity, dofs3.clone())),
    ];
    let mut pairs: Vec<(u32, u32)> = (0..n as u32).map(|i| (i, i)).collect();
    for d in &dofs6 {
        for &r in d {
            pairs.extend(d.iter().map(|&c| (r, c)));
        }
    }
    for d in &dofs3 {
        for &r in d {
            pairs.extend(d.iter().map(|&c| (r, c)));
        }
    }
    assert_eq!(hessian_pattern(n, &sets), CsrMatrix::from_pattern(n, pairs));
}
