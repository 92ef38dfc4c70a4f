//! Additive continuous collision detection (Li et al. 2021, "Codimensional
//! IPC", sec. 5): a conservative time of impact for linear trajectories,
//! used to cap the line-search step so no pair ever gets closer than its
//! hard core (docs/MODEL.md, "Thickness contact").
//!
//! Why it is conservative: after removing the mean displacement of the
//! stencil (a rigid translation does not change distances), the relative
//! motion of any two points of the pair is bounded by
//! `l = max_A |dx| + max_B |dx|` per unit time. So the distance cannot fall
//! by more than `l t` in time `t`, and advancing by
//! `t_k = s (d_k - xi) / l` (with `s < 1`) can never cross the separation
//! `xi`. The steps are added up until the remaining gap `d - xi` falls below
//! `(1 - s)` of the initial one; the time reached *before* the last step is
//! returned, which is always earlier than the true impact.
//!
//! The distances are taken as `(d^2 - xi^2) / (d + xi)` (= `d - xi`), as in
//! the paper, so the squared distances of [`super::distance`] serve directly.

use super::distance::{edge_edge_distance_sq, point_edge_distance_sq};
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// Additive CCD settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CcdParams {
    /// Fraction `s` of the remaining gap a step may close (C-IPC and ipctk: 0.9).
    pub conservative_rescaling: f64,
    /// Safety cap on iterations; hitting it returns the (still conservative)
    /// time reached so far.
    pub max_iterations: usize,
}

impl Default for CcdParams {
    fn default() -> Self {
        Self {
            conservative_rescaling: 0.9,
            max_iterations: 1_000_000,
        }
    }
}

/// Core loop on `M` points split into two groups (`split` = size of the first).
fn additive<const M: usize>(
    x0: &[V3; M],
    dx: &[V3; M],
    split: usize,
    min_separation: f64,
    params: &CcdParams,
    distance_sq: impl Fn(&[V3; M]) -> f64,
) -> f64 {
    let mean = dx.iter().sum::<V3>() / M as f64;
    let rel: [V3; M] = std::array::from_fn(|i| dx[i] - mean);
    let max_norm = |r: &[V3]| r.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let bound = max_norm(&rel[..split]) + max_norm(&rel[split..]);
    if bound == 0.0 {
        return 1.0;
    }
    let xi = min_separation;
    let s = params.conservative_rescaling;
    let gap_of = |x: &[V3; M]| {
        let d_sq = distance_sq(x);
        (d_sq - xi * xi) / (d_sq.sqrt() + xi)
    };
    let mut x = *x0;
    let mut gap = gap_of(&x);
    if gap <= 0.0 {
        return 0.0;
    }
    let target = (1.0 - s) * gap;
    let mut toi = 0.0;
    for _ in 0..params.max_iterations {
        let step = s * gap / bound;
        for (xi_, r) in x.iter_mut().zip(&rel) {
            *xi_ += r * step;
        }
        gap = gap_of(&x);
        if toi > 0.0 && gap < target {
            return toi;
        }
        toi += step;
        if toi > 1.0 {
            return 1.0;
        }
    }
    toi
}

/// Conservative time of impact in `[0, 1]` of edges A `(a0, a1)` and B
/// `(b0, b1)` moving linearly by `d*`, with minimum separation
/// `min_separation` (the hard core `eta`). 1 means no impact in the step.
#[allow(clippy::too_many_arguments)]
pub fn edge_edge_toi(
    [a0, a1, b0, b1]: [&V3; 4],
    [da0, da1, db0, db1]: [&V3; 4],
    min_separation: f64,
    params: &CcdParams,
) -> f64 {
    additive(
        &[*a0, *a1, *b0, *b1],
        &[*da0, *da1, *db0, *db1],
        2,
        min_separation,
        params,
        |x| edge_edge_distance_sq(&x[0], &x[1], &x[2], &x[3]),
    )
}

/// Conservative time of impact of point `p` and edge `(e0, e1)`.
pub fn point_edge_toi([p, e0, e1]: [&V3; 3], [dp, de0, de1]: [&V3; 3], min_separation: f64, params: &CcdParams) -> f64 {
    additive(&[*p, *e0, *e1], &[*dp, *de0, *de1], 1, min_separation, params, |x| {
        point_edge_distance_sq(&x[0], &x[1], &x[2])
    })
}

/// Largest step fraction in `[0, 1]` such that no candidate pair comes
/// closer than its minimum separation: the smallest time of impact.
/// `pairs` lists segment pairs with their minimum separation.
pub fn max_step_fraction(
    x: &[V3],
    dx: &[V3],
    segments: &[[usize; 2]],
    pairs: &[([u32; 2], f64)],
    params: &CcdParams,
) -> f64 {
    pairs.iter().fold(1.0, |best: f64, &([i, j], xi)| {
        let (a, b) = (segments[i as usize], segments[j as usize]);
        let toi = edge_edge_toi(
            [&x[a[0]], &x[a[1]], &x[b[0]], &x[b[1]]],
            [&dx[a[0]], &dx[a[1]], &dx[b[0]], &dx[b[1]]],
            xi,
            params,
        );
        best.min(toi)
    })
}

#[cfg(test)]
mod tests;
