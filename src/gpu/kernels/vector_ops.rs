//! axpy / xpay with a factor read from the GPU, `shaders/vector_ops.wgsl`.

use super::{Dispatch, Kernels};
use crate::gpu::buffers::{grid, uniform};
use crate::gpu::context::GpuContext;
use bytemuck::{Pod, Zeroable};

pub(crate) const SOURCE: &str = include_str!("../../../shaders/vector_ops.wgsl");

/// `slot` value meaning "no GPU scalar: the factor is `coef` alone".
const NO_SLOT: u32 = u32::MAX;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    n: u32,
    slot: u32,
    coef: f32,
    _pad: u32,
}

/// The scale factor of an update: `coef * scalars[slot]`, or `coef`.
#[derive(Clone, Copy)]
pub(crate) struct Factor {
    pub coef: f32,
    pub slot: Option<u32>,
}

#[derive(Clone, Copy)]
pub(crate) enum Update {
    /// y += factor * x
    Axpy,
    /// y = x + factor * y
    Xpay,
}

pub(crate) fn dispatch(
    ctx: &GpuContext,
    kernels: &Kernels,
    update: Update,
    n: u32,
    factor: Factor,
    scalars: &wgpu::Buffer,
    (x, y): (&wgpu::Buffer, &wgpu::Buffer),
) -> Dispatch {
    let params = uniform(
        ctx,
        "vector op params",
        &Params {
            n,
            slot: factor.slot.unwrap_or(NO_SLOT),
            coef: factor.coef,
            _pad: 0,
        },
    );
    let pipeline = match update {
        Update::Axpy => &kernels.axpy,
        Update::Xpay => &kernels.xpay,
    };
    Dispatch::new(
        &ctx.device,
        pipeline,
        &[(0, &params), (1, scalars), (2, x), (3, y)],
        grid(n, ctx.max_workgroups_per_dim),
    )
}
