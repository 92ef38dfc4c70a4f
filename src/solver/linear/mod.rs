//! Linear solvers for the Newton system `H dq = -g`.
//!
//! - [`cg`]: block-Jacobi preconditioned conjugate gradients on [`CsrMatrix`],
//!   the scalable CPU path and the reference for the GPU kernels.
//! - [`direct`]: sparse Cholesky (faer) with the symbolic analysis reused
//!   while the pattern is unchanged; the robust default on the CPU.
//! - `gpu` (feature `gpu`): `crate::gpu::GpuPcg` as an inexact Newton
//!   solve, with the device buffers kept while the pattern is unchanged.
//! - [`choice`]: the `--solver auto|cpu-direct|cpu-cg|gpu` rule.
//!
//! [`LinearSolver`] is an enum rather than a trait object so a configuration
//! (CLI flag, scene file) maps onto it directly and each variant keeps its own
//! reusable state (the symbolic factorization, later the GPU buffers). The
//! preconditioner partition is passed per solve because it follows the node
//! layout, which the solver does not own.

pub mod cg;
pub mod choice;
pub mod direct;
#[cfg(feature = "gpu")]
pub mod gpu_solver;

pub use crate::sparse::{BlockJacobi, CgResult};
pub use cg::{pcg, CgParams};
pub use choice::{select, software_adapter, AutoParams, SelectError, Selection, SolverChoice};
pub use direct::{DirectError, DirectParams, DirectSolver, FactorKind, Ordering};
#[cfg(feature = "gpu")]
pub use gpu_solver::{GpuLinearParams, GpuSolver};

use crate::sparse::CsrMatrix;

/// A linear solver with whatever state it reuses across Newton iterations.
pub enum LinearSolver {
    Direct(DirectSolver),
    Cg(CgParams),
    /// f32 block-Jacobi PCG on the GPU (inexact Newton, docs/GPU.md); boxed
    /// because the device handles dwarf the CPU variants.
    #[cfg(feature = "gpu")]
    Gpu(Box<GpuSolver>),
}

impl LinearSolver {
    pub fn direct() -> Self {
        LinearSolver::Direct(DirectSolver::default())
    }

    pub fn cg() -> Self {
        LinearSolver::Cg(CgParams::default())
    }

    pub fn name(&self) -> &'static str {
        match self {
            LinearSolver::Direct(_) => "direct",
            LinearSolver::Cg(_) => "cg",
            #[cfg(feature = "gpu")]
            LinearSolver::Gpu(_) => "gpu",
        }
    }

    /// The group (node) of each unknown, for the direct solver's grouped
    /// fill-reducing ordering ([`direct::Ordering`]); the iterative solvers
    /// do not order, and ignore it.
    pub fn set_ordering_groups(&mut self, groups: &[u32]) {
        if let LinearSolver::Direct(s) = self {
            s.set_ordering_groups(groups);
        }
    }

    /// Whether the next solves must find `a` positive definite: the direct
    /// solver then factors with plain LLT only and fails otherwise, and a
    /// CG run that meets non-positive curvature reports itself not
    /// converged (as it always does). Newton's exact-Hessian iterations
    /// use this to fall back to the projected Hessian the same way with
    /// every solver.
    pub fn set_definite_only(&mut self, on: bool) {
        if let LinearSolver::Direct(s) = self {
            s.params.definite_only = on;
        }
    }

    /// Solves `a x = b`. `x` is the CG starting guess and is overwritten.
    /// `blocks` is the block-Jacobi partition (starts, closed by `a.n`); an
    /// empty slice means scalar Jacobi. The direct solver ignores it.
    ///
    /// A CG run that stops before its tolerance is not an error: the caller
    /// (Newton) gets an inexact step and checks it is a descent direction.
    pub fn solve(
        &mut self,
        a: &CsrMatrix,
        b: &[f64],
        x: &mut [f64],
        blocks: &[usize],
    ) -> Result<LinearReport, LinearError> {
        if b.len() != a.n || x.len() != a.n {
            return Err(LinearError::Dimension {
                n: a.n,
                b: b.len(),
                x: x.len(),
            });
        }
        match self {
            LinearSolver::Direct(s) => {
                let kind = s.solve(a, b, x)?;
                Ok(LinearReport {
                    iterations: 0,
                    rel_residual: 0.0,
                    converged: true,
                    factor: Some(kind),
                })
            }
            LinearSolver::Cg(params) => {
                let valid_blocks =
                    blocks.first() == Some(&0) && blocks.last() == Some(&a.n) && blocks.windows(2).all(|w| w[0] < w[1]);
                let pre = if valid_blocks {
                    BlockJacobi::new(a, blocks)
                } else {
                    BlockJacobi::diagonal(a)
                };
                let r = pcg(a, b, x, &pre, *params);
                Ok(LinearReport {
                    iterations: r.iterations,
                    rel_residual: r.rel_residual,
                    converged: r.converged,
                    factor: None,
                })
            }
            #[cfg(feature = "gpu")]
            LinearSolver::Gpu(gpu) => {
                let r = gpu.solve(a, b, x, blocks)?;
                Ok(LinearReport {
                    iterations: r.iterations,
                    rel_residual: r.rel_residual,
                    converged: r.converged,
                    factor: None,
                })
            }
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum LinearError {
    #[error("matrix is {n}x{n}, right-hand side has length {b}, solution {x}")]
    Dimension { n: usize, b: usize, x: usize },
    #[error(transparent)]
    Direct(#[from] DirectError),
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
}

/// What one linear solve did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearReport {
    /// CG iterations (0 for the direct solver).
    pub iterations: usize,
    /// Final CG `|r| / |b|` (0 for the direct solver, which checks its own residual).
    pub rel_residual: f64,
    pub converged: bool,
    /// The factorization used by the direct solver.
    pub factor: Option<FactorKind>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Block tridiagonal SPD matrix with 3x3 blocks coupling neighbours.
    fn block_chain(nb: usize) -> CsrMatrix {
        let n = 3 * nb;
        let mut e = Vec::new();
        for r in 0..n {
            for c in 0..n {
                if (r / 3).abs_diff(c / 3) <= 1 {
                    e.push((r as u32, c as u32));
                }
            }
        }
        let mut a = CsrMatrix::from_pattern(n, e);
        for r in 0..n {
            for k in a.row_ptr[r]..a.row_ptr[r + 1] {
                let c = a.col_idx[k] as usize;
                a.values[k] = if r == c {
                    8.0
                } else if r / 3 == c / 3 {
                    1.5
                } else if r % 3 == c % 3 {
                    -1.0
                } else {
                    0.0
                };
            }
        }
        a
    }

    #[test]
    fn direct_and_block_cg_agree() {
        let a = block_chain(20);
        let b: Vec<f64> = (0..a.n).map(|i| ((i * 13) % 5) as f64 - 2.0).collect();
        let blocks: Vec<usize> = (0..=a.n).step_by(3).collect();
        let mut xd = vec![0.0; a.n];
        let rd = LinearSolver::direct().solve(&a, &b, &mut xd, &blocks).unwrap();
        assert_eq!(rd.factor, Some(FactorKind::Llt));
        let mut xc = vec![0.0; a.n];
        let mut cg = LinearSolver::Cg(CgParams {
            rel_tol: 1e-12,
            max_iter: 1000,
        });
        let rc = cg.solve(&a, &b, &mut xc, &blocks).unwrap();
        assert!(rc.converged && rc.iterations > 0);
        let err = xd.iter().zip(&xc).map(|(u, v)| (u - v).abs()).fold(0.0, f64::max);
        assert!(err < 1e-9, "{err}");
        // A malformed partition falls back to scalar Jacobi instead of panicking.
        let mut xs = vec![0.0; a.n];
        assert!(cg.solve(&a, &b, &mut xs, &[0, 5]).unwrap().converged);
    }
}
