//! Adapter and device selection.
//!
//! One [`GpuContext`] owns a device and its queue; solvers clone the (cheap,
//! reference-counted) handles. We ask for the adapter's own limits instead of
//! the WebGPU defaults because the default storage-binding cap (128 MiB) is
//! reached by a Hessian with ~1M unknowns, while desktop GPUs and llvmpipe
//! allow far more. Buffers above the device's cap are refused with
//! [`GpuError::BufferTooLarge`] rather than left to a wgpu validation panic.
//!
//! Tests need to behave differently on machines without any adapter: a
//! developer laptop without Vulkan should skip, CI (which installs llvmpipe)
//! must not silently skip. [`adapter_required`] reads `KNITSIM_REQUIRE_ADAPTER`
//! to tell the two apart.

use std::fmt;
use thiserror::Error;

/// Environment variable that turns "no adapter" from a skip into a failure.
pub const REQUIRE_ADAPTER_ENV: &str = "KNITSIM_REQUIRE_ADAPTER";

#[derive(Debug, Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found (wgpu: {0}); install a Vulkan driver, e.g. `mesa-vulkan-drivers` \
         for the llvmpipe software adapter"
    )]
    NoAdapter(String),
    #[error("the adapter refused to create a device: {0}")]
    Device(String),
    #[error("buffer `{name}` needs {bytes} bytes, above the device limit of {limit} bytes")]
    BufferTooLarge { name: &'static str, bytes: u64, limit: u64 },
    #[error("the device ran out of memory while allocating the solver: {0}")]
    OutOfMemory(String),
    #[error("block {block} has size {size}; the GPU preconditioner supports blocks of 1..=4 unknowns")]
    BlockSize { block: usize, size: usize },
    #[error("block starts must increase from 0 to n = {n}")]
    BlockStarts { n: usize },
    #[error("matrix pattern differs from the one uploaded (n {n}, nnz {nnz})")]
    PatternMismatch { n: usize, nnz: usize },
    #[error("vector length {got} does not match the system size {expected}")]
    Length { expected: usize, got: usize },
    #[error("reading results back from the GPU failed: {0}")]
    Readback(String),
}

/// A device, its queue and a description of the adapter behind them.
#[derive(Clone, Debug)]
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: AdapterSummary,
    /// Largest workgroup count per dispatch dimension; kernels switch to a 2D
    /// grid above it. Taken from the device limits (65535 on most devices).
    pub max_workgroups_per_dim: u32,
}

/// What the user should see in logs and benchmark tables.
#[derive(Clone, Debug)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: wgpu::Backend,
    pub device_type: wgpu::DeviceType,
    pub driver: String,
}

impl fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({:?}, {:?}", self.name, self.backend, self.device_type)?;
        if !self.driver.is_empty() {
            write!(f, ", {}", self.driver)?;
        }
        write!(f, ")")
    }
}

impl GpuContext {
    /// Picks the high-performance adapter (discrete GPU over integrated over
    /// software) and opens a device with the adapter's full limits.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Self, GpuError> {
        // Vulkan/Metal/DX12 only: the GL backend's compute support is patchy
        // and probing it on a headless machine only produces noise.
        // `WGPU_BACKEND` still overrides the choice.
        let descriptor = wgpu::InstanceDescriptor {
            backends: wgpu::Backends::PRIMARY,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        };
        let instance = wgpu::Instance::new(descriptor.with_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("knitsim"),
                required_limits: limits.clone(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(GpuContext {
            device,
            queue,
            adapter: AdapterSummary {
                name: info.name,
                backend: info.backend,
                device_type: info.device_type,
                driver: info.driver,
            },
            max_workgroups_per_dim: limits.max_compute_workgroups_per_dimension,
        })
    }

    /// Lowers the per-dimension workgroup cap so that small problems exercise
    /// the 2D dispatch path (used by the parity tests).
    pub fn with_max_workgroups_per_dim(mut self, max: u32) -> Self {
        self.max_workgroups_per_dim = max.clamp(1, self.max_workgroups_per_dim);
        self
    }

    /// Largest buffer that one storage binding may cover on this device.
    pub fn max_binding_bytes(&self) -> u64 {
        let l = self.device.limits();
        l.max_storage_buffer_binding_size.min(l.max_buffer_size)
    }
}

/// True when `KNITSIM_REQUIRE_ADAPTER=1`: GPU tests must fail, not skip,
/// when [`GpuContext::new`] finds no adapter.
pub fn adapter_required() -> bool {
    std::env::var(REQUIRE_ADAPTER_ENV).is_ok_and(|v| v == "1")
}
