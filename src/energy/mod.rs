//! Energies as stencils, the way ipc-toolkit writes them.
//!
//! A stencil is a small potential on a fixed-size local vector gathered from
//! the global coordinates. It knows nothing of the global system: one generic
//! routine (`solver::assembly`) gathers, evaluates and scatters every stencil,
//! so a new energy term is one file with `value`, `gradient` and `hessian`, and
//! its finite-difference test.

pub mod fd;
pub mod psd;
pub mod symmetric_qr;

use nalgebra::{SMatrix, SVector};

/// A stencil's gradient and (possibly projected) Hessian.
pub type Derivatives<const N: usize> = (SVector<f64, N>, SMatrix<f64, N, N>);

/// A potential on `N` local coordinates.
pub trait Stencil<const N: usize> {
    fn value(&self, x: &SVector<f64, N>) -> f64;
    fn gradient(&self, x: &SVector<f64, N>) -> SVector<f64, N>;
    fn hessian(&self, x: &SVector<f64, N>) -> SMatrix<f64, N, N>;

    /// Gradient and Hessian together, the Hessian projected onto the PSD
    /// cone when `project` is set. Assembly calls only this, so a stencil
    /// that shares work between the two (an AD jet) or knows a cheaper
    /// projection (in a reduced space) overrides it.
    fn derivatives(&self, x: &SVector<f64, N>, project: bool) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        let h = self.hessian(x);
        (self.gradient(x), if project { psd::project_psd(&h) } else { h })
    }

    /// [`derivatives`](Self::derivatives) of two stencils of this kind,
    /// each result bit for bit its own call's. Assembly evaluates stencils
    /// in pairs through this, so a stencil whose projection is a
    /// latency-bound eigen-decomposition can interleave the two
    /// ([`psd::project_psd_pair`]); the default is two calls.
    fn derivatives_pair(
        a: &Self,
        xa: &SVector<f64, N>,
        b: &Self,
        xb: &SVector<f64, N>,
        project: bool,
    ) -> [Derivatives<N>; 2]
    where
        Self: Sized,
    {
        [a.derivatives(xa, project), b.derivatives(xb, project)]
    }
}

/// [`Stencil::derivatives_pair`] for a stencil that keeps the default
/// [`Stencil::derivatives`] (its whole Hessian projected): the two
/// projections interleaved, bit for bit the two single calls. A stencil
/// opts in by overriding `derivatives_pair` with this; it cannot be the
/// trait's default, which must respect an overridden `derivatives`.
pub fn whole_hessian_pair<const N: usize, S: Stencil<N>>(
    a: &S,
    xa: &SVector<f64, N>,
    b: &S,
    xb: &SVector<f64, N>,
    project: bool,
) -> [Derivatives<N>; 2] {
    let (ha, hb) = (a.hessian(xa), b.hessian(xb));
    let [ha, hb] = if project {
        psd::project_psd_pair(&ha, &hb)
    } else {
        [ha, hb]
    };
    [(a.gradient(xa), ha), (b.gradient(xb), hb)]
}
