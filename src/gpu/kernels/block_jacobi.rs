//! z = P^-1 r with per-block inverses, `shaders/block_jacobi.wgsl`.
//!
//! The inverses are computed by the CPU [`BlockJacobi`] in f64 and only then
//! rounded to f32: inverting a stiff 3x3 block in f32 would lose digits the
//! preconditioner needs, while storing the finished inverse in f32 costs one
//! rounding per entry.

use super::{Dispatch, Kernels};
use crate::gpu::buffers::{grid, storage_init, storage_zeroed, uniform};
use crate::gpu::context::{GpuContext, GpuError};
use crate::sparse::BlockJacobi;
use bytemuck::{Pod, Zeroable};

pub(crate) const SOURCE: &str = include_str!("../../../shaders/block_jacobi.wgsl");

/// Largest block the shader handles (it stages a block of r in 4 registers).
pub(crate) const MAX_BLOCK: usize = 4;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    n_blocks: u32,
    _pad: [u32; 3],
}

/// The block layout (fixed) and the inverse entries (refreshed per matrix).
pub(crate) struct BlockBuffers {
    pub n_blocks: u32,
    pub starts: wgpu::Buffer,
    pub offsets: wgpu::Buffer,
    pub inv: wgpu::Buffer,
}

/// Checks `starts` (0 = s_0 < s_1 < ... = n, blocks of 1..=MAX_BLOCK) and
/// returns the offset of each block's inverse, closed by the total length.
pub(crate) fn inverse_offsets(starts: &[usize], n: usize) -> Result<Vec<u32>, GpuError> {
    if starts.first() != Some(&0) || starts.last() != Some(&n) {
        return Err(GpuError::BlockStarts { n });
    }
    let mut offsets = Vec::with_capacity(starts.len());
    let mut total = 0usize;
    for (block, w) in starts.windows(2).enumerate() {
        let size = w[1].checked_sub(w[0]).ok_or(GpuError::BlockStarts { n })?;
        if !(1..=MAX_BLOCK).contains(&size) {
            return Err(GpuError::BlockSize { block, size });
        }
        offsets.push(total as u32);
        total += size * size;
    }
    offsets.push(total as u32);
    Ok(offsets)
}

impl BlockBuffers {
    pub fn new(ctx: &GpuContext, starts: &[usize], offsets: &[u32]) -> Result<Self, GpuError> {
        let starts32: Vec<u32> = starts.iter().map(|&s| s as u32).collect();
        let inv_len = offsets.last().copied().unwrap_or(0) as usize;
        Ok(BlockBuffers {
            n_blocks: (starts.len() - 1) as u32,
            starts: storage_init(ctx, "block starts", &starts32)?,
            offsets: storage_init(ctx, "block inverse offsets", offsets)?,
            inv: storage_zeroed(ctx, "block inverses", inv_len)?,
        })
    }

    /// Uploads the inverses of a preconditioner built on the same blocks.
    pub fn upload(&self, ctx: &GpuContext, pre: &BlockJacobi) {
        crate::gpu::buffers::write_f32(ctx, &self.inv, &pre.inv);
    }
}

pub(crate) fn dispatch(
    ctx: &GpuContext,
    kernels: &Kernels,
    blocks: &BlockBuffers,
    r: &wgpu::Buffer,
    z: &wgpu::Buffer,
) -> Dispatch {
    let params = uniform(
        ctx,
        "block jacobi params",
        &Params {
            n_blocks: blocks.n_blocks,
            _pad: [0; 3],
        },
    );
    Dispatch::new(
        &ctx.device,
        &kernels.block_jacobi,
        &[
            (0, &params),
            (1, &blocks.starts),
            (2, &blocks.offsets),
            (3, &blocks.inv),
            (4, r),
            (5, z),
        ],
        grid(blocks.n_blocks, ctx.max_workgroups_per_dim),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_accumulate_squared_block_sizes() {
        assert_eq!(inverse_offsets(&[0, 3, 4, 6], 6).unwrap(), vec![0, 9, 10, 14]);
    }

    #[test]
    fn rejects_bad_layouts() {
        assert!(matches!(
            inverse_offsets(&[0, 5], 5),
            Err(GpuError::BlockSize { block: 0, size: 5 })
        ));
        assert!(matches!(
            inverse_offsets(&[0, 2, 2, 3], 3),
            Err(GpuError::BlockSize { block: 1, size: 0 })
        ));
        assert!(matches!(
            inverse_offsets(&[0, 2], 3),
            Err(GpuError::BlockStarts { n: 3 })
        ));
        assert!(matches!(inverse_offsets(&[1, 3], 3), Err(GpuError::BlockStarts { .. })));
    }
}
