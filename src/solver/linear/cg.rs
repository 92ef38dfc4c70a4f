//! Preconditioned conjugate gradients with a block-Jacobi preconditioner.
//!
//! Why block-Jacobi: the Newton matrix couples the three components of a node
//! strongly (stretch along a segment direction), so inverting 3x3 node blocks
//! removes most of the anisotropy a scalar Jacobi leaves. Blocks are given as
//! a partition of the unknowns (node `x` blocks of 3, material `u` blocks of 1),
//! so the preconditioner knows nothing of the EoL layout. The GPU solver
//! implements exactly this algorithm in f32; this f64 version is its reference.

use crate::sparse::{dot, BlockJacobi, CgResult, CsrMatrix};

#[derive(Clone, Copy, Debug)]
pub struct CgParams {
    /// Stop when `|r| <= rel_tol * |b|`. The default 1e-10 is tight on
    /// purpose: with friction the relaxed fabric depends on the Newton path,
    /// and a looser solve changes it (the 4x4 stockinette swatch ends 1.4%
    /// of a radius from cpu-direct at 1e-8, 7e-8 of a radius at 1e-11, for
    /// 10% more time; docs/GPU.md, "Parity test").
    pub rel_tol: f64,
    pub max_iter: usize,
}

impl Default for CgParams {
    fn default() -> Self {
        CgParams {
            rel_tol: 1e-10,
            max_iter: 10_000,
        }
    }
}

/// Solves `A x = b` for symmetric positive (semi-)definite `A`, starting from `x`.
pub fn pcg(a: &CsrMatrix, b: &[f64], x: &mut [f64], pre: &BlockJacobi, p: CgParams) -> CgResult {
    let n = a.n;
    let mut r = vec![0.0; n];
    a.residual(x, b, &mut r);
    let bn = dot(b, b).sqrt().max(f64::MIN_POSITIVE);
    let mut z = vec![0.0; n];
    pre.apply(&r, &mut z);
    let mut d = z.clone();
    let mut rz = dot(&r, &z);
    let mut ad = vec![0.0; n];
    let mut rel = dot(&r, &r).sqrt() / bn;
    for it in 0..p.max_iter {
        if rel <= p.rel_tol {
            return CgResult {
                iterations: it,
                rel_residual: rel,
                converged: true,
            };
        }
        a.mul_vec(&d, &mut ad);
        let dad = dot(&d, &ad);
        if dad <= 0.0 || !dad.is_finite() {
            // Direction of non-positive curvature: the matrix is not PD here.
            return CgResult {
                iterations: it,
                rel_residual: rel,
                converged: false,
            };
        }
        let alpha = rz / dad;
        for i in 0..n {
            x[i] += alpha * d[i];
            r[i] -= alpha * ad[i];
        }
        pre.apply(&r, &mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..n {
            d[i] = z[i] + beta * d[i];
        }
        rel = dot(&r, &r).sqrt() / bn;
    }
    CgResult {
        iterations: p.max_iter,
        rel_residual: rel,
        converged: rel <= p.rel_tol,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1D Laplacian plus a shift: SPD with a known exact solution.
    fn laplacian(n: usize) -> CsrMatrix {
        let mut e = Vec::new();
        for i in 0..n as u32 {
            e.push((i, i));
            if i > 0 {
                e.push((i, i - 1));
                e.push((i - 1, i));
            }
        }
        let mut a = CsrMatrix::from_pattern(n, e);
        for i in 0..n {
            for k in a.row_ptr[i]..a.row_ptr[i + 1] {
                a.values[k] = if a.col_idx[k] as usize == i {
                    2.0 + 0.01 * (i % 7) as f64
                } else {
                    -1.0
                };
            }
        }
        a
    }

    #[test]
    fn solves_to_tolerance_against_dense_solve() {
        let n = 60;
        let a = laplacian(n);
        let b: Vec<f64> = (0..n).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
        let dense = nalgebra::DMatrix::from_fn(n, n, |r, c| a.find(r, c).map_or(0.0, |k| a.values[k]));
        let exact = dense.lu().solve(&nalgebra::DVector::from_vec(b.clone())).unwrap();
        for pre in [
            BlockJacobi::diagonal(&a),
            BlockJacobi::new(&a, &(0..=n).step_by(3).collect::<Vec<_>>()),
        ] {
            let mut x = vec![0.0; n];
            let res = pcg(
                &a,
                &b,
                &mut x,
                &pre,
                CgParams {
                    rel_tol: 1e-12,
                    max_iter: 500,
                },
            );
            assert!(res.converged, "{res:?}");
            let err = x
                .iter()
                .zip(exact.iter())
                .map(|(u, v)| (u - v).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-8, "max error {err}");
        }
    }
}
