// The scalar part of PCG, run by a single invocation between the vector
// kernels so that alpha, beta and the stopping test never leave the GPU.
// The layout mirrors `CgScalars` in src/gpu/kernels/cg_scalars.rs; the dot
// kernel writes rz, rz_new, dad, rr and bb through an f32 view of it.

struct CgScalars {
    rz: f32,
    rz_new: f32,
    dad: f32,
    rr: f32,
    bb: f32,
    alpha: f32,
    beta: f32,
    tol2: f32,
    rel_tol: f32,
    iterations: u32,
    max_iter: u32,
    status: u32,
}

const RUNNING: u32 = 0u;
const CONVERGED: u32 = 1u;
const BREAKDOWN: u32 = 2u;
const MAX_ITER: u32 = 3u;

@group(0) @binding(0) var<storage, read_write> s: CgScalars;

// After r0 = b - A x0, z0 = P^-1 r0 and the dots rz, rr, bb.
@compute @workgroup_size(1)
fn start() {
    s.tol2 = s.rel_tol * s.rel_tol * s.bb;
    s.iterations = 0u;
    if s.rr <= s.tol2 {
        s.status = CONVERGED;
    } else if s.max_iter == 0u {
        s.status = MAX_ITER;
    } else {
        s.status = RUNNING;
    }
}

// After q = A d and dad = d . q. A stopped solve gets alpha = 0, so the
// iterations left in a batch leave x and r untouched.
@compute @workgroup_size(1)
fn step_alpha() {
    s.alpha = 0.0;
    if s.status != RUNNING {
        return;
    }
    if s.dad > 0.0 {
        s.alpha = s.rz / s.dad;
    } else {
        // Non-positive curvature: the matrix is not positive definite here.
        s.status = BREAKDOWN;
    }
}

// After the x, r updates, z = P^-1 r and the dots rz_new, rr.
@compute @workgroup_size(1)
fn step_beta() {
    s.beta = 0.0;
    if s.status != RUNNING {
        return;
    }
    s.iterations += 1u;
    if s.rr <= s.tol2 {
        s.status = CONVERGED;
        return;
    }
    if s.iterations >= s.max_iter {
        s.status = MAX_ITER;
        return;
    }
    s.beta = s.rz_new / s.rz;
    s.rz = s.rz_new;
}
