//! Compressed sparse row storage for the symmetric Newton matrix.
//!
//! Both triangles are stored: the CG and the GPU SpMV then need no transpose
//! logic, and the direct solver takes the lower triangle when it converts.
//! The pattern is built once per node assignment and only `values` are
//! refilled each Newton iteration.

/// A square sparse matrix in CSR form, column indices sorted within a row.
#[derive(Clone, Debug, PartialEq)]
pub struct CsrMatrix {
    pub n: usize,
    pub row_ptr: Vec<usize>,
    pub col_idx: Vec<u32>,
    pub values: Vec<f64>,
}

impl CsrMatrix {
    /// Builds the pattern from (row, col) entries; duplicates merge, values are zero.
    pub fn from_pattern(n: usize, entries: impl IntoIterator<Item = (u32, u32)>) -> Self {
        let mut rows: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (r, c) in entries {
            rows[r as usize].push(c);
        }
        let mut row_ptr = Vec::with_capacity(n + 1);
        let mut col_idx = Vec::new();
        row_ptr.push(0);
        for mut r in rows {
            r.sort_unstable();
            r.dedup();
            col_idx.extend_from_slice(&r);
            row_ptr.push(col_idx.len());
        }
        let nnz = col_idx.len();
        CsrMatrix {
            n,
            row_ptr,
            col_idx,
            values: vec![0.0; nnz],
        }
    }

    /// Position of entry (r, c) in `values`, if it is in the pattern.
    pub fn find(&self, r: usize, c: usize) -> Option<usize> {
        let row = &self.col_idx[self.row_ptr[r]..self.row_ptr[r + 1]];
        row.binary_search(&(c as u32)).ok().map(|k| self.row_ptr[r] + k)
    }

    pub fn nnz(&self) -> usize {
        self.col_idx.len()
    }

    /// y = A x
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        for (r, yr) in y.iter_mut().enumerate().take(self.n) {
            let (a, b) = (self.row_ptr[r], self.row_ptr[r + 1]);
            *yr = self.values[a..b]
                .iter()
                .zip(&self.col_idx[a..b])
                .map(|(v, &c)| v * x[c as usize])
                .sum();
        }
    }

    /// r = b - A x
    pub fn residual(&self, x: &[f64], b: &[f64], r: &mut [f64]) {
        self.mul_vec(x, r);
        for (ri, bi) in r.iter_mut().zip(b) {
            *ri = bi - *ri;
        }
    }

    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n)
            .map(|r| self.find(r, r).map_or(0.0, |k| self.values[k]))
            .collect()
    }
}

/// Euclidean inner product of two vectors of the global system.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_merges_duplicates_and_multiplies() {
        let mut a = CsrMatrix::from_pattern(3, [(0, 0), (0, 1), (1, 0), (1, 1), (2, 2), (0, 1)]);
        assert_eq!(a.nnz(), 5);
        for (r, c, v) in [(0, 0, 2.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 2.0), (2, 2, 3.0)] {
            let k = a.find(r, c).unwrap();
            a.values[k] = v;
        }
        let mut y = [0.0; 3];
        a.mul_vec(&[1.0, 2.0, 3.0], &mut y);
        assert_eq!(y, [0.0, 3.0, 9.0]);
        assert_eq!(a.diagonal(), vec![2.0, 2.0, 3.0]);
        assert!(a.find(2, 0).is_none());
    }
}
