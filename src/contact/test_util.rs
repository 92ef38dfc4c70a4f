//! Shared test inputs: a tiny deterministic RNG and yarn-like segment soups.

use nalgebra::Vector3;

/// Deterministic pseudo-random numbers in [0, 1) (xorshift64).
pub struct Rng(pub u64);

impl Rng {
    /// Seeds by a multiplicative hash so that small seeds start well mixed.
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1)
    }

    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Random yarn-like polylines: `yarns` walks of `len` segments with step
/// `step` and a slowly turning direction, in a box of side `side`.
pub fn polyline_soup(
    seed: u64,
    yarns: usize,
    len: usize,
    step: f64,
    side: f64,
) -> (Vec<Vector3<f64>>, Vec<[usize; 2]>) {
    let mut rng = Rng::new(seed);
    let mut x = Vec::new();
    let mut segs = Vec::new();
    for _ in 0..yarns {
        let mut p = Vector3::new(rng.next(), rng.next(), rng.next()) * side;
        let mut dir = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
        x.push(p);
        for _ in 0..len {
            let turn = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5) * 0.6;
            dir = (dir + turn).normalize();
            p += dir * step;
            x.push(p);
            segs.push([x.len() - 2, x.len() - 1]);
        }
    }
    (x, segs)
}
