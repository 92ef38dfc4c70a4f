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
//! - **Mixed-precision iterative refinement.** An f32 solve is accurate to
//!   about 1e-5, and with friction that is not good enough: the Coulomb
//!   anchors are updated from each step's end state, so a relaxation driven
//!   by inexact steps settles on a different (equally valid) equilibrium.
//!   Relaxing the 4x4 stockinette swatch with CPU CG at `|r| <= 1e-5 |b|`
//!   ends 2.3 yarn radii RMS away from cpu-direct; at 1e-8, 1.4% of a
//!   radius; at 1e-11, 7e-8 of a radius (docs/GPU.md, "Parity test"). So
//!   after the f32 solve the residual `b - A x` is formed in f64 on the CPU,
//!   the f32 solver solves for the correction, and this repeats until the
//!   f64 residual is below [`GpuLinearParams::refine_tol`] (classic
//!   iterative refinement: each round gains the f32 solve's accuracy as
//!   long as `cond(A)` times the f32 unit roundoff, 6e-8, is well below 1). Setting `refine_tol` to 0
//!   or `max_refinements` to 0 gives the plain inexact Newton step.
//! - **A stopped CG is not an error.** Like the CPU CG, an unconverged or
//!   broken-down solve returns its iterate; Newton checks that it is a
//!   descent direction and otherwise falls back to steepest descent.

use crate::gpu::{AdapterSummary, GpuContext, GpuError, GpuPcg, GpuPcgParams};
use crate::sparse::{dot, CsrMatrix};

/// Tuning of the GPU Newton solve.
#[derive(Clone, Copy, Debug)]
pub struct GpuLinearParams {
    /// Inexact-Newton forcing term: stop at `|r| <= rel_tol |b|` (f32 recursive residual).
    pub rel_tol: f64,
    pub max_iter: usize,
    /// CG iterations between scalar readbacks (see `gpu::pcg`, "Readback policy").
    pub check_every: usize,
    /// Iterative refinement target on the f64 residual `|b - A x| <= refine_tol |b|`.
    pub refine_tol: f64,
    /// Refinement rounds (extra f32 solves) at most per Newton solve.
    pub max_refinements: usize,
}

impl Default for GpuLinearParams {
    fn default() -> Self {
        let pcg = GpuPcgParams::default();
        GpuLinearParams {
            rel_tol: 1e-5,
            max_iter: 10_000,
            check_every: pcg.check_every,
            refine_tol: 1e-10,
            max_refinements: 6,
        }
    }
}

/// Outcome of one GPU solve, in the terms of [`super::LinearReport`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuSolveStats {
    pub iterations: usize,
    pub rel_residual: f64,
    pub converged: bool,
    /// Refinement rounds after the first solve.
    pub refinements: usize,
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
        let mut iterations = stats.iterations;
        // Refining an f32 solve that did not converge would repeat its cost
        // for a correction no better than itself.
        let (refinements, rel_residual) = if stats.converged {
            self.refine(a, b, x, &params, &mut iterations)?
        } else {
            (0, None)
        };
        Ok(GpuSolveStats {
            iterations,
            rel_residual: rel_residual.unwrap_or(stats.rel_residual),
            converged: stats.converged || rel_residual.is_some_and(|r| r <= self.params.rel_tol),
            refinements,
            rebound,
        })
    }

    /// Iterative refinement of `x` (see the module docs). Returns the rounds
    /// made and the final f64 relative residual (None when refinement is off).
    /// Stops early when a round fails to cut the residual tenfold (the
    /// system is then so ill-conditioned that refinement converges slowly,
    /// each round at the cost of a full solve) or when its f32 solve did not
    /// converge; the best iterate so far is kept.
    fn refine(
        &mut self,
        a: &CsrMatrix,
        b: &[f64],
        x: &mut [f64],
        params: &GpuPcgParams,
        iterations: &mut usize,
    ) -> Result<(usize, Option<f64>), GpuError> {
        if self.params.max_refinements == 0 || self.params.refine_tol <= 0.0 {
            return Ok((0, None));
        }
        let pcg = self.pcg.as_ref().expect("refine runs after a solve");
        let b_norm = norm(b).max(f64::MIN_POSITIVE);
        let mut r = vec![0.0; a.n];
        let mut rel = residual(a, b, x, &mut r) / b_norm;
        let zero = vec![0.0; a.n];
        let mut rounds = 0;
        while rel > self.params.refine_tol && rounds < self.params.max_refinements {
            let (dx, stats) = pcg.solve(&r, &zero, params)?;
            *iterations += stats.iterations;
            rounds += 1;
            let trial: Vec<f64> = x.iter().zip(&dx).map(|(xi, di)| xi + di).collect();
            let mut r_trial = vec![0.0; a.n];
            let rel_trial = residual(a, b, &trial, &mut r_trial) / b_norm;
            if rel_trial.is_nan() || rel_trial >= rel {
                break;
            }
            x.copy_from_slice(&trial);
            r = r_trial;
            let contracted = rel_trial <= 0.1 * rel;
            rel = rel_trial;
            if !contracted || !stats.converged {
                break;
            }
        }
        Ok((rounds, Some(rel)))
    }
}

/// `r = b - A x` in f64; returns `|r|`.
fn residual(a: &CsrMatrix, b: &[f64], x: &[f64], r: &mut [f64]) -> f64 {
    a.residual(x, b, r);
    norm(r)
}

fn norm(v: &[f64]) -> f64 {
    dot(v, v).sqrt()
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
