//! Fill-reducing orderings: AMD on the unknowns, or AMD on groups of them.
//!
//! The Newton matrix of a yarn model has a natural grouping: the three `x`
//! coordinates of a node and the `u` of every yarn point at that node
//! couple to the same neighbours. AMD on the scalar graph only merges
//! unknowns whose patterns are identical, which `x` and `u` are not, so it
//! orders 4 or 5 unknowns per node one by one, and its greedy tie-breaking
//! can land far from a good ordering. AMD on the graph of groups (one vertex
//! per node, an edge wherever any of their unknowns couple), with each
//! group's unknowns kept together, is a different heuristic on the same
//! matrix. On the first Newton matrix of a relaxation neither wins
//! everywhere: grouped AMD gives a stockinette's factor 25 to 30% fewer
//! entries, and a linen stitch's 8 to 17% more (docs/RELAX.md, "Ordering",
//! measured with `examples/bench_linear.rs --orderings`),
//! so [`super::DirectSolver`] analyses both once per pattern and keeps the
//! one with the smaller factor. Both are deterministic, and an analysis is
//! cheap next to the numeric factorizations that reuse it.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::SymbolicSparseColMatRef;

/// Which ordering an analysis uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ordering {
    /// faer's AMD on the unknowns.
    Scalar,
    /// AMD on the groups (see the module docs), each group's unknowns
    /// consecutive in ascending order.
    Grouped,
}

/// The grouped AMD permutation `(forward, inverse)` of an `n`-unknown
/// matrix given by its lower triangle in CSC (`col_ptr`, `row_idx`).
/// `groups[i]` is unknown `i`'s group. `None` when `groups` does not have
/// one entry per unknown, or AMD fails.
pub fn grouped_amd(col_ptr: &[usize], row_idx: &[usize], groups: &[u32]) -> Option<(Vec<usize>, Vec<usize>)> {
    let n = col_ptr.len().checked_sub(1)?;
    if groups.len() != n || n == 0 {
        return None;
    }
    let m = *groups.iter().max()? as usize + 1;
    // Quotient graph, both triangles, no self loops, sorted and unique.
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); m];
    for j in 0..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            let (a, b) = (groups[i] as usize, groups[j] as usize);
            if a != b {
                adj[a].push(b);
                adj[b].push(a);
            }
        }
    }
    let mut g_ptr = Vec::with_capacity(m + 1);
    let mut g_idx = Vec::new();
    g_ptr.push(0);
    for list in &mut adj {
        list.sort_unstable();
        list.dedup();
        g_idx.extend_from_slice(list);
        g_ptr.push(g_idx.len());
    }
    let graph = SymbolicSparseColMatRef::new_checked(m, m, &g_ptr, None, &g_idx);
    let (mut perm, mut perm_inv) = (vec![0usize; m], vec![0usize; m]);
    let mut mem = MemBuffer::try_new(amd::order_scratch::<usize>(m, g_idx.len())).ok()?;
    amd::order(
        &mut perm,
        &mut perm_inv,
        graph,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .ok()?;
    // Unknowns coupled to nothing (rows the assembly cancelled, whose
    // couplings the analysis left out) go first. Left inside their group,
    // each would split its group's columns into separate supernodes: on a
    // 40x40 linen stitch that made the numeric factorizations of the first
    // two steps 1.5 to 2.6 times slower with a factor 27% smaller
    // (docs/RELAX.md, "Ordering").
    let mut coupled = vec![false; n];
    for j in 0..n {
        for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            if i != j {
                coupled[i] = true;
                coupled[j] = true;
            }
        }
    }
    // Expand: unknowns of each group in group order, ascending within it.
    let mut start = vec![0usize; m + 1];
    for (&g, _) in groups.iter().zip(&coupled).filter(|(_, &c)| c) {
        start[g as usize + 1] += 1;
    }
    for k in 0..m {
        start[k + 1] += start[k];
    }
    let mut members = vec![0usize; start[m]];
    let mut fill = start.clone();
    for (i, (&g, _)) in groups.iter().zip(&coupled).enumerate().filter(|(_, (_, &c))| c) {
        members[fill[g as usize]] = i;
        fill[g as usize] += 1;
    }
    let forward: Vec<usize> = (0..n)
        .filter(|&i| !coupled[i])
        .chain(
            perm.iter()
                .flat_map(|&g| members[start[g]..start[g + 1]].iter().copied()),
        )
        .collect();
    let mut inverse = vec![0usize; n];
    for (k, &i) in forward.iter().enumerate() {
        inverse[i] = k;
    }
    Some((forward, inverse))
}

/// Floating-point operations of a numeric factorization under `symbolic`,
/// counted as multiply-adds. A supernode of `k` columns with `r` rows below
/// its diagonal block costs `k^3/3` (its dense Cholesky) plus `k^2 r` (the
/// triangular solve under it) plus `k r^2` (its update of the ancestors);
/// a simplicial column with `c` entries below the diagonal costs `c^2`.
pub fn factor_flops(symbolic: &SymbolicCholesky<usize>) -> f64 {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => {
            let (begin, end, rows) = (s.supernode_begin(), s.supernode_end(), s.col_ptr_for_row_idx());
            (0..s.n_supernodes())
                .map(|k| {
                    let (c, r) = ((end[k] - begin[k]) as f64, (rows[k + 1] - rows[k]) as f64);
                    c * c * c / 3.0 + c * c * r + c * r * r
                })
                .sum()
        }
        SymbolicCholeskyRaw::Simplicial(s) => s
            .col_ptr()
            .windows(2)
            .map(|w| {
                let below = (w[1] - w[0]).saturating_sub(1) as f64;
                below * below
            })
            .sum(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lower CSC of a path graph 0-1-2-...-(n-1) with diagonal.
    fn path(n: usize) -> (Vec<usize>, Vec<usize>) {
        let (mut ptr, mut idx) = (vec![0], vec![]);
        for j in 0..n {
            idx.push(j);
            if j + 1 < n {
                idx.push(j + 1);
            }
            ptr.push(idx.len());
        }
        (ptr, idx)
    }

    #[test]
    fn a_grouped_ordering_is_a_permutation_that_keeps_each_group_together() {
        let (ptr, idx) = path(9);
        // Groups interleaved in storage: unknown i belongs to group i % 3.
        let groups: Vec<u32> = (0..9).map(|i| (i % 3) as u32).collect();
        let (fwd, inv) = grouped_amd(&ptr, &idx, &groups).unwrap();
        let mut seen = fwd.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..9).collect::<Vec<_>>());
        for (k, &i) in fwd.iter().enumerate() {
            assert_eq!(inv[i], k);
        }
        // Each group's three unknowns are consecutive, ascending.
        for chunk in fwd.chunks(3) {
            assert!(chunk.iter().all(|&i| groups[i] == groups[chunk[0]]));
            assert!(chunk.windows(2).all(|w| w[0] < w[1]));
        }
    }

    #[test]
    fn unknowns_coupled_to_nothing_come_first_and_groups_stay_together() {
        // Path 0-1-...-8 with unknowns 4 and 7 cut loose (diagonal only).
        let (mut ptr, mut idx) = (vec![0], vec![]);
        for j in 0..9 {
            idx.push(j);
            if j + 1 < 9 && ![3, 4, 6, 7].contains(&j) {
                idx.push(j + 1);
            }
            ptr.push(idx.len());
        }
        let groups: Vec<u32> = (0..9).map(|i| (i / 3) as u32).collect();
        let (fwd, inv) = grouped_amd(&ptr, &idx, &groups).unwrap();
        assert_eq!(&fwd[..2], &[4, 7]);
        for (k, &i) in fwd.iter().enumerate() {
            assert_eq!(inv[i], k);
        }
        // The coupled members of each group are consecutive.
        let rest: Vec<u32> = fwd[2..].iter().map(|&i| groups[i]).collect();
        assert!(rest.windows(2).filter(|w| w[0] != w[1]).count() == 2, "{rest:?}");
    }

    /// Flops of a dense `n x n` lower triangle under the identity ordering,
    /// as simplicial columns or supernodes, whichever faer chose.
    #[test]
    fn factor_flops_count_a_dense_factor_by_hand() {
        use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymmetricOrdering};
        use faer::Side;
        let n = 6;
        // Upper triangle: faer's identity ordering reads the pattern as given.
        let (mut ptr, mut idx) = (vec![0], vec![]);
        for j in 0..n {
            idx.extend(0..=j);
            ptr.push(idx.len());
        }
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &ptr, None, &idx);
        let symbolic =
            factorize_symbolic_cholesky(sym, Side::Upper, SymmetricOrdering::Identity, Default::default()).unwrap();
        let expect = match symbolic.raw() {
            // Columns with 5, 4, ..., 0 entries below the diagonal.
            SymbolicCholeskyRaw::Simplicial(_) => 25.0 + 16.0 + 9.0 + 4.0 + 1.0,
            // Supernodes of c columns, r rows below: c^3/3 + c^2 r + c r^2.
            SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
                .map(|k| {
                    let c = (s.supernode_end()[k] - s.supernode_begin()[k]) as f64;
                    let r = (n - s.supernode_end()[k]) as f64;
                    c * c * c / 3.0 + c * c * r + c * r * r
                })
                .sum(),
        };
        assert!(
            (factor_flops(&symbolic) - expect).abs() < 1e-9,
            "{} vs {expect}",
            factor_flops(&symbolic)
        );
        // A diagonal matrix costs nothing.
        let diag_ptr: Vec<usize> = (0..=n).collect();
        let diag_idx: Vec<usize> = (0..n).collect();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &diag_ptr, None, &diag_idx);
        let symbolic =
            factorize_symbolic_cholesky(sym, Side::Upper, SymmetricOrdering::Identity, Default::default()).unwrap();
        let ones = match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => 0.0,
            SymbolicCholeskyRaw::Supernodal(s) => s.n_supernodes() as f64 / 3.0,
        };
        assert!((factor_flops(&symbolic) - ones).abs() < 1e-9);
    }

    #[test]
    fn groups_of_the_wrong_length_give_no_ordering() {
        let (ptr, idx) = path(4);
        assert!(grouped_amd(&ptr, &idx, &[0, 0, 1]).is_none());
        assert!(grouped_amd(&[0], &[], &[]).is_none());
    }
}
