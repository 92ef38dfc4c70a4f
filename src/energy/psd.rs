//! Projection of a local Hessian onto the positive semi-definite cone.
//!
//! Newton needs a descent direction; a stencil's exact Hessian can be
//! indefinite (bending past straight, a stretched spring's transverse modes,
//! barriers). Clamping each stencil's negative eigenvalues to zero keeps the
//! assembled matrix PSD at the cost of a slightly worse model. Cyclic Jacobi
//! is used because it works for any `N` without trait gymnastics and is
//! accurate for the small (<= 24) matrices stencils produce.

use nalgebra::SMatrix;

/// Symmetric eigen-decomposition by cyclic Jacobi: returns (eigenvalues, eigenvectors as columns).
pub fn sym_eigen<const N: usize>(m: &SMatrix<f64, N, N>) -> ([f64; N], SMatrix<f64, N, N>) {
    let mut a = (m + m.transpose()) * 0.5;
    let mut v = SMatrix::<f64, N, N>::identity();
    let scale = a.norm().max(f64::MIN_POSITIVE);
    for _sweep in 0..60 {
        let mut off = 0.0;
        for p in 0..N {
            for q in p + 1..N {
                off += a[(p, q)] * a[(p, q)];
            }
        }
        if off.sqrt() <= 1e-15 * scale {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                let apq = a[(p, q)];
                if apq.abs() <= 1e-300 {
                    continue;
                }
                let theta = (a[(q, q)] - a[(p, p)]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..N {
                    let akp = a[(k, p)];
                    let akq = a[(k, q)];
                    a[(k, p)] = c * akp - s * akq;
                    a[(k, q)] = s * akp + c * akq;
                }
                for k in 0..N {
                    let apk = a[(p, k)];
                    let aqk = a[(q, k)];
                    a[(p, k)] = c * apk - s * aqk;
                    a[(q, k)] = s * apk + c * aqk;
                }
                for k in 0..N {
                    let vkp = v[(k, p)];
                    let vkq = v[(k, q)];
                    v[(k, p)] = c * vkp - s * vkq;
                    v[(k, q)] = s * vkp + c * vkq;
                }
            }
        }
    }
    let mut ev = [0.0; N];
    for (i, e) in ev.iter_mut().enumerate() {
        *e = a[(i, i)];
    }
    (ev, v)
}

/// Returns the nearest PSD matrix (negative eigenvalues clamped to zero).
pub fn project_psd<const N: usize>(m: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    let (ev, v) = sym_eigen(m);
    if ev.iter().all(|&e| e >= 0.0) {
        return (m + m.transpose()) * 0.5;
    }
    let mut out = SMatrix::<f64, N, N>::zeros();
    for (i, &e) in ev.iter().enumerate() {
        if e > 0.0 {
            let c = v.column(i);
            out += c * c.transpose() * e;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    #[test]
    fn reconstructs_and_clamps() {
        let m = Matrix3::new(2.0, 1.0, 0.0, 1.0, -3.0, 0.5, 0.0, 0.5, 1.0);
        let (ev, v) = sym_eigen(&m);
        let d = Matrix3::from_diagonal(&nalgebra::Vector3::from(ev));
        assert!((v * d * v.transpose() - m).norm() < 1e-12);
        let p = project_psd(&m);
        let (evp, _) = sym_eigen(&p);
        assert!(evp.iter().all(|&e| e > -1e-12));
        // Compare to nalgebra's own eigen-solver: the projection keeps positive modes.
        let se = m.symmetric_eigen();
        let mut expect = Matrix3::zeros();
        for i in 0..3 {
            if se.eigenvalues[i] > 0.0 {
                let c = se.eigenvectors.column(i);
                expect += c * c.transpose() * se.eigenvalues[i];
            }
        }
        assert!((p - expect).norm() < 1e-10);
    }
}
