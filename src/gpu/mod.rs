//! wgpu compute solver: block-Jacobi preconditioned CG in f32.
//!
//! - [`context`]: adapter/device selection and [`GpuError`].
//! - [`pcg`]: [`GpuPcg`], the solver the Newton loop calls; its module docs
//!   explain the readback policy and the f32 accuracy limit.
//! - `kernels`: one Rust module per `shaders/*.wgsl` file (SpMV, block-Jacobi
//!   apply, dot reduction, axpy/xpay, CG scalars), each including its shader
//!   with `include_str!` so the binary carries no loose files.
//! - `buffers`, `plan`: buffer helpers, workgroup grids and the recorded
//!   dispatch sequence of one CG iteration.
//!
//! Why f32 and a GPU at all: the CG inner loop is memory bound (SpMV streams
//! ~8 bytes per nonzero per iteration), and f32 halves that traffic and runs
//! on every WebGPU adapter, including those without f64 support.

mod buffers;
pub mod context;
mod kernels;
pub mod pcg;
mod plan;

pub use context::{adapter_required, AdapterSummary, GpuContext, GpuError, REQUIRE_ADAPTER_ENV};
pub use pcg::{GpuCgStats, GpuPcg, GpuPcgParams};
