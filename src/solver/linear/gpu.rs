//! The Newton linear solve on the GPU: [`GpuPcg`] (f32) inside the f64
//! Newton loop, i.e. an inexact Newton method (docs/GPU.md, "Precision").
//!
//! Design decisions:
//! - **Pattern resident, values streamed.** The Hessian pattern of one
//!   Newton solve is fixed (the problem cancels EIL rows in place), so the
//!   device buffers and bind groups are built once and every iteration only
//!   uploads the new values and block inverses. A new pattern (a new contact
//!   set or EIL assignment at the next step) rebinds the buffers but keeps
//!   the compiled pipelines.
//! - **Forcing term above the f32 floor.** CG stops at `|r| <= eta |b|` with
//!   `eta` = [`GpuLinearParams::rel_tol`] (1e-5 by default). The true f32
//!   residual stalls near 1e-6 (measured, see `gpu::pcg`), so a smaller
//!   `eta` buys iterations, not accuracy. Newton tolerates `eta < 1`
//!   (Dembo, Eisenstat & Steihaug 1982): the gradient and energy are
//!   recomputed in f64 each iteration and the line search rejects a step
//!   that does not decrease the f64 energy.
//! - **A stopped CG is not an error.** Like the CPU CG, an unconverged or
//!   broken-down solve returns its iterate; Newton checks that it is a
//!   descent direction and otherwise falls back to steepest descent.

use crate::gpu::{AdapterSummary, GpuContext, GpuError, GpuPcg, GpuPcgParams};
use crate::solver::sparse::CsrMatrix;

/// Tuning of the GPU Newton solve.
#[derive(Clone, Copy, Debug)]
pub struct GpuLinearParams {
    /// Inexact-Newton forcing term: stop at `|r| <= rel_tol |b|` (f32 recursive residual).
    pub rel_tol: f64,
    pub max_iter: usize,
    /// CG iterations between scalar readbacks (see `gpu::pcg`, "Readback policy").
    pub check_every: usize,
}

impl Default for GpuLinearParams {
    fn default() -> Self {
        let pcg = GpuPcgParams::default();
        GpuLinearParams {
            rel_tol: 1e-5,
            max_iter: 10_000,
            check_every: pcg.check_every,
        }
    }
}

/// Outcome of one GPU solve, in the terms of [`super::LinearReport`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuSolveStats {
    pub iterations: usize,
    pub rel_residual: f64,
    pub converged: bool,
    /// The pattern changed and the device buffers were rebuilt for this solve.
    pub rebound: bool,
}

/// A device plus the resident solver of the current pattern.
pub struct GpuSolver {
    ctx: GpuContext,
    pcg: Option<GpuPcg>,
    pub params: GpuLinearParams,
    /// Pattern uploads so far (the first one included); a diagnostic of reuse.
    pub pattern_uploads: usize,
}

impl GpuSolver {
    pub fn new(ctx: GpuContext) -> Self {
        GpuSolver {
            ctx,
            pcg: None,
            params: GpuLinearParams::default(),
            pattern_uploads: 0,
        }
    }

    /// Opens the default (high-performance) adapter; fails with
    /// [`GpuError::NoAdapter`] on a machine without one.
    pub fn with_default_adapter() -> Result<Self, GpuError> {
        Ok(Self::new(GpuContext::new()?))
    }

    pub fn adapter(&self) -> &AdapterSummary {
        &self.ctx.adapter
    }

    /// Solves `a x = b` from the guess in `x`. `blocks` as in
    /// [`super::LinearSolver::solve`]; a partition the GPU preconditioner
    /// cannot use (malformed, or blocks above 4 unknowns) becomes scalar Jacobi.
    pub fn solve(
        &mut self,
        a: &CsrMatrix,
        b: &[f64],
        x: &mut [f64],
        blocks: &[usize],
    ) -> Result<GpuSolveStats, GpuError> {
        let scalar;
        let blocks = if usable_blocks(blocks, a.n) {
            blocks
        } else {
            scalar = (0..=a.n).collect::<Vec<_>>();
            &scalar
        };
        // On an upload error the resident solver is dropped and the next
        // solve starts afresh.
        let (pcg, rebound) = match self.pcg.take() {
            Some(mut pcg) if pcg.matches(a, blocks) => {
                pcg.update_values(a)?;
                (pcg, false)
            }
            Some(mut pcg) => {
                pcg.rebind(a, blocks)?;
                (pcg, true)
            }
            None => (GpuPcg::new(&self.ctx, a, blocks)?, true),
        };
        let pcg = self.pcg.insert(pcg);
        self.pattern_uploads += usize::from(rebound);
        let params = GpuPcgParams {
            rel_tol: self.params.rel_tol,
            max_iter: self.params.max_iter,
            check_every: self.params.check_every,
        };
        let (solution, stats) = pcg.solve(b, x, &params)?;
        x.copy_from_slice(&solution);
        Ok(GpuSolveStats {
            iterations: stats.iterations,
            rel_residual: stats.rel_residual,
            converged: stats.converged,
            rebound,
        })
    }
}

/// Increasing starts from 0 to n with blocks of 1..=4 unknowns.
fn usable_blocks(starts: &[usize], n: usize) -> bool {
    starts.first() == Some(&0)
        && starts.last() == Some(&n)
        && starts.windows(2).all(|w| w[0] < w[1] && w[1] - w[0] <= 4)
}

#[cfg(test)]
mod tests {
    use super::usable_blocks;

    #[test]
    fn block_partitions_the_gpu_preconditioner_accepts() {
        assert!(usable_blocks(&[0, 3, 6, 7], 7));
        assert!(!usable_blocks(&[], 7));
        assert!(!usable_blocks(&[0, 3, 6], 7));
        assert!(!usable_blocks(&[0, 3, 3, 7], 7));
        assert!(!usable_blocks(&[0, 5, 7], 7));
    }
}
