//! Sparse linear algebra shared by the solvers: the CSR matrix of the
//! Newton system, the block-Jacobi preconditioner and what a
//! conjugate-gradient solve reports.
//!
//! These are data, not solvers: both the host solvers (`solver::linear`)
//! and the GPU kernels (`gpu`) use them, so they live below both, and the
//! GPU code never imports the solver that drives it.

mod csr;
mod preconditioner;

pub use csr::*;
pub use preconditioner::BlockJacobi;

/// What a conjugate-gradient solve reports (host or GPU).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CgResult {
    pub iterations: usize,
    /// Final `|r| / |b|`.
    pub rel_residual: f64,
    pub converged: bool,
}
