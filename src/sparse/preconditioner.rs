//! The block-Jacobi preconditioner of the conjugate-gradient solvers: the
//! inverted diagonal blocks of a symmetric matrix, applied on the host by
//! `solver::linear::cg` and uploaded to the device by `gpu`.

use super::CsrMatrix;
use nalgebra::DMatrix;

/// Inverted diagonal blocks of a symmetric matrix.
#[derive(Clone, Debug)]
pub struct BlockJacobi {
    /// Start of each block; a final entry equal to `n` closes the last one.
    pub starts: Vec<usize>,
    /// Row-major inverse of each block, concatenated.
    pub inv: Vec<f64>,
    offsets: Vec<usize>,
}

impl BlockJacobi {
    /// `starts` must be increasing, begin at 0 and end at `a.n`.
    /// A block that is singular falls back to the inverse of its diagonal.
    pub fn new(a: &CsrMatrix, starts: &[usize]) -> Self {
        let mut inv = Vec::new();
        let mut offsets = Vec::with_capacity(starts.len());
        for w in starts.windows(2) {
            let (s, e) = (w[0], w[1]);
            let m = e - s;
            offsets.push(inv.len());
            let mut b = DMatrix::<f64>::zeros(m, m);
            for r in 0..m {
                for c in 0..m {
                    b[(r, c)] = a.find(s + r, s + c).map_or(0.0, |k| a.values[k]);
                }
            }
            let bi = b
                .clone()
                .try_inverse()
                .filter(|bi| bi.iter().all(|v| v.is_finite()))
                .unwrap_or_else(|| {
                    DMatrix::from_diagonal(&b.diagonal().map(|d| if d.abs() > 0.0 { 1.0 / d } else { 1.0 }))
                });
            for r in 0..m {
                for c in 0..m {
                    inv.push(bi[(r, c)]);
                }
            }
        }
        offsets.push(inv.len());
        BlockJacobi {
            starts: starts.to_vec(),
            inv,
            offsets,
        }
    }

    /// Scalar blocks: plain Jacobi.
    pub fn diagonal(a: &CsrMatrix) -> Self {
        let starts: Vec<usize> = (0..=a.n).collect();
        Self::new(a, &starts)
    }

    /// z = P^-1 r
    pub fn apply(&self, r: &[f64], z: &mut [f64]) {
        for (bi, w) in self.starts.windows(2).enumerate() {
            let (s, m) = (w[0], w[1] - w[0]);
            let blk = &self.inv[self.offsets[bi]..self.offsets[bi + 1]];
            for i in 0..m {
                z[s + i] = (0..m).map(|j| blk[i * m + j] * r[s + j]).sum();
            }
        }
    }
}
