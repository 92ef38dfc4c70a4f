//! Block-Jacobi preconditioned CG on the GPU, in f32.
//!
//! The algorithm is exactly [`crate::solver::linear::pcg`] (same update
//! order, same stopping test `|r| <= rel_tol |b|`), with every vector and
//! scalar resident on the device. The matrix pattern and the block layout are
//! uploaded once; [`GpuPcg::update_values`] refreshes only the values and the
//! block inverses each Newton iteration.
//!
//! # Readback policy
//! The host reads back a 48-byte scalar struct once per batch of
//! [`GpuPcgParams::check_every`] iterations (default 8) and the solution once
//! at the end. The stopping test itself runs on the GPU every iteration and
//! freezes the iteration counter, so the reported count is exact; the cost of
//! batching is at most `check_every - 1` idle iterations (alpha = 0) after
//! convergence. Each readback is a full queue drain (tens of microseconds on
//! a discrete GPU, more on a software adapter), which is why it is not done
//! every iteration.
//!
//! # Precision
//! f32 has a unit roundoff of u ≈ 6e-8. The matrix and x are rounded to
//! f32, and the recursively updated residual r drifts away from the true
//! `b - A x` by O(u |A| |x|) over the run. The recursive residual keeps
//! shrinking, so a tight `rel_tol` still reports convergence, but the true
//! relative residual stalls near 1e-6 (measured on the 3000-unknown test
//! system: 2.4e-6 at rel_tol 1e-6, 2.7e-6 at 1e-7 and 1e-8, where the f64
//! reference reaches 1e-8). Tolerances below ~1e-6 therefore only cost
//! iterations. That is fine where this solver is meant to run: inside an f64
//! Newton loop the linear solve only has to be an *inexact* Newton step.
//! Newton converges as long as `|H dq + g| <= eta |g|` with a forcing term
//! eta < 1 (Dembo, Eisenstat & Steihaug 1982), and the gradient and energy
//! are recomputed in f64 every Newton iteration, so the f32 error never
//! accumulates across steps: it only limits how small eta can be made.

use super::buffers::{storage_init, storage_zeroed, submit_and_read, write_f32};
use super::context::{GpuContext, GpuError};
use super::kernels::block_jacobi::{inverse_offsets, BlockBuffers};
use super::kernels::cg_scalars::{CgScalars, Status};
use super::kernels::spmv::CsrBuffers;
use super::kernels::Kernels;
use super::plan::{Plan, Vectors};
use crate::sparse::{BlockJacobi, CgResult, CsrMatrix};

#[derive(Clone, Copy, Debug)]
pub struct GpuPcgParams {
    /// Stop when `|r| <= rel_tol * |b|` (recursive residual, f32); the true
    /// residual stalls near 1e-6, see the module docs.
    pub rel_tol: f64,
    pub max_iter: usize,
    /// Iterations per submitted batch, i.e. between scalar readbacks.
    pub check_every: usize,
}

impl Default for GpuPcgParams {
    fn default() -> Self {
        GpuPcgParams {
            rel_tol: 1e-5,
            max_iter: 10_000,
            check_every: 8,
        }
    }
}

/// Outcome of [`GpuPcg::solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuCgStats {
    pub iterations: usize,
    /// Final `|r| / |b|` of the recursive f32 residual (optimistic below
    /// ~1e-6, see the module docs).
    pub rel_residual: f64,
    pub converged: bool,
    /// Stopped on a direction of non-positive curvature (matrix not PD).
    pub breakdown: bool,
    /// Host round trips for the scalar state (batches submitted).
    pub readbacks: usize,
}

impl From<GpuCgStats> for CgResult {
    fn from(s: GpuCgStats) -> Self {
        CgResult {
            iterations: s.iterations,
            rel_residual: s.rel_residual,
            converged: s.converged,
        }
    }
}

/// A PCG solver bound to one sparsity pattern and block layout.
pub struct GpuPcg {
    ctx: GpuContext,
    row_ptr: Vec<usize>,
    col_idx: Vec<u32>,
    block_starts: Vec<usize>,
    kernels: Kernels,
    csr: CsrBuffers,
    blocks: BlockBuffers,
    vectors: Vectors,
    plan: Plan,
}

impl GpuPcg {
    /// Uploads the pattern and values of `a` and the block-Jacobi inverses
    /// for blocks `block_starts` (0 = s_0 < ... < s_m = n, sizes 1..=4).
    pub fn new(ctx: &GpuContext, a: &CsrMatrix, block_starts: &[usize]) -> Result<Self, GpuError> {
        let kernels = Kernels::new(&ctx.device);
        let mut solver = Self::allocate_checked(ctx, kernels, a, block_starts)?;
        solver.update_values(a)?;
        Ok(solver)
    }

    /// True when `a` has the uploaded sparsity pattern and `block_starts`
    /// the uploaded block layout, i.e. [`GpuPcg::update_values`] suffices.
    pub fn matches(&self, a: &CsrMatrix, block_starts: &[usize]) -> bool {
        a.row_ptr == self.row_ptr && a.col_idx == self.col_idx && block_starts == self.block_starts
    }

    /// Rebinds the solver to a new pattern or block layout: new buffers and
    /// bind groups, the compiled pipelines kept. On error the solver keeps
    /// its previous pattern.
    pub fn rebind(&mut self, a: &CsrMatrix, block_starts: &[usize]) -> Result<(), GpuError> {
        let mut fresh = Self::allocate_checked(&self.ctx, self.kernels.clone(), a, block_starts)?;
        fresh.update_values(a)?;
        *self = fresh;
        Ok(())
    }

    fn allocate_checked(
        ctx: &GpuContext,
        kernels: Kernels,
        a: &CsrMatrix,
        block_starts: &[usize],
    ) -> Result<Self, GpuError> {
        // Allocation failures would otherwise reach wgpu's uncaptured-error
        // handler, which panics; a large pattern is user input.
        let scope = ctx.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let built = Self::allocate(ctx, kernels, a, block_starts);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::OutOfMemory(e.to_string()));
        }
        built
    }

    fn allocate(ctx: &GpuContext, kernels: Kernels, a: &CsrMatrix, block_starts: &[usize]) -> Result<Self, GpuError> {
        let offsets = inverse_offsets(block_starts, a.n)?;
        // The shaders index with u32, so offsets past 2^32 entries are refused.
        let too_large = |name| GpuError::BufferTooLarge {
            name,
            bytes: 4 * a.nnz().max(a.n) as u64,
            limit: 4 * u32::MAX as u64,
        };
        let n = u32::try_from(a.n).map_err(|_| too_large("vectors"))?;
        let row_ptr: Vec<u32> = a
            .row_ptr
            .iter()
            .map(|&p| u32::try_from(p).map_err(|_| too_large("row pointers")))
            .collect::<Result<_, _>>()?;
        let csr = CsrBuffers {
            n,
            row_ptr: storage_init(ctx, "row pointers", &row_ptr)?,
            col_idx: storage_init(ctx, "column indices", &a.col_idx)?,
            values: storage_zeroed(ctx, "matrix values", a.nnz())?,
        };
        let blocks = BlockBuffers::new(ctx, block_starts, &offsets)?;
        let vectors = Vectors::new(ctx, a.n)?;
        let plan = Plan::new(ctx, &kernels, &csr, &blocks, &vectors);
        Ok(GpuPcg {
            ctx: ctx.clone(),
            row_ptr: a.row_ptr.clone(),
            col_idx: a.col_idx.clone(),
            block_starts: block_starts.to_vec(),
            kernels,
            csr,
            blocks,
            vectors,
            plan,
        })
    }

    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.csr.n as usize
    }

    /// Uploads new values for the same pattern and rebuilds the block
    /// inverses (in f64 on the CPU, then rounded to f32). The pattern is
    /// compared in full: it costs less than converting the values, and a
    /// silently different pattern would make the SpMV read wrong columns.
    pub fn update_values(&mut self, a: &CsrMatrix) -> Result<(), GpuError> {
        if a.row_ptr != self.row_ptr || a.col_idx != self.col_idx {
            return Err(GpuError::PatternMismatch { n: a.n, nnz: a.nnz() });
        }
        write_f32(&self.ctx, &self.csr.values, &a.values);
        self.blocks.upload(&self.ctx, &BlockJacobi::new(a, &self.block_starts));
        Ok(())
    }

    /// Solves `A x = b` from `x0`; returns x in f64 and the iteration stats.
    pub fn solve(&self, b: &[f64], x0: &[f64], params: &GpuPcgParams) -> Result<(Vec<f64>, GpuCgStats), GpuError> {
        self.check_len(b)?;
        self.check_len(x0)?;
        let v = &self.vectors;
        write_f32(&self.ctx, &v.b, b);
        write_f32(&self.ctx, &v.x, x0);
        let initial = CgScalars {
            rel_tol: params.rel_tol as f32,
            max_iter: params.max_iter.min(u32::MAX as usize) as u32,
            ..Default::default()
        };
        self.ctx.queue.write_buffer(&v.scalars, 0, bytemuck::bytes_of(&initial));

        let batch = params.check_every.max(1);
        let mut encoder = self.encoder();
        self.plan.record_start(&mut encoder, v);
        let mut readbacks = 0;
        let scalars = loop {
            self.plan.record_iterations(&mut encoder, batch);
            let s = self.read_scalars(encoder)?;
            readbacks += 1;
            if Status::from_raw(s.status) != Status::Running {
                break s;
            }
            encoder = self.encoder();
        };
        let x = self.read_vector(self.encoder(), &v.x)?;
        let status = Status::from_raw(scalars.status);
        let b_norm = f64::from(scalars.bb).sqrt().max(f64::MIN_POSITIVE);
        Ok((
            x,
            GpuCgStats {
                iterations: scalars.iterations as usize,
                rel_residual: f64::from(scalars.rr).sqrt() / b_norm,
                converged: status == Status::Converged,
                breakdown: status == Status::Breakdown,
                readbacks,
            },
        ))
    }

    /// y = A x with the uploaded f32 matrix (kernel check and diagnostics).
    pub fn multiply(&self, x: &[f64]) -> Result<Vec<f64>, GpuError> {
        self.check_len(x)?;
        write_f32(&self.ctx, &self.vectors.d, x);
        let mut encoder = self.encoder();
        self.plan.in_pass(&mut encoder, |pass| self.plan.spmv_d.record(pass));
        self.read_vector(encoder, &self.vectors.q)
    }

    /// z = P^-1 r with the uploaded f32 block inverses.
    pub fn precondition(&self, r: &[f64]) -> Result<Vec<f64>, GpuError> {
        self.check_len(r)?;
        write_f32(&self.ctx, &self.vectors.r, r);
        let mut encoder = self.encoder();
        self.plan
            .in_pass(&mut encoder, |pass| self.plan.precondition.record(pass));
        self.read_vector(encoder, &self.vectors.z)
    }

    /// a . b with the GPU reduction (inputs rounded to f32).
    pub fn dot(&self, a: &[f64], b: &[f64]) -> Result<f64, GpuError> {
        self.check_len(a)?;
        self.check_len(b)?;
        write_f32(&self.ctx, &self.vectors.r, a);
        write_f32(&self.ctx, &self.vectors.z, b);
        let mut encoder = self.encoder();
        self.plan
            .in_pass(&mut encoder, |pass| self.plan.dot_rz_new.record(pass));
        Ok(f64::from(self.read_scalars(encoder)?.rz_new))
    }

    fn check_len(&self, v: &[f64]) -> Result<(), GpuError> {
        if v.len() != self.n() {
            return Err(GpuError::Length {
                expected: self.n(),
                got: v.len(),
            });
        }
        Ok(())
    }

    fn encoder(&self) -> wgpu::CommandEncoder {
        self.ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("pcg") })
    }

    fn read_scalars(&self, encoder: wgpu::CommandEncoder) -> Result<CgScalars, GpuError> {
        let v = &self.vectors;
        let words: Vec<CgScalars> = submit_and_read(&self.ctx, encoder, &v.scalars, &v.staging_scalars, 1)?;
        words
            .first()
            .copied()
            .ok_or_else(|| GpuError::Readback("empty scalar readback".into()))
    }

    fn read_vector(&self, encoder: wgpu::CommandEncoder, src: &wgpu::Buffer) -> Result<Vec<f64>, GpuError> {
        let values: Vec<f32> = submit_and_read(&self.ctx, encoder, src, &self.vectors.staging_vector, self.n())?;
        Ok(values.into_iter().map(f64::from).collect())
    }
}
