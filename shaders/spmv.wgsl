// y = A x for a CSR matrix (f32 values, u32 column indices), one invocation
// per row. Rows of the knit Hessian hold ~10-40 entries, so a row per thread
// keeps every invocation busy without cross-lane reductions.

struct Params {
    n_rows: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

const WORKGROUP_SIZE: u32 = 256u;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> row_ptr: array<u32>;
@group(0) @binding(2) var<storage, read> col_idx: array<u32>;
@group(0) @binding(3) var<storage, read> values: array<f32>;
@group(0) @binding(4) var<storage, read> x: array<f32>;
@group(0) @binding(5) var<storage, read_write> y: array<f32>;

@compute @workgroup_size(256)
fn spmv(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    // 2D grid: the host spills into y once x reaches the per-dimension cap.
    let row = (wid.y * groups.x + wid.x) * WORKGROUP_SIZE + lid;
    if row >= params.n_rows {
        return;
    }
    var sum = 0.0;
    let end = row_ptr[row + 1u];
    for (var k = row_ptr[row]; k < end; k++) {
        sum += values[k] * x[col_idx[k]];
    }
    y[row] = sum;
}
