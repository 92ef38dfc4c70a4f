// z = P^-1 r for a block-diagonal P with blocks of 1..=4 unknowns, one
// invocation per block. The inverses come from the CPU (f64, then cast), so
// the kernel is a small dense mat-vec per block.

struct Params {
    n_blocks: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

const WORKGROUP_SIZE: u32 = 256u;
const MAX_BLOCK: u32 = 4u;

@group(0) @binding(0) var<uniform> params: Params;
// First unknown of each block; entry n_blocks closes the last block.
@group(0) @binding(1) var<storage, read> block_starts: array<u32>;
// Offset of each block's row-major inverse in `inv`.
@group(0) @binding(2) var<storage, read> inv_offsets: array<u32>;
@group(0) @binding(3) var<storage, read> inv: array<f32>;
@group(0) @binding(4) var<storage, read> r: array<f32>;
@group(0) @binding(5) var<storage, read_write> z: array<f32>;

@compute @workgroup_size(256)
fn block_jacobi(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let block = (wid.y * groups.x + wid.x) * WORKGROUP_SIZE + lid;
    if block >= params.n_blocks {
        return;
    }
    let start = block_starts[block];
    let size = min(block_starts[block + 1u] - start, MAX_BLOCK);
    let offset = inv_offsets[block];
    // Stage the block of r in registers: each entry is used `size` times.
    var local_r: array<f32, 4>;
    for (var j = 0u; j < size; j++) {
        local_r[j] = r[start + j];
    }
    for (var i = 0u; i < size; i++) {
        var acc = 0.0;
        for (var j = 0u; j < size; j++) {
            acc += inv[offset + i * size + j] * local_r[j];
        }
        z[start + i] = acc;
    }
}
