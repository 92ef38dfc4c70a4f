//! nalgebra's symmetric eigen-decomposition (Householder tridiagonalisation,
//! then implicit QR with Wilkinson shifts), re-written on fixed-size arrays
//! so that it gives **the same bits** as `nalgebra::SymmetricEigen::try_new`,
//! and so that two decompositions can run interleaved ([`eigen_pair`]).
//!
//! Why: the PSD projection of every indefinite stencil Hessian runs one of
//! these per Newton iteration (18 000 8x8 bending blocks and 4 000 9x9
//! wrapping blocks on a 40x40 linen stitch, a quarter of a relaxation's
//! time). Each QR rotation is a chain of dependent square root, divisions
//! and products, about 60 cycles with little else to do, so one
//! decomposition leaves the core mostly idle; stepping two independent
//! ones alternately fills it (about 20% less time per 8x8 block, measured
//! by `examples/assembly_costs`). A faster *different* algorithm would
//! round differently, and the float patterns' iteration counts are chaotic
//! in the last bit (docs/RELAX.md, "PSD projections": two exact-in-theory
//! projections lengthened the 40x40 runs). So this port keeps every
//! floating-point operation of nalgebra 0.35 in its order; only storage,
//! loop bounds and control flow change. The tests compare it with nalgebra
//! bit for bit, so a nalgebra upgrade that changes its arithmetic fails
//! them.
//!
//! Only finite input is handled here; [`eigen`] returns `None` for
//! anything else, and for a QR that does not converge in `max_niter`
//! sweeps, exactly when nalgebra's `try_new` does (the caller falls back).
//!
//! Storage is column-major (`a[j][i]` is row `i` of column `j`), as
//! nalgebra's, so every column segment the algorithm reads is a slice, and
//! an `SMatrix`'s own array (`m.data.0`) is the input as it is.

/// Eigenvalues and eigenvectors (as columns), or `None`.
pub type Decomposition<const N: usize> = Option<([f64; N], [[f64; N]; N])>;

/// nalgebra's `dotc` of two equally long slices: eight partial sums over
/// whole chunks of eight, folded in pairs, then the tail one by one.
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len();
    let mut acc = [0.0f64; 8];
    let mut i = 0;
    while n - i >= 8 {
        for k in 0..8 {
            acc[k] += a[i + k] * b[i + k];
        }
        i += 8;
    }
    let mut res = 0.0;
    res += acc[0] + acc[4];
    res += acc[1] + acc[5];
    res += acc[2] + acc[6];
    res += acc[3] + acc[7];
    for k in i..n {
        res += a[k] * b[k];
    }
    res
}

/// `f64::to_exp` as simba defines it: `(|x|, sign)` with `+0` and `-0` both
/// of sign `+1`.
#[inline(always)]
fn to_exp(x: f64) -> (f64, f64) {
    // Branch-free: the sign of the Givens vector is a coin toss, and a
    // mispredicted branch here stalls the rotation chain.
    let neg = ((x < 0.0) as u64) << 63;
    (
        f64::from_bits(x.to_bits() ^ neg),
        f64::from_bits(1.0f64.to_bits() | neg),
    )
}

/// nalgebra's `SymmetricTridiagonal::new`: Householder reflections stored
/// below the sub-diagonal of `a`, the updated lower triangle in `a`, the
/// signed sub-diagonal returned.
fn tridiagonalize<const N: usize>(a: &mut [[f64; N]; N]) -> [f64; N] {
    std::array::from_fn(|i| if i + 1 < N { reflect_column(a, i) } else { 0.0 })
}

/// Step `i` of [`tridiagonalize`]: the reflection that clears column `i`
/// below its sub-diagonal, applied to the trailing block; returns the
/// signed sub-diagonal entry. Steps of two matrices interleave well (each
/// is a few chains of dependent sums, square roots and divisions).
#[inline(always)]
fn reflect_column<const N: usize>(a: &mut [[f64; N]; N], i: usize) -> f64 {
    // `reflection_axis_mut` on column i, rows i+1..N.
    let (left, right) = a.split_at_mut(i + 1);
    let axis = &mut left[i][i + 1..];
    let sq = dot(axis, axis);
    let norm = sq.sqrt();
    let (modulus, sign) = to_exp(axis[0]);
    let signed_norm = sign * norm;
    let factor = (sq + modulus * norm) * 2.0;
    axis[0] += signed_norm;
    if factor == 0.0 {
        return signed_norm;
    }
    let f = factor.sqrt();
    for v in axis.iter_mut() {
        *v /= f;
    }
    let n = dot(axis, axis).sqrt();
    for v in axis.iter_mut() {
        *v /= n;
    }
    let axis = &left[i][i + 1..];
    let m = right; // columns i+1..N; rows i+1..N of each are the block.
    let d = N - i - 1;
    let o = i + 1;
    // `p.hegemv(2, m, axis, 0)`: only the lower triangle of the block.
    let mut p = [0.0; N];
    let p = &mut p[..d];
    let alpha = 2.0;
    let val = axis[0];
    for r in 0..d {
        p[r] = alpha * val * m[0][o + r] * 1.0;
    }
    p[0] += alpha * dot(&m[0][o + 1..], &axis[1..]);
    for j in 1..d {
        let col = &m[j][o..];
        let dt = dot(&col[j..], &axis[j..]);
        let val = axis[j];
        p[j] += alpha * dt;
        let av = alpha * val;
        for r in j + 1..d {
            p[r] = av * col[r] * 1.0 + 1.0 * p[r];
        }
    }
    let dt = dot(axis, p);
    // Three `hegerc` rank-one updates of the lower triangle.
    let rank_one = |m: &mut [[f64; N]], alpha: f64, x: &[f64], y: &[f64]| {
        for j in 0..d {
            let av = alpha * y[j];
            let col = &mut m[j][o..];
            for r in j..d {
                col[r] = av * x[r] * 1.0 + 1.0 * col[r];
            }
        }
    };
    rank_one(m, -1.0, p, axis);
    rank_one(m, -1.0, axis, p);
    rank_one(m, dt * 2.0, axis, axis);
    -signed_norm
}

/// nalgebra's `householder::assemble_q` for the reflections `tridiagonalize`
/// left in `a`, with the signs of its sub-diagonal.
#[inline(always)]
fn assemble_q<const N: usize>(a: &[[f64; N]; N], signs: &[f64; N]) -> [[f64; N]; N] {
    let mut q = identity();
    for i in (0..N.saturating_sub(1)).rev() {
        reflect_q(&mut q, a, signs, i);
    }
    q
}

fn identity<const N: usize>() -> [[f64; N]; N] {
    let mut q = [[0.0; N]; N];
    for (j, col) in q.iter_mut().enumerate() {
        col[j] = 1.0;
    }
    q
}

/// Step `i` of [`assemble_q`] (they run from the last reflection down).
#[inline(always)]
fn reflect_q<const N: usize>(q: &mut [[f64; N]; N], a: &[[f64; N]; N], signs: &[f64; N], i: usize) {
    let axis = &a[i][i + 1..];
    let sign = if signs[i].is_sign_negative() { -1.0 } else { 1.0 };
    let m_two = sign * -2.0;
    for col in q[i..].iter_mut() {
        let col = &mut col[i + 1..];
        let factor = (dot(axis, col) - 0.0) * m_two;
        for (c, &x) in col.iter_mut().zip(axis) {
            *c = factor * x * 1.0 + sign * *c;
        }
    }
}

/// nalgebra's Wilkinson shift.
#[inline(always)]
fn wilkinson_shift(tmm: f64, tnn: f64, tmn: f64) -> f64 {
    let sq_tmn = tmn * tmn;
    if sq_tmn != 0.0 {
        let d = (tmm - tnn) * 0.5;
        tnn - sq_tmn / (d + d.signum() * (d * d + sq_tmn).sqrt())
    } else {
        tnn
    }
}

/// nalgebra's `delimit_subproblem`.
#[inline(always)]
fn delimit<const N: usize>(diag: &[f64; N], off: &mut [f64; N], end: usize, eps: f64) -> (usize, usize) {
    let mut n = end;
    while n > 0 {
        let m = n - 1;
        if off[m].abs() > eps * (diag[n].abs() + diag[m].abs()) {
            break;
        }
        n -= 1;
    }
    if n == 0 {
        return (0, 0);
    }
    let mut new_start = n - 1;
    while new_start > 0 {
        let m = new_start - 1;
        if off[m] == 0.0 || off[m].abs() <= eps * (diag[new_start].abs() + diag[m].abs()) {
            off[m] = 0.0;
            break;
        }
        new_start -= 1;
    }
    (new_start, n)
}

/// Rotates columns `i` and `i + 1` of `q` by `(c, s)` as nalgebra's
/// `GivensRotation::rotate_rows` does.
#[inline(always)]
fn rotate_columns<const N: usize>(q: &mut [[f64; N]; N], i: usize, c: f64, s: f64) {
    let (left, right) = q.split_at_mut(i + 1);
    for (a, b) in left[i].iter_mut().zip(right[0].iter_mut()) {
        let (x, y) = (*a, *b);
        *a = x * c + s * y;
        *b = -s * x + y * c;
    }
}

/// The matrix divided by its largest magnitude (nalgebra's `camax` and
/// `unscale_mut`), and that magnitude; `None` unless every entry is finite.
fn scaled<const N: usize>(m: &[[f64; N]; N]) -> Option<([[f64; N]; N], f64)> {
    // One pass for both: `f64::max` skips a NaN, so it is caught apart.
    let (amax, finite) = m
        .iter()
        .flatten()
        .fold((0.0f64, true), |(a, ok), v| (a.max(v.abs()), ok & v.is_finite()));
    if N == 0 || !finite {
        return None;
    }
    let mut a = *m;
    if amax != 0.0 {
        for v in a.iter_mut().flatten() {
            *v /= amax;
        }
    }
    Some((a, amax))
}

/// The implicit QR iteration of one matrix as a state machine that
/// advances one Givens rotation per [`step`](Self::step), so two of them
/// can run interleaved: a rotation is a chain of dependent square root,
/// divisions and products (about 50 cycles) with little else to do, and two
/// independent chains fill the core's pipelines where one leaves them idle.
struct QrLane<const N: usize> {
    diag: [f64; N],
    off: [f64; N],
    q: [[f64; N]; N],
    amax: f64,
    start: usize,
    end: usize,
    niter: usize,
    /// Inside a sweep: the next rotation's index and its vector `(vx, vy)`.
    sweep: Option<(usize, f64, f64)>,
    failed: bool,
}

impl<const N: usize> QrLane<N> {
    /// Scaling, tridiagonalisation and the first subproblem; `None` for
    /// non-finite input.
    fn new(m: &[[f64; N]; N], eps: f64) -> Option<Self> {
        let (mut a, amax) = scaled(m)?;
        let signed_off = tridiagonalize(&mut a);
        let q = assemble_q(&a, &signed_off);
        Some(Self::from_tridiagonal(&a, &signed_off, q, amax, eps))
    }

    /// Two lanes, their tridiagonalisations interleaved column by column.
    fn new_pair(ma: &[[f64; N]; N], mb: &[[f64; N]; N], eps: f64) -> Option<[Self; 2]> {
        let ((mut a, amax_a), (mut b, amax_b)) = (scaled(ma)?, scaled(mb)?);
        let (mut off_a, mut off_b) = ([0.0; N], [0.0; N]);
        for i in 0..N.saturating_sub(1) {
            off_a[i] = reflect_column(&mut a, i);
            off_b[i] = reflect_column(&mut b, i);
        }
        let (mut qa, mut qb) = (identity(), identity());
        for i in (0..N.saturating_sub(1)).rev() {
            reflect_q(&mut qa, &a, &off_a, i);
            reflect_q(&mut qb, &b, &off_b, i);
        }
        Some([
            Self::from_tridiagonal(&a, &off_a, qa, amax_a, eps),
            Self::from_tridiagonal(&b, &off_b, qb, amax_b, eps),
        ])
    }

    fn from_tridiagonal(a: &[[f64; N]; N], signed_off: &[f64; N], q: [[f64; N]; N], amax: f64, eps: f64) -> Self {
        let mut diag = [0.0; N];
        let mut off = [0.0; N];
        for i in 0..N {
            diag[i] = a[i][i];
            off[i] = signed_off[i].abs();
        }
        let (start, end) = if N == 1 {
            (0, 0)
        } else {
            delimit(&diag, &mut off, N - 1, eps)
        };
        QrLane {
            diag,
            off,
            q,
            amax,
            start,
            end,
            niter: 0,
            sweep: None,
            failed: false,
        }
    }

    fn running(&self) -> bool {
        self.end != self.start && !self.failed
    }

    /// One rotation of the current sweep, or the 2x2 subproblem, or the
    /// start of a sweep; nothing once converged or failed.
    #[inline(always)]
    fn step(&mut self, eps: f64, max_niter: usize) {
        if !self.running() {
            return;
        }
        let (start, end) = (self.start, self.end);
        let Some((i, vx, vy)) = self.sweep else {
            if end - start + 1 > 2 {
                let shift = wilkinson_shift(self.diag[end - 1], self.diag[end], self.off[end - 1]);
                self.sweep = Some((start, self.diag[start] - shift, self.off[start]));
            } else {
                self.solve_2x2(eps);
                self.end -= 1;
                self.next_subproblem(eps, max_niter);
            }
            return;
        };
        let n = end;
        // `GivensRotation::cancel_y`; a zero `vy` ends the sweep.
        let mut more = vy != 0.0;
        if more {
            let (diag, off) = (&mut self.diag, &mut self.off);
            let j = i + 1;
            let (mod0, sign0) = to_exp(vx);
            let denom = (mod0 * mod0 + vy * vy).sqrt();
            let c = mod0 / denom;
            let s = -vy / (sign0 * denom);
            let norm = sign0 * denom;
            if i > start {
                off[i - 1] = norm;
            }
            let (mii, mjj, mij) = (diag[i], diag[j], off[i]);
            let cc = c * c;
            let ss = s * s;
            let cs = c * s;
            let b = cs * 2.0 * mij;
            diag[i] = (cc * mii + ss * mjj) - b;
            diag[j] = (ss * mii + cc * mjj) + b;
            off[i] = cs * (mii - mjj) + mij * (cc - ss);
            more = i != n - 1;
            if more {
                self.sweep = Some((j, off[i], -s * off[i + 1]));
                off[i + 1] *= c;
            }
            rotate_columns(&mut self.q, i, c, -s);
        }
        if !more {
            self.sweep = None;
            let m = end - 1;
            if self.off[m].abs() <= eps * (self.diag[m].abs() + self.diag[n].abs()) {
                self.end -= 1;
            }
            self.next_subproblem(eps, max_niter);
        }
    }

    /// `Matrix2::eigenvalues` of the trailing 2x2 block, then the rotation
    /// nalgebra builds from it.
    fn solve_2x2(&mut self, eps: f64) {
        let start = self.start;
        let (h00, h11, h10) = (self.diag[start], self.diag[start + 1], self.off[start]);
        let val = (h00 - h11) * 0.5;
        let discr = h10 * h10 + val * val;
        let sqrt_discr = discr.sqrt();
        let half_tra = (h00 + h11) * 0.5;
        let (e0, e1) = (half_tra + sqrt_discr, half_tra - sqrt_discr);
        let (bx, by) = if (e0 - h11).abs() > (e0 - h00).abs() {
            (e0 - h11, h10)
        } else {
            (h10, e0 - h00)
        };
        self.diag[start] = e0;
        self.diag[start + 1] = e1;
        let (mod0, sign0) = to_exp(bx);
        let denom = (mod0 * mod0 + by * by).sqrt();
        if denom > eps {
            let norm = sign0 * denom;
            rotate_columns(&mut self.q, start, mod0 / denom, by / norm);
        }
    }

    /// Re-delimits after a sweep (decoupling may have occurred) and counts it.
    fn next_subproblem(&mut self, eps: f64, max_niter: usize) {
        (self.start, self.end) = delimit(&self.diag, &mut self.off, self.end, eps);
        self.niter += 1;
        if self.niter == max_niter {
            self.failed = true;
        }
    }

    fn finish(mut self) -> Decomposition<N> {
        if self.failed {
            return None;
        }
        for d in self.diag.iter_mut() {
            *d *= self.amax;
        }
        Some((self.diag, self.q))
    }
}

/// Eigenvalues and eigenvectors (columns, column-major) of the symmetric
/// `m` (column-major; only its lower triangle is read after the first
/// column), bit for bit those of `nalgebra::SymmetricEigen::try_new(m, eps,
/// max_niter)`. `None` for non-finite input or no convergence.
pub fn eigen<const N: usize>(m: &[[f64; N]; N], eps: f64, max_niter: usize) -> Decomposition<N> {
    let mut lane = QrLane::new(m, eps)?;
    while lane.running() {
        lane.step(eps, max_niter);
    }
    lane.finish()
}

/// [`eigen`] of two matrices at once, their QR iterations interleaved
/// rotation by rotation. Each result is bit for bit the single one.
pub fn eigen_pair<const N: usize>(
    a: &[[f64; N]; N],
    b: &[[f64; N]; N],
    eps: f64,
    max_niter: usize,
) -> [Decomposition<N>; 2] {
    let Some([mut la, mut lb]) = QrLane::new_pair(a, b, eps) else {
        return [eigen(a, eps, max_niter), eigen(b, eps, max_niter)];
    };
    while la.running() || lb.running() {
        la.step(eps, max_niter);
        lb.step(eps, max_niter);
    }
    [la.finish(), lb.finish()]
}

#[cfg(test)]
mod tests;
