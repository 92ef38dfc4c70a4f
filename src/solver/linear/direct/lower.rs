//! The lower triangle the Cholesky factor is computed from, without the
//! couplings of identity rows.
//!
//! The Newton matrix keeps one sparsity pattern for a whole relaxation
//! step, and the rows it cancels (pinned coordinates, the Lagrangian
//! coordinates of EIL nodes: `solver::assembly`) stay in that pattern as
//! explicit zeros around a diagonal 1. A factorization of the full pattern
//! carries their fill: after three steps of a 40x40 linen stitch, 11864 of
//! 63612 rows are cancelled, and leaving out their couplings shrinks the
//! factor from 8.17M to 5.30M entries and the numeric factorization from
//! 0.126 to 0.100 s (a temporary example, not kept).
//!
//! A row counts as an identity row when its diagonal is exactly 1 and every
//! other entry exactly 0 in the matrix the analysis is built from. The
//! couplings left out are then remembered as CSR slots, and every later
//! matrix is checked to hold exact zeros there ([`LowerPattern::fits`])
//! before the analysis is reused; otherwise it is rebuilt. So the factor is
//! always the factor of the matrix passed in.

use crate::sparse::CsrMatrix;

/// CSC lower triangle of a symmetric `CsrMatrix` (row `j` restricted to
/// columns `>= j` is column `j`), minus the couplings of identity rows.
pub(super) struct LowerPattern {
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
    /// `lower[k]` is the position in `CsrMatrix::values` of lower entry `k`.
    pub source: Vec<usize>,
    /// Position in the lower values of each column's diagonal (for shifts).
    pub diag: Vec<Option<usize>>,
    /// CSR slots of the lower entries left out; they must stay exactly 0.
    pub dropped: Vec<usize>,
}

/// True when row `r` of `a` is a row of the identity matrix.
fn is_identity_row(a: &CsrMatrix, r: usize) -> bool {
    let mut has_unit_diagonal = false;
    for k in a.row_ptr[r]..a.row_ptr[r + 1] {
        let v = a.values[k];
        if a.col_idx[k] as usize == r {
            has_unit_diagonal = v == 1.0;
        } else if v != 0.0 {
            return false;
        }
    }
    has_unit_diagonal
}

impl LowerPattern {
    pub fn new(a: &CsrMatrix) -> Self {
        let n = a.n;
        let identity: Vec<bool> = (0..n).map(|r| is_identity_row(a, r)).collect();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut source = Vec::new();
        let mut diag = vec![None; n];
        let mut dropped = Vec::new();
        col_ptr.push(0);
        for (j, d) in diag.iter_mut().enumerate() {
            for k in a.row_ptr[j]..a.row_ptr[j + 1] {
                let i = a.col_idx[k] as usize;
                if i < j {
                    continue;
                }
                if i == j {
                    *d = Some(row_idx.len());
                } else if identity[i] || identity[j] {
                    dropped.push(k);
                    continue;
                }
                row_idx.push(i);
                source.push(k);
            }
            col_ptr.push(row_idx.len());
        }
        LowerPattern {
            col_ptr,
            row_idx,
            source,
            diag,
            dropped,
        }
    }

    /// The diagonal of `a` (of the pattern this was built from) through
    /// the cached slots, not a search per row (`CsrMatrix::diagonal`); a
    /// structurally missing diagonal counts as 0.
    pub fn diagonal<'a>(&'a self, a: &'a CsrMatrix) -> impl Iterator<Item = f64> + 'a {
        self.diag.iter().map(|d| d.map_or(0.0, |k| a.values[self.source[k]]))
    }

    /// Whether `a` (of the pattern this was built from) is zero wherever
    /// this left an entry out, so a factor of the kept entries is a factor of `a`.
    pub fn fits(&self, a: &CsrMatrix) -> bool {
        self.dropped.iter().all(|&k| a.values[k] == 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4x4 tridiagonal matrix whose row 1 has been cancelled (identity).
    fn cancelled_row_one() -> CsrMatrix {
        let mut a = CsrMatrix::from_pattern(4, (0..4).flat_map(|i| [(i, i), (i, (i + 1) % 4), ((i + 1) % 4, i)]));
        for r in 0..4 {
            for k in a.row_ptr[r]..a.row_ptr[r + 1] {
                let c = a.col_idx[k] as usize;
                a.values[k] = if r == c { 4.0 } else { -1.0 };
                if r == 1 || c == 1 {
                    a.values[k] = if r == c { 1.0 } else { 0.0 };
                }
            }
        }
        a
    }

    #[test]
    fn an_identity_row_keeps_its_diagonal_and_loses_its_couplings() {
        let a = cancelled_row_one();
        let lower = LowerPattern::new(&a);
        // Kept: every diagonal, (3, 0) and (3, 2); dropped: (1, 0) and (2, 1).
        assert_eq!(lower.col_ptr, vec![0, 2, 3, 5, 6]);
        assert_eq!(lower.row_idx, vec![0, 3, 1, 2, 3, 3]);
        assert_eq!(lower.dropped.len(), 2);
        assert!(lower.diag.iter().all(Option::is_some));
        assert!(lower.fits(&a));
    }

    #[test]
    fn a_value_where_an_entry_was_left_out_no_longer_fits() {
        let mut a = cancelled_row_one();
        let lower = LowerPattern::new(&a);
        // Lower entry (2, 1) is read from CSR row 1 (column j is row j from the diagonal on).
        let k = a.find(1, 2).unwrap();
        a.values[k] = 1e-300;
        assert!(!lower.fits(&a));
    }

    #[test]
    fn rows_that_only_look_cancelled_are_kept() {
        // A zero row (diagonal 0) and a scaled one (diagonal 2) are not identity rows.
        let mut a = cancelled_row_one();
        let k = a.find(1, 1).unwrap();
        a.values[k] = 2.0;
        assert!(LowerPattern::new(&a).dropped.is_empty());
        a.values[k] = 0.0;
        assert!(LowerPattern::new(&a).dropped.is_empty());
    }
}
