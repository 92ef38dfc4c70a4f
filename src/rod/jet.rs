//! Second-order forward-mode differentiation on `N` variables.
//!
//! A [`Jet`] carries a value with its exact gradient and Hessian with respect
//! to the stencil's local vector. Arithmetic propagates them by the chain
//! rule (`(fg)'' = f''g + 2 f'g' + fg''` in matrix form), so an energy written
//! once as scalar code gets derivatives that are exact to rounding, not
//! finite-difference approximations. Used where a hand derivation would be
//! long and error-prone (the wrapping angle); the cost is `O(N^2)` per
//! operation, acceptable for the few dozen operations of one stencil.

use nalgebra::{SMatrix, SVector};
use std::ops::{Add, Mul, Neg, Sub};

/// A value with its gradient and Hessian.
#[derive(Clone, Copy, Debug)]
pub struct Jet<const N: usize> {
    pub v: f64,
    pub g: SVector<f64, N>,
    pub h: SMatrix<f64, N, N>,
}

impl<const N: usize> Jet<N> {
    pub fn constant(v: f64) -> Self {
        Jet {
            v,
            g: SVector::zeros(),
            h: SMatrix::zeros(),
        }
    }

    /// The local coordinate `i`, with value `v`.
    pub fn variable(i: usize, v: f64) -> Self {
        let mut g = SVector::zeros();
        g[i] = 1.0;
        Jet {
            v,
            g,
            h: SMatrix::zeros(),
        }
    }

    /// Applies a scalar function given its value and first two derivatives at `self.v`.
    pub fn chain(&self, f: f64, df: f64, d2f: f64) -> Self {
        Jet {
            v: f,
            g: self.g * df,
            h: SMatrix::from_fn(|i, j| self.h[(i, j)] * df + self.g[i] * self.g[j] * d2f),
        }
    }

    pub fn sqrt(&self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }

    pub fn recip(&self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }

    pub fn scale(&self, k: f64) -> Self {
        Jet {
            v: self.v * k,
            g: self.g * k,
            h: self.h * k,
        }
    }

    /// `atan2(self, x)`; smooth wherever `(x, self) != (0, 0)`.
    pub fn atan2(&self, x: &Self) -> Self {
        let y = self;
        let r2 = x.v * x.v + y.v * y.v;
        let (dy, dx) = (x.v / r2, -y.v / r2);
        let r4 = r2 * r2;
        let dyy = -2.0 * x.v * y.v / r4;
        let dxy = (y.v * y.v - x.v * x.v) / r4;
        let mixed = y.g * x.g.transpose();
        Jet {
            v: y.v.atan2(x.v),
            g: y.g * dy + x.g * dx,
            h: y.h * dy + x.h * dx + y.g * y.g.transpose() * dyy - x.g * x.g.transpose() * dyy
                + (mixed + mixed.transpose()) * dxy,
        }
    }
}

impl<const N: usize> Add for Jet<N> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Jet {
            v: self.v + o.v,
            g: self.g + o.g,
            h: self.h + o.h,
        }
    }
}

impl<const N: usize> Sub for Jet<N> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Jet {
            v: self.v - o.v,
            g: self.g - o.g,
            h: self.h - o.h,
        }
    }
}

impl<const N: usize> Neg for Jet<N> {
    type Output = Self;
    fn neg(self) -> Self {
        self.scale(-1.0)
    }
}

impl<const N: usize> Mul for Jet<N> {
    type Output = Self;
    /// `h = self.h o.v + o.h self.v + C + C^T` with `C = self.g o.g^T`,
    /// entry by entry in that order (the wrapping stencil's hottest
    /// operation: one pass, no 9x9 temporaries).
    fn mul(self, o: Self) -> Self {
        let h = SMatrix::from_fn(|i, j| {
            self.h[(i, j)] * o.v + o.h[(i, j)] * self.v + self.g[i] * o.g[j] + self.g[j] * o.g[i]
        });
        Jet {
            v: self.v * o.v,
            g: self.g * o.v + o.g * self.v,
            h,
        }
    }
}

/// A 3-vector of jets, for geometry written as in the formulas.
#[derive(Clone, Copy, Debug)]
pub struct JetVec3<const N: usize>(pub [Jet<N>; 3]);

impl<const N: usize> JetVec3<N> {
    /// The three local coordinates starting at `at`.
    pub fn variables(q: &SVector<f64, N>, at: usize) -> Self {
        JetVec3([0, 1, 2].map(|k| Jet::variable(at + k, q[at + k])))
    }

    pub fn sub(&self, o: &Self) -> Self {
        JetVec3([0, 1, 2].map(|k| self.0[k] - o.0[k]))
    }

    pub fn scale(&self, s: &Jet<N>) -> Self {
        JetVec3(self.0.map(|c| c * *s))
    }

    pub fn dot(&self, o: &Self) -> Jet<N> {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }

    pub fn cross(&self, o: &Self) -> Self {
        let (a, b) = (&self.0, &o.0);
        JetVec3([
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn product_and_quotient_match_hand_derivatives() {
        // f(a, b) = a^2 b / (a + b) at (2, 3): hand-derived values.
        let (a, b) = (Jet::<2>::variable(0, 2.0), Jet::<2>::variable(1, 3.0));
        let f = a * a * b * (a + b).recip();
        assert!((f.v - 12.0 / 5.0).abs() < 1e-15);
        // df/da = (2ab(a+b) - a^2 b)/(a+b)^2 = (60 - 12)/25; df/db = a^3/(a+b)^2 = 8/25.
        assert!((f.g - Vector2::new(48.0 / 25.0, 8.0 / 25.0)).norm() < 1e-14);
        // d2f/db2 = -2 a^3/(a+b)^3 = -16/125.
        assert!((f.h[(1, 1)] + 16.0 / 125.0).abs() < 1e-14);
        // d2f/da2 = 2 b^3/(a+b)^3 = 54/125.
        assert!((f.h[(0, 0)] - 54.0 / 125.0).abs() < 1e-14);
    }

    #[test]
    fn fused_product_and_chain_rule_are_the_matrix_expressions_bit_for_bit() {
        let mut rng = crate::rod::testutil::Rng::new(3);
        let mut next = || rng.range(-1.0, 1.0);
        let jet = |next: &mut dyn FnMut() -> f64| Jet::<9> {
            v: next(),
            g: SVector::from_fn(|_, _| next()),
            h: SMatrix::from_fn(|_, _| next()),
        };
        let bits = |m: &SMatrix<f64, 9, 9>| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for _ in 0..100 {
            let (a, b) = (jet(&mut next), jet(&mut next));
            let cross = a.g * b.g.transpose();
            let want = a.h * b.v + b.h * a.v + cross + cross.transpose();
            assert_eq!(bits(&(a * b).h), bits(&want));
            let (df, d2f) = (next(), next());
            let want = a.h * df + a.g * a.g.transpose() * d2f;
            assert_eq!(bits(&a.chain(0.0, df, d2f).h), bits(&want));
        }
    }

    #[test]
    fn atan2_and_sqrt_derivatives() {
        // theta = atan2(y, x) at (x, y) = (1, 1): grad = (-y, x)/r^2 in (x, y) order.
        let (x, y) = (Jet::<2>::variable(0, 1.0), Jet::<2>::variable(1, 1.0));
        let t = y.atan2(&x);
        assert!((t.v - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
        assert!((t.g - Vector2::new(-0.5, 0.5)).norm() < 1e-15);
        // Harmonic function: the Hessian is traceless; d2/dx2 = 2xy/r^4 = 0.5.
        assert!((t.h[(0, 0)] - 0.5).abs() < 1e-15 && (t.h.trace()).abs() < 1e-15);
        let r = (x * x + y * y).sqrt();
        assert!((r.v - 2f64.sqrt()).abs() < 1e-15);
        // d2r/dx2 = y^2 / r^3.
        assert!((r.h[(0, 0)] - 1.0 / 2f64.sqrt().powi(3)).abs() < 1e-15);
    }
}
