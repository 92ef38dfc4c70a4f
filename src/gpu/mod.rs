//! wgpu compute solver.

pub mod context;

pub use context::{adapter_required, AdapterSummary, GpuContext, GpuError, REQUIRE_ADAPTER_ENV};
