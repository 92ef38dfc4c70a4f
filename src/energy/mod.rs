//! Energies as stencils, the way ipc-toolkit writes them.
//!
//! A stencil is a small potential on a fixed-size local vector gathered from
//! the global coordinates. It knows nothing of the global system: one generic
//! routine (`solver::assembly`) gathers, evaluates and scatters every stencil,
//! so a new energy term is one file with `value`, `gradient` and `hessian`, and
//! its finite-difference test.

pub mod fd;
pub mod psd;

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
}
