// Vector updates whose scale factor may live on the GPU: factor =
// coef * scalars[slot] (or just coef when slot == NO_SLOT). Reading alpha and
// beta from the scalars buffer is what lets CG run without host round trips.

struct Params {
    n: u32,
    slot: u32,
    coef: f32,
    _pad: u32,
}

const WORKGROUP_SIZE: u32 = 256u;
const NO_SLOT: u32 = 0xffffffffu;

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> scalars: array<f32>;
@group(0) @binding(2) var<storage, read> x: array<f32>;
@group(0) @binding(3) var<storage, read_write> y: array<f32>;

fn factor() -> f32 {
    if params.slot == NO_SLOT {
        return params.coef;
    }
    return params.coef * scalars[params.slot];
}

fn index(wid: vec3<u32>, groups: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * groups.x + wid.x) * WORKGROUP_SIZE + lid;
}

// y += factor * x
@compute @workgroup_size(256)
fn axpy(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let i = index(wid, groups, lid);
    if i < params.n {
        y[i] += factor() * x[i];
    }
}

// y = x + factor * y
@compute @workgroup_size(256)
fn xpay(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let i = index(wid, groups, lid);
    if i < params.n {
        y[i] = x[i] + factor() * y[i];
    }
}
