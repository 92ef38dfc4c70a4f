//! The scalar CG state kept on the GPU, `shaders/cg_scalars.wgsl`.
//!
//! alpha = rz / d.Ad and beta = rz_new / rz are formed by one-invocation
//! kernels, and the stopping test `r.r <= rel_tol^2 b.b` is evaluated there
//! too, so the host reads this 48-byte struct only to decide whether to
//! submit another batch.

use super::{Dispatch, Kernels};
use bytemuck::{Pod, Zeroable};
use std::mem::offset_of;

pub(crate) const SOURCE: &str = include_str!("../../../shaders/cg_scalars.wgsl");

/// Mirror of `struct CgScalars` in the shader (all 4-byte fields, no padding).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct CgScalars {
    pub rz: f32,
    pub rz_new: f32,
    pub dad: f32,
    pub rr: f32,
    pub bb: f32,
    pub alpha: f32,
    pub beta: f32,
    pub tol2: f32,
    pub rel_tol: f32,
    pub iterations: u32,
    pub max_iter: u32,
    pub status: u32,
}

/// Index of an f32 field in the buffer viewed as `array<f32>` (dot outputs,
/// vector-op factors).
pub(crate) mod slot {
    use super::*;
    pub const RZ: u32 = (offset_of!(CgScalars, rz) / 4) as u32;
    pub const RZ_NEW: u32 = (offset_of!(CgScalars, rz_new) / 4) as u32;
    pub const DAD: u32 = (offset_of!(CgScalars, dad) / 4) as u32;
    pub const RR: u32 = (offset_of!(CgScalars, rr) / 4) as u32;
    pub const BB: u32 = (offset_of!(CgScalars, bb) / 4) as u32;
    pub const ALPHA: u32 = (offset_of!(CgScalars, alpha) / 4) as u32;
    pub const BETA: u32 = (offset_of!(CgScalars, beta) / 4) as u32;
}

/// `status` values written by the shader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Status {
    Running,
    Converged,
    /// d.Ad <= 0: the matrix is not positive definite along d.
    Breakdown,
    MaxIter,
}

impl Status {
    pub fn from_raw(raw: u32) -> Status {
        match raw {
            0 => Status::Running,
            1 => Status::Converged,
            2 => Status::Breakdown,
            _ => Status::MaxIter,
        }
    }
}

/// The three scalar steps of one solve: start, after d.Ad, after r.z.
pub(crate) struct CgScalarDispatches {
    pub start: Dispatch,
    pub alpha: Dispatch,
    pub beta: Dispatch,
}

impl CgScalarDispatches {
    pub fn new(device: &wgpu::Device, kernels: &Kernels, scalars: &wgpu::Buffer) -> Self {
        let bind = |pipeline| Dispatch::new(device, pipeline, &[(0, scalars)], (1, 1));
        CgScalarDispatches {
            start: bind(&kernels.cg_start),
            alpha: bind(&kernels.cg_alpha),
            beta: bind(&kernels.cg_beta),
        }
    }
}
