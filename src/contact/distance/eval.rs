//! One closed form for every distance type, with exact derivatives.
//!
//! Each type is a difference of two points that are affine in the
//! coordinates and in `k <= 2` free parameters `tau` (position along an
//! edge): `r(x, tau) = sum_i c_i(tau) x_i`, with `c(tau) = c0 + sum_j tau_j
//! dir_j`. Its squared distance is `f(x) = min_tau g(x, tau)`,
//! `g = |r|^2`. At the (interior) minimiser, by the envelope theorem and
//! implicit differentiation of `g_tau = 0`,
//!
//! ```text
//!   grad f = g_x = 2 c_i r                      (block i)
//!   hess f = g_xx - g_x,tau (g_tau,tau)^-1 g_tau,x
//! ```
//!
//! with `g_xx = 2 (c c^T) (x) I3`, `g_tau_j tau_l = 2 D_j . D_l` and
//! `g_tau_j,x_i = 2 (c_i D_j + dir_j,i r)` where `D_j = sum_i dir_j,i x_i`
//! is the edge direction the parameter moves along. This covers
//! point-point (`k = 0`), point-line (`k = 1`) and line-line (`k = 2`)
//! without three hand-expanded Hessians.

use nalgebra::{SMatrix, SVector, Vector3};

/// Squared distance and its derivatives on `N = 3 M` coordinates.
#[derive(Clone, Copy, Debug)]
pub struct DistanceDerivs<const N: usize> {
    pub value: f64,
    pub gradient: SVector<f64, N>,
    pub hessian: SMatrix<f64, N, N>,
}

impl<const N: usize> DistanceDerivs<N> {
    /// Unsquared distance `d = sqrt(d^2)` by the chain rule. Requires `d > 0`.
    pub fn sqrt(&self) -> Self {
        let d = self.value.sqrt();
        let g = self.gradient / (2.0 * d);
        let hessian = self.hessian / (2.0 * d) - g * g.transpose() / d;
        Self {
            value: d,
            gradient: g,
            hessian,
        }
    }
}

/// A distance type as coefficient vectors over the `M` points.
pub(super) struct AffinePair<const M: usize> {
    pub c0: [f64; M],
    /// Directions of the free parameters; the first `k` are used.
    pub dirs: [[f64; M]; 2],
    pub k: usize,
}

fn combine<const M: usize>(x: &[Vector3<f64>; M], c: &[f64; M]) -> Vector3<f64> {
    let mut r = Vector3::zeros();
    for (xi, ci) in x.iter().zip(c) {
        r += xi * *ci;
    }
    r
}

/// Evaluates `f`, `grad f`, `hess f` for a type at given parameters `tau`
/// (the caller computes them with a formula suited to the type) and the
/// inverse of the parameter Gram matrix `G_jl = D_j . D_l`.
pub(super) fn evaluate<const M: usize, const N: usize>(
    x: &[Vector3<f64>; M],
    pair: &AffinePair<M>,
    tau: &[f64],
    gram_inv: &[[f64; 2]; 2],
) -> DistanceDerivs<N> {
    debug_assert_eq!(N, 3 * M);
    let mut c = pair.c0;
    for (dir, t) in pair.dirs[..pair.k].iter().zip(tau) {
        for i in 0..M {
            c[i] += t * dir[i];
        }
    }
    let r = combine(x, &c);
    let mut gradient = SVector::<f64, N>::zeros();
    let mut hessian = SMatrix::<f64, N, N>::zeros();
    for i in 0..M {
        gradient.fixed_rows_mut::<3>(3 * i).copy_from(&(r * (2.0 * c[i])));
        for j in 0..M {
            let cc = 2.0 * c[i] * c[j];
            for k in 0..3 {
                hessian[(3 * i + k, 3 * j + k)] = cc;
            }
        }
    }
    // Mixed derivatives g_tau_j,x as full-length vectors.
    let mut mixed = [SVector::<f64, N>::zeros(); 2];
    for (dir, b) in pair.dirs[..pair.k].iter().zip(mixed.iter_mut()) {
        let dj = combine(x, dir);
        for i in 0..M {
            b.fixed_rows_mut::<3>(3 * i)
                .copy_from(&((dj * c[i] + r * dir[i]) * 2.0));
        }
    }
    // (g_tau,tau)^-1 = G^-1 / 2.
    let mixed = &mixed[..pair.k];
    for (j, bj) in mixed.iter().enumerate() {
        for (l, bl) in mixed.iter().enumerate() {
            hessian -= bj * bl.transpose() * (0.5 * gram_inv[j][l]);
        }
    }
    DistanceDerivs {
        value: r.norm_squared(),
        gradient,
        hessian,
    }
}
