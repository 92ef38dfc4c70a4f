//! a . b into a slot of the CG scalars, `shaders/dot.wgsl`.
//!
//! Pass 1 uses at most `MAX_PARTIALS` workgroups with a grid-stride loop, so
//! pass 2 always fits one workgroup (4 partials per thread) and pass 1 never
//! needs a 2D grid; at 3M unknowns each thread sums ~12 products serially
//! before the tree, which keeps the f32 error small.

use super::{Dispatch, Kernels};
use crate::gpu::buffers::{uniform, WORKGROUP_SIZE};
use crate::gpu::context::GpuContext;
use bytemuck::{Pod, Zeroable};

pub(crate) const SOURCE: &str = include_str!("../../../shaders/dot.wgsl");

/// Upper bound on pass-1 workgroups, i.e. on the partials buffer length.
pub(crate) const MAX_PARTIALS: u32 = 1024;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    n: u32,
    n_partials: u32,
    out_slot: u32,
    _pad: u32,
}

/// Both passes of one dot product; record them back to back.
pub(crate) struct DotDispatch {
    partial: Dispatch,
    finish: Dispatch,
}

impl DotDispatch {
    /// `partials` holds `MAX_PARTIALS` floats and may be shared by all dots:
    /// dispatches in a pass run in order.
    pub fn new(
        ctx: &GpuContext,
        kernels: &Kernels,
        n: u32,
        (a, b): (&wgpu::Buffer, &wgpu::Buffer),
        partials: &wgpu::Buffer,
        out: &wgpu::Buffer,
        out_slot: u32,
    ) -> Self {
        let n_partials = n
            .div_ceil(WORKGROUP_SIZE)
            .clamp(1, MAX_PARTIALS.min(ctx.max_workgroups_per_dim));
        let params = uniform(
            ctx,
            "dot params",
            &Params {
                n,
                n_partials,
                out_slot,
                _pad: 0,
            },
        );
        DotDispatch {
            partial: Dispatch::new(
                &ctx.device,
                &kernels.dot_partial,
                &[(0, &params), (1, a), (2, b), (3, partials)],
                (n_partials, 1),
            ),
            finish: Dispatch::new(
                &ctx.device,
                &kernels.dot_finish,
                &[(0, &params), (3, partials), (4, out)],
                (1, 1),
            ),
        }
    }

    pub fn record(&self, pass: &mut wgpu::ComputePass<'_>) {
        self.partial.record(pass);
        self.finish.record(pass);
    }
}
