// Dot product a . b in two atomics-free passes.
//
// `partial`: a fixed number of workgroups stride over the vectors; each thread
// accumulates a short serial sum, then the workgroup tree-reduces in shared
// memory and writes one partial. `finish`: a single workgroup reduces the
// partials and stores the result into `out[out_slot]`, which stays on the GPU
// (the CG scalars live there). Tree reductions keep the f32 rounding error
// growing with log2(n) instead of n.

struct Params {
    // Vector length (pass 1).
    n: u32,
    // Number of partials written by pass 1 = its workgroup count.
    n_partials: u32,
    // Index in `out` (an f32 view of the CG scalars) receiving the result.
    out_slot: u32,
    _pad: u32,
}

const WORKGROUP_SIZE: u32 = 256u;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> a: array<f32>;
@group(0) @binding(2) var<storage, read> b: array<f32>;
@group(0) @binding(3) var<storage, read_write> partials: array<f32>;
@group(0) @binding(4) var<storage, read_write> out: array<f32>;

var<workgroup> scratch: array<f32, 256>;

fn reduce_scratch(lid: u32) {
    for (var stride = WORKGROUP_SIZE / 2u; stride > 0u; stride /= 2u) {
        if lid < stride {
            scratch[lid] += scratch[lid + stride];
        }
        workgroupBarrier();
    }
}

@compute @workgroup_size(256)
fn partial(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    var acc = 0.0;
    let grid = groups.x * WORKGROUP_SIZE;
    for (var i = wid.x * WORKGROUP_SIZE + lid; i < params.n; i += grid) {
        acc += a[i] * b[i];
    }
    scratch[lid] = acc;
    workgroupBarrier();
    reduce_scratch(lid);
    if lid == 0u {
        partials[wid.x] = scratch[0];
    }
}

@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_index) lid: u32) {
    var acc = 0.0;
    for (var i = lid; i < params.n_partials; i += WORKGROUP_SIZE) {
        acc += partials[i];
    }
    scratch[lid] = acc;
    workgroupBarrier();
    reduce_scratch(lid);
    if lid == 0u {
        out[params.out_slot] = scratch[0];
    }
}
