//! The lower triangle in the factor's own ordering, gathered straight from
//! the Newton matrix's CSR values.
//!
//! faer's `SymbolicCholesky::factorize_numeric_llt` permutes its input into
//! the fill-reducing order on every call (a counting sort over all entries)
//! and recomputes the workspace its supernodal kernel needs by walking every
//! supernode's descendants. Both depend on the pattern only, which is fixed
//! for a whole relaxation step. Profiling 100 refactorizations of a 40x40
//! linen stitch's Newton matrix put 5.9% of the time in that permutation,
//! 2.1% in the workspace query and 6% in our own gather before it. Here the
//! permuted pattern and the source slot of each of its entries are computed
//! once per analysis, so a refactorization is one gather and faer's
//! supernodal kernel. The kernel sees the same values at the same positions
//! as through faer's wrapper, so the factor is the same bit for bit.

use super::lower::LowerPattern;

/// CSC lower triangle of `P A P^T`, each column's rows sorted.
pub(super) struct PermutedLower {
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// `values[k] = csr.values[source[k]]`.
    pub source: Vec<usize>,
    /// Position of each permuted column's diagonal, where it has one.
    pub diag: Vec<Option<usize>>,
}

impl PermutedLower {
    /// The lower pattern `lower` (in the original numbering) under the
    /// permutation whose inverse is `perm_inv` (`new = perm_inv[old]`).
    pub fn new(lower: &LowerPattern, perm_inv: &[usize]) -> Self {
        let n = lower.col_ptr.len() - 1;
        // Each kept entry's (new column, new row): the smaller new index is
        // the column. A counting sort by column, then each (short) column
        // sorted by row: a comparison sort of all 1.5M entries of a 40x40
        // linen stitch took 20 ms per relaxation step.
        let new_place = |j: usize, k: usize| {
            let (ni, nj) = (perm_inv[lower.row_idx[k]], perm_inv[j]);
            (ni.min(nj), ni.max(nj))
        };
        let mut col_ptr = vec![0; n + 1];
        for j in 0..n {
            for k in lower.col_ptr[j]..lower.col_ptr[j + 1] {
                col_ptr[new_place(j, k).0 + 1] += 1;
            }
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut next = col_ptr.clone();
        let mut entries = vec![(0usize, 0usize); lower.row_idx.len()];
        for j in 0..n {
            for k in lower.col_ptr[j]..lower.col_ptr[j + 1] {
                let (c, r) = new_place(j, k);
                entries[next[c]] = (r, lower.source[k]);
                next[c] += 1;
            }
        }
        let mut diag = vec![None; n];
        for c in 0..n {
            let column = &mut entries[col_ptr[c]..col_ptr[c + 1]];
            column.sort_unstable();
            // Rows are at least the column, so a diagonal sorts first.
            if column.first().is_some_and(|&(r, _)| r == c) {
                diag[c] = Some(col_ptr[c]);
            }
        }
        PermutedLower {
            col_ptr,
            row_idx: entries.iter().map(|e| e.0).collect(),
            source: entries.iter().map(|e| e.1).collect(),
            diag,
        }
    }

    /// Fills `values` (one per entry) from the CSR values `csr`.
    pub fn gather(&self, csr: &[f64], values: &mut [f64]) {
        for (dst, &src) in values.iter_mut().zip(&self.source) {
            *dst = csr[src];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sparse::CsrMatrix;

    #[test]
    fn the_permuted_pattern_holds_every_entry_once_in_its_new_place() {
        // A 4x4 arrow matrix with distinct values, reversed.
        let mut a = CsrMatrix::from_pattern(4, (0..4).flat_map(|i| [(i, i), (i, 0), (0, i)]));
        for r in 0..4 {
            for k in a.row_ptr[r]..a.row_ptr[r + 1] {
                let c = a.col_idx[k] as usize;
                a.values[k] = (10 * r.max(c) + r.min(c)) as f64;
            }
        }
        let lower = LowerPattern::new(&a);
        let inv = [3, 2, 1, 0];
        let p = PermutedLower::new(&lower, &inv);
        let mut values = vec![0.0; p.source.len()];
        p.gather(&a.values, &mut values);
        // Old (i, j) lands at new (3 - i, 3 - j), stored in the lower triangle.
        for c in 0..4 {
            let range = p.col_ptr[c]..p.col_ptr[c + 1];
            for (&r, &v) in p.row_idx[range.clone()].iter().zip(&values[range]) {
                assert!(r >= c);
                let (oi, oj) = (3 - c, 3 - r);
                assert_eq!(v, (10 * oi.max(oj) + oi.min(oj)) as f64);
            }
            assert_eq!(p.diag[c].map(|k| p.row_idx[k]), Some(c));
        }
        assert_eq!(p.row_idx.len(), lower.row_idx.len());
    }
}
