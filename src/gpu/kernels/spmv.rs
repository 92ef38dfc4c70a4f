//! y = A x on the CSR pattern, `shaders/spmv.wgsl`.

use super::{Dispatch, Kernels};
use crate::gpu::buffers::{grid, uniform};
use crate::gpu::context::GpuContext;
use bytemuck::{Pod, Zeroable};

pub(crate) const SOURCE: &str = include_str!("../../../shaders/spmv.wgsl");

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    n_rows: u32,
    _pad: [u32; 3],
}

/// The matrix as uploaded: u32 row pointers and columns, f32 values.
pub(crate) struct CsrBuffers {
    pub n: u32,
    pub row_ptr: wgpu::Buffer,
    pub col_idx: wgpu::Buffer,
    pub values: wgpu::Buffer,
}

pub(crate) fn dispatch(
    ctx: &GpuContext,
    kernels: &Kernels,
    csr: &CsrBuffers,
    x: &wgpu::Buffer,
    y: &wgpu::Buffer,
) -> Dispatch {
    let params = uniform(
        ctx,
        "spmv params",
        &Params {
            n_rows: csr.n,
            _pad: [0; 3],
        },
    );
    Dispatch::new(
        &ctx.device,
        &kernels.spmv,
        &[
            (0, &params),
            (1, &csr.row_ptr),
            (2, &csr.col_idx),
            (3, &csr.values),
            (4, x),
            (5, y),
        ],
        grid(csr.n, ctx.max_workgroups_per_dim),
    )
}
