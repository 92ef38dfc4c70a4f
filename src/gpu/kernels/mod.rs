//! Compute pipelines, one per WGSL entry point, and recorded dispatches.
//!
//! Each submodule pairs one `shaders/*.wgsl` file with its parameter struct
//! (a `#[repr(C)]` mirror of the WGSL uniform) and a constructor that binds
//! concrete buffers. Bind groups are built once per solver: during CG only
//! buffer contents change, so an iteration is a replay of prebuilt
//! [`Dispatch`]es. Pipelines use wgpu's automatic layouts, derived from the
//! bindings each entry point actually touches.

pub(crate) mod block_jacobi;
pub(crate) mod cg_scalars;
pub(crate) mod dot;
pub(crate) mod spmv;
pub(crate) mod vector_ops;

/// The pipelines of all kernels. Compiled once per [`crate::gpu::GpuPcg`]
/// and kept when the solver is rebound to a new pattern: shader compilation
/// is the slowest part of setup on a software adapter, and the pipelines do
/// not depend on buffer sizes. Cloning copies reference-counted handles.
#[derive(Clone)]
pub(crate) struct Kernels {
    pub spmv: wgpu::ComputePipeline,
    pub block_jacobi: wgpu::ComputePipeline,
    pub dot_partial: wgpu::ComputePipeline,
    pub dot_finish: wgpu::ComputePipeline,
    pub axpy: wgpu::ComputePipeline,
    pub xpay: wgpu::ComputePipeline,
    pub cg_start: wgpu::ComputePipeline,
    pub cg_alpha: wgpu::ComputePipeline,
    pub cg_beta: wgpu::ComputePipeline,
}

impl Kernels {
    pub fn new(device: &wgpu::Device) -> Self {
        let spmv = module(device, "spmv", spmv::SOURCE);
        let block_jacobi = module(device, "block_jacobi", block_jacobi::SOURCE);
        let dot = module(device, "dot", dot::SOURCE);
        let vector_ops = module(device, "vector_ops", vector_ops::SOURCE);
        let cg = module(device, "cg_scalars", cg_scalars::SOURCE);
        Kernels {
            spmv: pipeline(device, &spmv, "spmv"),
            block_jacobi: pipeline(device, &block_jacobi, "block_jacobi"),
            dot_partial: pipeline(device, &dot, "partial"),
            dot_finish: pipeline(device, &dot, "finish"),
            axpy: pipeline(device, &vector_ops, "axpy"),
            xpay: pipeline(device, &vector_ops, "xpay"),
            cg_start: pipeline(device, &cg, "start"),
            cg_alpha: pipeline(device, &cg, "step_alpha"),
            cg_beta: pipeline(device, &cg, "step_beta"),
        }
    }
}

fn module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

fn pipeline(device: &wgpu::Device, module: &wgpu::ShaderModule, entry: &str) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// A pipeline with its bound buffers and workgroup grid, ready to record.
pub(crate) struct Dispatch {
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    groups: (u32, u32),
}

impl Dispatch {
    /// Binds `(binding, buffer)` pairs to group 0 of `pipeline`.
    pub fn new(
        device: &wgpu::Device,
        pipeline: &wgpu::ComputePipeline,
        bindings: &[(u32, &wgpu::Buffer)],
        groups: (u32, u32),
    ) -> Self {
        let entries: Vec<wgpu::BindGroupEntry> = bindings
            .iter()
            .map(|&(binding, buffer)| wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        Dispatch {
            pipeline: pipeline.clone(),
            bind_group,
            groups,
        }
    }

    pub fn record(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
    }
}
