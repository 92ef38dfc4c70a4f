//! Buffer creation, dispatch grids and readback.
//!
//! Every vector kernel runs `WORKGROUP_SIZE` (256) invocations per workgroup:
//! the WebGPU default cap on invocations per workgroup, a multiple of every
//! vendor's SIMD width (32/64) and enough to hide memory latency. A vector of
//! n entries then needs `ceil(n / 256)` workgroups; above the per-dimension
//! cap (65535 → n ≈ 16.7M) the grid folds into a second dimension and the
//! shaders rebuild the linear index from `num_workgroups`.
//!
//! Readback is the only synchronous point: [`submit_and_read`] appends a copy
//! into a mappable staging buffer to the caller's encoder, submits, and blocks
//! until the map completes.

use super::context::{GpuContext, GpuError};
use bytemuck::Pod;
use wgpu::util::DeviceExt;

/// Invocations per workgroup of the vector kernels (mirrored in `shaders/`).
pub(crate) const WORKGROUP_SIZE: u32 = 256;

/// Workgroups (x, y) covering `items` invocations of `WORKGROUP_SIZE`.
pub(crate) fn grid(items: u32, max_per_dim: u32) -> (u32, u32) {
    let groups = items.div_ceil(WORKGROUP_SIZE);
    if groups <= max_per_dim {
        (groups, 1)
    } else {
        (max_per_dim, groups.div_ceil(max_per_dim))
    }
}

fn checked_bytes(ctx: &GpuContext, name: &'static str, bytes: u64) -> Result<u64, GpuError> {
    let limit = ctx.max_binding_bytes();
    if bytes > limit {
        return Err(GpuError::BufferTooLarge { name, bytes, limit });
    }
    // Zero-sized bindings are invalid; an empty system still gets 4 bytes.
    Ok(bytes.max(4))
}

/// A storage buffer holding `data`, writable later through the queue.
pub(crate) fn storage_init<T: Pod>(ctx: &GpuContext, name: &'static str, data: &[T]) -> Result<wgpu::Buffer, GpuError> {
    let bytes: &[u8] = bytemuck::cast_slice(data);
    checked_bytes(ctx, name, bytes.len() as u64)?;
    let padded;
    let contents = if bytes.is_empty() {
        padded = [0u8; 4];
        &padded[..]
    } else {
        bytes
    };
    Ok(ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(name),
        contents,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
    }))
}

/// A zero-filled storage buffer of `len` 4-byte elements.
pub(crate) fn storage_zeroed(ctx: &GpuContext, name: &'static str, len: usize) -> Result<wgpu::Buffer, GpuError> {
    let size = checked_bytes(ctx, name, 4 * len as u64)?;
    Ok(ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(name),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    }))
}

/// A mappable buffer that receives copies of `len` 4-byte elements.
pub(crate) fn staging(ctx: &GpuContext, name: &'static str, len: usize) -> Result<wgpu::Buffer, GpuError> {
    let size = checked_bytes(ctx, name, 4 * len as u64)?;
    Ok(ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(name),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    }))
}

/// A uniform buffer holding one parameter struct.
pub(crate) fn uniform<T: Pod>(ctx: &GpuContext, name: &'static str, value: &T) -> wgpu::Buffer {
    ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(name),
        contents: bytemuck::bytes_of(value),
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

/// Writes f64 host data into an f32 device buffer.
pub(crate) fn write_f32(ctx: &GpuContext, buffer: &wgpu::Buffer, data: &[f64]) {
    if data.is_empty() {
        return;
    }
    let narrow: Vec<f32> = data.iter().map(|&v| v as f32).collect();
    ctx.queue.write_buffer(buffer, 0, bytemuck::cast_slice(&narrow));
}

/// Copies the first `count` elements of `src` into `staging`, submits the
/// encoder and waits for the mapped result.
pub(crate) fn submit_and_read<T: Pod>(
    ctx: &GpuContext,
    mut encoder: wgpu::CommandEncoder,
    src: &wgpu::Buffer,
    staging: &wgpu::Buffer,
    count: usize,
) -> Result<Vec<T>, GpuError> {
    let bytes = (count * std::mem::size_of::<T>()) as u64;
    if bytes > 0 {
        encoder.copy_buffer_to_buffer(src, 0, staging, 0, bytes);
    }
    ctx.queue.submit([encoder.finish()]);
    if bytes == 0 {
        return Ok(Vec::new());
    }
    let (sender, receiver) = std::sync::mpsc::channel();
    staging.map_async(wgpu::MapMode::Read, ..bytes, move |result| {
        // The receiver outlives the poll below; a send error cannot happen.
        let _ = sender.send(result);
    });
    ctx.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    receiver
        .recv()
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    let values = {
        let view = staging
            .get_mapped_range(..bytes)
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        bytemuck::pod_collect_to_vec(&view)
    };
    staging.unmap();
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_covers_items_and_folds_into_2d() {
        assert_eq!(grid(0, 65535), (0, 1));
        assert_eq!(grid(1, 65535), (1, 1));
        assert_eq!(grid(256, 65535), (1, 1));
        assert_eq!(grid(257, 65535), (2, 1));
        // 20M rows: 78125 groups > 65535, so two rows of groups.
        assert_eq!(grid(20_000_000, 65535), (65535, 2));
        let (x, y) = grid(3000, 4);
        assert!(x * y * WORKGROUP_SIZE >= 3000 && x == 4 && y == 3);
    }
}
