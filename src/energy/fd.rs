//! Finite-difference checks for stencils, used by every energy's tests.
//!
//! Central differences with a relative step: the gradient is checked against
//! differences of `value`, the Hessian against differences of `gradient`.
//! Errors are measured relative to the larger of the two norms (plus a floor)
//! so the check is meaningful for both stiff and soft terms.

use super::Stencil;
use nalgebra::{SMatrix, SVector};

/// Numerical gradient of `s.value` at `x` with step `h`.
pub fn fd_gradient<const N: usize, S: Stencil<N>>(s: &S, x: &SVector<f64, N>, h: f64) -> SVector<f64, N> {
    let mut g = SVector::<f64, N>::zeros();
    for i in 0..N {
        let mut xp = *x;
        let mut xm = *x;
        xp[i] += h;
        xm[i] -= h;
        g[i] = (s.value(&xp) - s.value(&xm)) / (2.0 * h);
    }
    g
}

/// Numerical Hessian from differences of `s.gradient`, symmetrised.
pub fn fd_hessian<const N: usize, S: Stencil<N>>(s: &S, x: &SVector<f64, N>, h: f64) -> SMatrix<f64, N, N> {
    let mut hm = SMatrix::<f64, N, N>::zeros();
    for i in 0..N {
        let mut xp = *x;
        let mut xm = *x;
        xp[i] += h;
        xm[i] -= h;
        let col = (s.gradient(&xp) - s.gradient(&xm)) / (2.0 * h);
        hm.set_column(i, &col);
    }
    (hm + hm.transpose()) * 0.5
}

/// Relative error `|a - b| / max(|a|, |b|, floor)`.
pub fn rel_err(a: f64, b: f64, floor: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(floor)
}

/// Asserts analytic gradient and Hessian agree with finite differences.
/// `h` is the FD step; `tol` the allowed relative error (in Frobenius norm).
#[track_caller]
pub fn check_derivatives<const N: usize, S: Stencil<N>>(s: &S, x: &SVector<f64, N>, h: f64, tol: f64) {
    let g = s.gradient(x);
    let gf = fd_gradient(s, x, h);
    let floor = 1e-8;
    let eg = (g - gf).norm() / g.norm().max(gf.norm()).max(floor);
    assert!(g.iter().all(|v| v.is_finite()), "non-finite gradient at {x:?}: {g:?}");
    assert!(
        eg < tol,
        "gradient mismatch {eg:.3e} at x = {x:?}\n analytic {g:?}\n fd {gf:?}"
    );
    let hs = s.hessian(x);
    let hf = fd_hessian(s, x, h);
    assert!(hs.iter().all(|v| v.is_finite()), "non-finite Hessian at {x:?}");
    let eh = (hs - hf).norm() / hs.norm().max(hf.norm()).max(floor);
    assert!(
        eh < tol,
        "Hessian mismatch {eh:.3e} at x = {x:?}\n analytic {hs:?}\n fd {hf:?}"
    );
    assert!(
        (hs - hs.transpose()).norm() <= 1e-9 * hs.norm().max(1.0),
        "Hessian not symmetric"
    );
}
