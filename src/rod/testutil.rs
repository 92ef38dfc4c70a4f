//! Shared helpers for the rod tests: a tiny deterministic generator (the
//! crate has no `rand`), so failures reproduce exactly.

use nalgebra::{SVector, Vector3};

/// SplitMix64: small, well-mixed, deterministic.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    pub fn vec3(&mut self, scale: f64) -> Vector3<f64> {
        Vector3::new(
            self.range(-scale, scale),
            self.range(-scale, scale),
            self.range(-scale, scale),
        )
    }

    pub fn vector<const N: usize>(&mut self, scale: f64) -> SVector<f64, N> {
        SVector::<f64, N>::from_fn(|_, _| self.range(-scale, scale))
    }

    /// A random unit vector orthogonal to `v`.
    pub fn orthogonal_unit(&mut self, v: &Vector3<f64>) -> Vector3<f64> {
        loop {
            let r = self.vec3(1.0);
            let p = r - v * (r.dot(v) / v.norm_squared());
            if p.norm() > 1e-3 {
                return p.normalize();
            }
        }
    }
}

/// Writes a 3-vector into a local vector at `at`.
pub fn put3<const N: usize>(q: &mut SVector<f64, N>, at: usize, v: &Vector3<f64>) {
    q.fixed_rows_mut::<3>(at).copy_from(v);
}

#[track_caller]
pub fn assert_all_finite<const N: usize, S: crate::energy::Stencil<N>>(s: &S, q: &SVector<f64, N>) {
    assert!(s.value(q).is_finite(), "non-finite value at {q:?}");
    assert!(
        s.gradient(q).iter().all(|v| v.is_finite()),
        "non-finite gradient at {q:?}"
    );
    assert!(
        s.hessian(q).iter().all(|v| v.is_finite()),
        "non-finite Hessian at {q:?}"
    );
}
