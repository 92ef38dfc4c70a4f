//! The device buffers of one solver and the dispatch sequences of PCG.
//!
//! One iteration is ten dispatches, all bound once at construction:
//! q = A d; dad = d.q; alpha; x += alpha d; r -= alpha q; z = P^-1 r;
//! rz_new = r.z; rr = r.r; beta (and the stopping test); d = z + beta d.
//! A batch of iterations is recorded into a single compute pass: WebGPU
//! orders dispatches in a pass and makes each one's storage writes visible
//! to the next, so no host synchronisation is needed inside a batch.

use super::buffers::{staging, storage_zeroed};
use super::context::{GpuContext, GpuError};
use super::kernels::block_jacobi::{self, BlockBuffers};
use super::kernels::cg_scalars::{slot, CgScalarDispatches, CgScalars};
use super::kernels::dot::{DotDispatch, MAX_PARTIALS};
use super::kernels::spmv::{self, CsrBuffers};
use super::kernels::vector_ops::{self, Factor, Update};
use super::kernels::{Dispatch, Kernels};

/// The CG vectors (f32, length n) and the scalar state.
pub(crate) struct Vectors {
    pub x: wgpu::Buffer,
    pub b: wgpu::Buffer,
    pub r: wgpu::Buffer,
    pub z: wgpu::Buffer,
    pub d: wgpu::Buffer,
    /// A d, and A x0 during start-up.
    pub q: wgpu::Buffer,
    partials: wgpu::Buffer,
    pub scalars: wgpu::Buffer,
    pub staging_scalars: wgpu::Buffer,
    pub staging_vector: wgpu::Buffer,
    n: usize,
}

impl Vectors {
    pub fn new(ctx: &GpuContext, n: usize) -> Result<Self, GpuError> {
        let scalar_words = std::mem::size_of::<CgScalars>() / 4;
        Ok(Vectors {
            x: storage_zeroed(ctx, "x", n)?,
            b: storage_zeroed(ctx, "b", n)?,
            r: storage_zeroed(ctx, "r", n)?,
            z: storage_zeroed(ctx, "z", n)?,
            d: storage_zeroed(ctx, "d", n)?,
            q: storage_zeroed(ctx, "q", n)?,
            partials: storage_zeroed(ctx, "dot partials", MAX_PARTIALS as usize)?,
            scalars: storage_zeroed(ctx, "cg scalars", scalar_words)?,
            staging_scalars: staging(ctx, "cg scalars readback", scalar_words)?,
            staging_vector: staging(ctx, "vector readback", n)?,
            n,
        })
    }

    fn bytes(&self) -> u64 {
        4 * self.n as u64
    }
}

/// Every dispatch PCG records, bound to one solver's buffers.
pub(crate) struct Plan {
    spmv_x: Dispatch,
    pub spmv_d: Dispatch,
    initial_residual: Dispatch,
    pub precondition: Dispatch,
    dot_rz: DotDispatch,
    dot_bb: DotDispatch,
    dot_dad: DotDispatch,
    pub dot_rz_new: DotDispatch,
    dot_rr: DotDispatch,
    scalars: CgScalarDispatches,
    update_x: Dispatch,
    update_r: Dispatch,
    update_d: Dispatch,
}

impl Plan {
    pub fn new(ctx: &GpuContext, k: &Kernels, csr: &CsrBuffers, blocks: &BlockBuffers, v: &Vectors) -> Self {
        let n = csr.n;
        let dot = |a, b, out_slot| DotDispatch::new(ctx, k, n, (a, b), &v.partials, &v.scalars, out_slot);
        let update =
            |kind, coef, slot, x, y| vector_ops::dispatch(ctx, k, kind, n, Factor { coef, slot }, &v.scalars, (x, y));
        Plan {
            spmv_x: spmv::dispatch(ctx, k, csr, &v.x, &v.q),
            spmv_d: spmv::dispatch(ctx, k, csr, &v.d, &v.q),
            initial_residual: update(Update::Axpy, -1.0, None, &v.q, &v.r),
            precondition: block_jacobi::dispatch(ctx, k, blocks, &v.r, &v.z),
            dot_rz: dot(&v.r, &v.z, slot::RZ),
            dot_bb: dot(&v.b, &v.b, slot::BB),
            dot_dad: dot(&v.d, &v.q, slot::DAD),
            dot_rz_new: dot(&v.r, &v.z, slot::RZ_NEW),
            dot_rr: dot(&v.r, &v.r, slot::RR),
            scalars: CgScalarDispatches::new(&ctx.device, k, &v.scalars),
            update_x: update(Update::Axpy, 1.0, Some(slot::ALPHA), &v.d, &v.x),
            update_r: update(Update::Axpy, -1.0, Some(slot::ALPHA), &v.q, &v.r),
            update_d: update(Update::Xpay, 1.0, Some(slot::BETA), &v.z, &v.d),
        }
    }

    /// r = b - A x, z = P^-1 r, d = z and the initial scalars (rz, rr, bb,
    /// tolerance, status). Needs x, b and the CG scalars already written.
    pub fn record_start(&self, encoder: &mut wgpu::CommandEncoder, v: &Vectors) {
        self.in_pass(encoder, |pass| self.spmv_x.record(pass));
        encoder.copy_buffer_to_buffer(&v.b, 0, &v.r, 0, v.bytes());
        self.in_pass(encoder, |pass| {
            self.initial_residual.record(pass);
            self.precondition.record(pass);
        });
        encoder.copy_buffer_to_buffer(&v.z, 0, &v.d, 0, v.bytes());
        self.in_pass(encoder, |pass| {
            self.dot_rz.record(pass);
            self.dot_rr.record(pass);
            self.dot_bb.record(pass);
            self.scalars.start.record(pass);
        });
    }

    /// `count` PCG iterations; those after the stopping test fired are no-ops
    /// (alpha = beta = 0 and the iteration counter frozen).
    pub fn record_iterations(&self, encoder: &mut wgpu::CommandEncoder, count: usize) {
        self.in_pass(encoder, |pass| {
            for _ in 0..count {
                self.spmv_d.record(pass);
                self.dot_dad.record(pass);
                self.scalars.alpha.record(pass);
                self.update_x.record(pass);
                self.update_r.record(pass);
                self.precondition.record(pass);
                self.dot_rz_new.record(pass);
                self.dot_rr.record(pass);
                self.scalars.beta.record(pass);
                self.update_d.record(pass);
            }
        });
    }

    pub fn in_pass(&self, encoder: &mut wgpu::CommandEncoder, body: impl FnOnce(&mut wgpu::ComputePass<'_>)) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("pcg"),
            timestamp_writes: None,
        });
        body(&mut pass);
    }
}
