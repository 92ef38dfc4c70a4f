//! EIL interpolation and the soft contact constraint (docs/MODEL.md, "Kinematics" and
//! "EIL constraint spring").
//!
//! An EIL point on a yarn has a free Eulerian coordinate `u` but no position
//! of its own: it sits on the chord between its yarn's neighbouring non-EIL
//! nodes `(x_a, u_a)` and `(x_c, u_c)`,
//!
//! ```text
//! x_eil = ((u_c - u) x_a + (u - u_a) x_c) / (u_c - u_a) = x_a + s (x_c - x_a)
//! s = (u - u_a) / (u_c - u_a)
//! ```
//!
//! Its contact with the partner yarn is a zero-rest-length spring
//! `1/2 kc |x_eil - x_partner|^2`, `kc = kc_factor * ks / du_rest`
//! (`RodParams::contact_stiffness`; *Robust Eulerian-on-Lagrangian Rods*
//! uses a factor of 1000). The partner is an
//! EoL node ([`EilToPoint`]) or another EIL point ([`EilToEil`], both yarns
//! degenerate at the same contact).
//!
//! **Interpolation local vector** (9): `[x_a(3), u_a, x_c(3), u_c, u]`.
//! Other terms acting at an EIL point (wrapping, shear) evaluate their force
//! `f = dV/dx_eil` and map it to these 9 coordinates with
//! `J^T f`, `J = d x_eil / d(local)` ([`eil_jacobian`]); their Hessian maps as
//! `J^T H J + sum_k f_k hess(x_eil,k)` ([`eil_curvature`] gives the sum).
//! With `w = (x_c - x_a) / (u_c - u_a)`:
//!
//! ```text
//! J = [ (1-s) I | -(1-s) w | s I | -s w | w ]
//! ```
//!
//! The `u` columns sum to zero: shifting all three Eulerian coordinates
//! together does not move the point. `x_eil` is bilinear in `s` and the
//! positions and `s` is rational in the `u`'s, so the curvature terms are
//! `d2x/dx_a du_i = -ds/du_i I`, `d2x/dx_c du_i = ds/du_i I` and
//! `d2x/du_i du_j = d2s/du_i du_j (x_c - x_a)`.
//!
//! `u_c <= u_a` is outside the model (the two non-EIL neighbours are at least
//! the EIL threshold apart): the constraint value is then `+inf` with zero
//! derivatives.

use crate::energy::Stencil;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

const XA: usize = 0;
const UA: usize = 3;
const XC: usize = 4;
const UC: usize = 7;
const U: usize = 8;

fn span(q: &SVector<f64, 9>) -> (Vector3<f64>, f64, f64) {
    let d = q.fixed_rows::<3>(XC) - q.fixed_rows::<3>(XA);
    let du = q[UC] - q[UA];
    (d, du, (q[U] - q[UA]) / du)
}

/// The interpolated position `x_eil`.
pub fn eil_position(q: &SVector<f64, 9>) -> Vector3<f64> {
    let (d, _, s) = span(q);
    q.fixed_rows::<3>(XA) + d * s
}

/// Gradient of `s` with respect to `(u_a, u_c, u)`.
fn ds(q: &SVector<f64, 9>) -> [f64; 3] {
    let du = q[UC] - q[UA];
    [(q[U] - q[UC]) / (du * du), -(q[U] - q[UA]) / (du * du), 1.0 / du]
}

/// `J = d x_eil / d(local)`, 3x9.
pub fn eil_jacobian(q: &SVector<f64, 9>) -> SMatrix<f64, 3, 9> {
    let (d, _, s) = span(q);
    let mut j = SMatrix::<f64, 3, 9>::zeros();
    j.fixed_view_mut::<3, 3>(0, XA)
        .copy_from(&(Matrix3::identity() * (1.0 - s)));
    j.fixed_view_mut::<3, 3>(0, XC).copy_from(&(Matrix3::identity() * s));
    for (col, dsi) in [UA, UC, U].into_iter().zip(ds(q)) {
        j.set_column(col, &(d * dsi));
    }
    j
}

/// `sum_k f_k hess(x_eil,k)`: the curvature term of a force `f` mapped
/// through the interpolation.
pub fn eil_curvature(q: &SVector<f64, 9>, f: &Vector3<f64>) -> SMatrix<f64, 9, 9> {
    let (d, du, _) = span(q);
    let (u, ua, uc) = (q[U], q[UA], q[UC]);
    let du3 = du * du * du;
    let cols = [UA, UC, U];
    let g = ds(q);
    // Hessian of s in (u_a, u_c, u), differentiated by hand from s = (u - u_a)/(u_c - u_a).
    let h_s = [
        [
            2.0 * (u - uc) / du3,
            -1.0 / (du * du) - 2.0 * (u - uc) / du3,
            1.0 / (du * du),
        ],
        [
            -1.0 / (du * du) - 2.0 * (u - uc) / du3,
            2.0 * (u - ua) / du3,
            -1.0 / (du * du),
        ],
        [1.0 / (du * du), -1.0 / (du * du), 0.0],
    ];
    let fd = f.dot(&d);
    let mut c = SMatrix::<f64, 9, 9>::zeros();
    for (i, &ci) in cols.iter().enumerate() {
        for (j, &cj) in cols.iter().enumerate() {
            c[(ci, cj)] = h_s[i][j] * fd;
        }
        for k in 0..3 {
            c[(XA + k, ci)] = -g[i] * f[k];
            c[(ci, XA + k)] = -g[i] * f[k];
            c[(XC + k, ci)] = g[i] * f[k];
            c[(ci, XC + k)] = g[i] * f[k];
        }
    }
    c
}

/// EIL point against an EoL node of the partner yarn, on
/// `[x_a(3), u_a, x_c(3), u_c, u, x_p(3)]` (N = 12).
#[derive(Clone, Copy, Debug)]
pub struct EilToPoint {
    /// Contact spring stiffness (N/m).
    pub kc: f64,
}

/// Two EIL points, one per yarn, on
/// `[x_a, u_a, x_c, u_c, u, y_a, v_a, y_c, v_c, v]` (N = 18): the first nine
/// interpolate yarn A's point, the last nine yarn B's.
#[derive(Clone, Copy, Debug)]
pub struct EilToEil {
    /// Contact spring stiffness (N/m).
    pub kc: f64,
}

impl EilToPoint {
    pub fn new(kc: f64) -> Self {
        EilToPoint { kc }
    }
}

impl EilToEil {
    pub fn new(kc: f64) -> Self {
        EilToEil { kc }
    }
}

fn valid(q: &SVector<f64, 9>) -> bool {
    q[UC] > q[UA]
}

impl Stencil<12> for EilToPoint {
    fn value(&self, q: &SVector<f64, 12>) -> f64 {
        let a = q.fixed_rows::<9>(0).into_owned();
        if !valid(&a) {
            return f64::INFINITY;
        }
        0.5 * self.kc * (eil_position(&a) - q.fixed_rows::<3>(9)).norm_squared()
    }

    fn gradient(&self, q: &SVector<f64, 12>) -> SVector<f64, 12> {
        let a = q.fixed_rows::<9>(0).into_owned();
        let mut g = SVector::<f64, 12>::zeros();
        if !valid(&a) {
            return g;
        }
        let f = (eil_position(&a) - q.fixed_rows::<3>(9)) * self.kc;
        g.fixed_rows_mut::<9>(0).copy_from(&(eil_jacobian(&a).transpose() * f));
        g.fixed_rows_mut::<3>(9).copy_from(&(-f));
        g
    }

    fn hessian(&self, q: &SVector<f64, 12>) -> SMatrix<f64, 12, 12> {
        let a = q.fixed_rows::<9>(0).into_owned();
        let mut h = SMatrix::<f64, 12, 12>::zeros();
        if !valid(&a) {
            return h;
        }
        let f = (eil_position(&a) - q.fixed_rows::<3>(9)) * self.kc;
        let j = eil_jacobian(&a);
        let h_aa = j.transpose() * j * self.kc + eil_curvature(&a, &f);
        let h_ap = -j.transpose() * self.kc;
        h.fixed_view_mut::<9, 9>(0, 0).copy_from(&h_aa);
        h.fixed_view_mut::<9, 3>(0, 9).copy_from(&h_ap);
        h.fixed_view_mut::<3, 9>(9, 0).copy_from(&h_ap.transpose());
        h.fixed_view_mut::<3, 3>(9, 9)
            .copy_from(&(Matrix3::identity() * self.kc));
        h
    }
}

impl Stencil<18> for EilToEil {
    fn value(&self, q: &SVector<f64, 18>) -> f64 {
        let (a, b) = (q.fixed_rows::<9>(0).into_owned(), q.fixed_rows::<9>(9).into_owned());
        if !valid(&a) || !valid(&b) {
            return f64::INFINITY;
        }
        0.5 * self.kc * (eil_position(&a) - eil_position(&b)).norm_squared()
    }

    fn gradient(&self, q: &SVector<f64, 18>) -> SVector<f64, 18> {
        let (a, b) = (q.fixed_rows::<9>(0).into_owned(), q.fixed_rows::<9>(9).into_owned());
        let mut g = SVector::<f64, 18>::zeros();
        if !valid(&a) || !valid(&b) {
            return g;
        }
        let f = (eil_position(&a) - eil_position(&b)) * self.kc;
        g.fixed_rows_mut::<9>(0).copy_from(&(eil_jacobian(&a).transpose() * f));
        g.fixed_rows_mut::<9>(9).copy_from(&(-eil_jacobian(&b).transpose() * f));
        g
    }

    fn hessian(&self, q: &SVector<f64, 18>) -> SMatrix<f64, 18, 18> {
        let (a, b) = (q.fixed_rows::<9>(0).into_owned(), q.fixed_rows::<9>(9).into_owned());
        let mut h = SMatrix::<f64, 18, 18>::zeros();
        if !valid(&a) || !valid(&b) {
            return h;
        }
        let f = (eil_position(&a) - eil_position(&b)) * self.kc;
        let (ja, jb) = (eil_jacobian(&a), eil_jacobian(&b));
        let h_ab = -ja.transpose() * jb * self.kc;
        h.fixed_view_mut::<9, 9>(0, 0)
            .copy_from(&(ja.transpose() * ja * self.kc + eil_curvature(&a, &f)));
        h.fixed_view_mut::<9, 9>(9, 9)
            .copy_from(&(jb.transpose() * jb * self.kc - eil_curvature(&b, &f)));
        h.fixed_view_mut::<9, 9>(0, 9).copy_from(&h_ab);
        h.fixed_view_mut::<9, 9>(9, 0).copy_from(&h_ab.transpose());
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::fd::check_derivatives;
    use crate::rod::testutil::{assert_all_finite, put3, Rng};

    fn interp(rng: &mut Rng, du: f64, s: f64) -> SVector<f64, 9> {
        let mut q = SVector::<f64, 9>::zeros();
        put3(&mut q, XA, &rng.vec3(1.0));
        put3(&mut q, XC, &rng.vec3(1.0));
        q[UA] = rng.range(-1.0, 1.0);
        q[UC] = q[UA] + du;
        q[U] = q[UA] + s * du;
        q
    }

    #[test]
    fn interpolation_by_hand_and_jacobian_by_fd() {
        // u at 1/4 of [2, 6]: x = 3/4 x_a + 1/4 x_c.
        let mut q = SVector::<f64, 9>::zeros();
        put3(&mut q, XA, &Vector3::new(4.0, 0.0, 0.0));
        put3(&mut q, XC, &Vector3::new(0.0, 8.0, 0.0));
        (q[UA], q[UC], q[U]) = (2.0, 6.0, 3.0);
        assert!((eil_position(&q) - Vector3::new(3.0, 2.0, 0.0)).norm() < 1e-15);
        let j = eil_jacobian(&q);
        let h = 1e-6;
        for i in 0..9 {
            let (mut p, mut m) = (q, q);
            p[i] += h;
            m[i] -= h;
            let col = (eil_position(&p) - eil_position(&m)) / (2.0 * h);
            assert!((col - j.column(i)).norm() < 1e-8, "column {i}");
        }
        // Sliding u by du moves the point by w du, w = (x_c - x_a)/4.
        assert!((j.column(U) - Vector3::new(-1.0, 2.0, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn spring_energy_by_hand() {
        let mut q = SVector::<f64, 12>::zeros();
        put3(&mut q, XC, &Vector3::new(2.0, 0.0, 0.0));
        (q[UA], q[UC], q[U]) = (0.0, 1.0, 0.5);
        put3(&mut q, 9, &Vector3::new(1.0, 3.0, 4.0));
        // Midpoint (1, 0, 0) to (1, 3, 4): distance 5, V = kc * 25 / 2.
        assert!((EilToPoint::new(2.0).value(&q) - 25.0).abs() < 1e-13);
    }

    #[test]
    fn eil_to_point_derivatives() {
        let mut rng = Rng::new(21);
        let c = EilToPoint::new(1e3);
        for (du, h) in [(1.0, 1e-6), (1e-6, 1e-12)] {
            for k in 0..30 {
                let s = [rng.range(0.0, 1.0), 0.0, 1.0, 1e-6][k % 4];
                let a = interp(&mut rng, du, s);
                let mut q = SVector::<f64, 12>::zeros();
                q.fixed_rows_mut::<9>(0).copy_from(&a);
                put3(&mut q, 9, &rng.vec3(1.0));
                assert_all_finite(&c, &q);
                check_derivatives(&c, &q, h, 1e-4);
            }
        }
    }

    #[test]
    fn eil_to_eil_derivatives() {
        let mut rng = Rng::new(22);
        let c = EilToEil::new(1e3);
        for (du, h) in [(1.0, 1e-6), (1e-6, 1e-12)] {
            for _ in 0..30 {
                let (sa, sb) = (rng.range(-0.2, 1.2), rng.range(0.0, 1.0));
                let a = interp(&mut rng, du, sa);
                let b = interp(&mut rng, 0.5, sb);
                let mut q = SVector::<f64, 18>::zeros();
                q.fixed_rows_mut::<9>(0).copy_from(&a);
                q.fixed_rows_mut::<9>(9).copy_from(&b);
                assert_all_finite(&c, &q);
                check_derivatives(&c, &q, h, 1e-4);
            }
        }
        // Coincident interpolation endpoints: finite.
        let mut q = SVector::<f64, 18>::zeros();
        (q[UC], q[U], q[9 + UC]) = (1.0, 0.5, 1.0);
        assert_all_finite(&c, &q);
    }
}
