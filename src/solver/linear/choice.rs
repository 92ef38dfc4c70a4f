//! Which linear solver a run uses: `--solver auto|cpu-direct|cpu-cg|gpu`.
//!
//! `auto` takes the GPU only when all of these hold, and cpu-direct otherwise:
//! - the build has the `gpu` feature;
//! - the problem has at least [`AutoParams::gpu_min_dofs`] (50K) unknowns.
//!   Below that the sparse Cholesky wins: one solve of ~0.05 s at 5K
//!   unknowns, against ~2000 f32 CG iterations whose cost on a GPU is
//!   dominated by dispatch and readback latency. The Cholesky's fill grows
//!   superlinearly (0.05 s at 5K, 2.9 s at 45K on the 2-core development machine), CG's
//!   memory-bound iterations linearly; docs/GPU.md "Auto threshold" gives
//!   the estimate and the measurements behind it;
//! - an adapter opens, and it is real hardware: a software adapter (Mesa's
//!   llvmpipe, `DeviceType::Cpu`) runs the same f32 CG on the same cores as
//!   the CPU solvers, only slower, so `auto` ignores it
//!   ([`AutoParams::allow_software_adapter`] overrides this for testing).
//!
//! An explicit `gpu` choice never falls back: without an adapter it is an
//! error naming the cause, so a user who asked for the GPU is not silently
//! given a CPU run.

use super::LinearSolver;

/// The user's choice, as on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolverChoice {
    Auto,
    CpuDirect,
    CpuCg,
    Gpu,
}

/// Tuning of the `auto` rule (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct AutoParams {
    /// Smallest problem (unknowns) for which `auto` considers the GPU.
    pub gpu_min_dofs: usize,
    /// Let `auto` pick a software (CPU-emulated) adapter.
    pub allow_software_adapter: bool,
}

impl Default for AutoParams {
    fn default() -> Self {
        AutoParams {
            gpu_min_dofs: 50_000,
            allow_software_adapter: false,
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum SelectError {
    #[cfg(feature = "gpu")]
    #[error("--solver gpu: no usable GPU")]
    GpuUnavailable(#[from] crate::gpu::GpuError),
    #[error("--solver gpu: this knitsim was built without the `gpu` feature (rebuild with default features)")]
    GpuNotBuilt,
}

/// The chosen solver and a one-line explanation for the log.
pub struct Selection {
    pub solver: LinearSolver,
    pub note: String,
}

/// Resolves `choice` for a problem of `n_dofs` unknowns.
pub fn select(choice: SolverChoice, n_dofs: usize, auto: &AutoParams) -> Result<Selection, SelectError> {
    let fixed = |solver: LinearSolver, what: &str| Selection {
        solver,
        note: format!("linear solver: {what}"),
    };
    match choice {
        SolverChoice::CpuDirect => Ok(fixed(LinearSolver::direct(), "cpu-direct")),
        SolverChoice::CpuCg => Ok(fixed(LinearSolver::cg(), "cpu-cg")),
        SolverChoice::Gpu => gpu_solver(),
        SolverChoice::Auto => Ok(auto_select(n_dofs, auto)),
    }
}

/// The adapter's description when `solver` runs on a software (CPU-emulated)
/// adapter, which times the host's cores rather than a GPU; `None` for
/// the CPU solvers and hardware adapters.
pub fn software_adapter(solver: &LinearSolver) -> Option<String> {
    #[cfg(feature = "gpu")]
    if let LinearSolver::Gpu(gpu) = solver {
        if gpu.adapter().device_type == wgpu::DeviceType::Cpu {
            return Some(gpu.adapter().to_string());
        }
    }
    let _ = solver;
    None
}

#[cfg(feature = "gpu")]
fn gpu_solver() -> Result<Selection, SelectError> {
    let gpu = super::GpuSolver::with_default_adapter()?;
    let note = format!("linear solver: gpu on {}", gpu.adapter());
    Ok(Selection {
        solver: LinearSolver::Gpu(Box::new(gpu)),
        note,
    })
}

#[cfg(not(feature = "gpu"))]
fn gpu_solver() -> Result<Selection, SelectError> {
    Err(SelectError::GpuNotBuilt)
}

fn cpu_fallback(reason: String) -> Selection {
    Selection {
        solver: LinearSolver::direct(),
        note: format!("linear solver: auto -> cpu-direct ({reason})"),
    }
}

fn auto_select(n_dofs: usize, auto: &AutoParams) -> Selection {
    if n_dofs < auto.gpu_min_dofs {
        return cpu_fallback(format!(
            "{n_dofs} unknowns, below the GPU threshold of {}",
            auto.gpu_min_dofs
        ));
    }
    auto_gpu(n_dofs, auto)
}

#[cfg(feature = "gpu")]
fn auto_gpu(n_dofs: usize, auto: &AutoParams) -> Selection {
    match super::GpuSolver::with_default_adapter() {
        Ok(gpu) if gpu.adapter().device_type == wgpu::DeviceType::Cpu && !auto.allow_software_adapter => {
            cpu_fallback(format!("the only adapter, {}, is a software one", gpu.adapter()))
        }
        Ok(gpu) => {
            let note = format!("linear solver: auto -> gpu on {} ({n_dofs} unknowns)", gpu.adapter());
            Selection {
                solver: LinearSolver::Gpu(Box::new(gpu)),
                note,
            }
        }
        Err(e) => cpu_fallback(e.to_string()),
    }
}

#[cfg(not(feature = "gpu"))]
fn auto_gpu(_n_dofs: usize, _auto: &AutoParams) -> Selection {
    cpu_fallback("built without the `gpu` feature".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_problems_and_explicit_cpu_choices_stay_on_the_cpu() {
        let auto = AutoParams::default();
        let s = select(SolverChoice::Auto, auto.gpu_min_dofs - 1, &auto).unwrap();
        assert_eq!(s.solver.name(), "direct");
        assert!(s.note.contains("below the GPU threshold"), "{}", s.note);
        assert_eq!(select(SolverChoice::CpuCg, 10, &auto).unwrap().solver.name(), "cg");
        assert_eq!(
            select(SolverChoice::CpuDirect, 1 << 30, &auto).unwrap().solver.name(),
            "direct"
        );
    }

    /// Holds with or without an adapter: the explicit choice is the GPU or
    /// an error that says why, never a panic and never a silent CPU run.
    #[cfg(feature = "gpu")]
    #[test]
    fn gpu_choice_is_the_gpu_or_a_named_error() {
        match select(SolverChoice::Gpu, 10, &AutoParams::default()) {
            Ok(s) => assert_eq!(s.solver.name(), "gpu"),
            Err(e) => assert!(
                e.to_string().starts_with("--solver gpu: ") && std::error::Error::source(&e).is_some(),
                "{e}"
            ),
        }
        let eager = AutoParams {
            gpu_min_dofs: 0,
            allow_software_adapter: true,
        };
        let s = select(SolverChoice::Auto, 10, &eager).unwrap();
        assert!(["gpu", "direct"].contains(&s.solver.name()), "{}", s.note);
    }

    #[cfg(not(feature = "gpu"))]
    #[test]
    fn gpu_choice_without_the_feature_is_an_error() {
        let auto = AutoParams::default();
        let err = select(SolverChoice::Gpu, 10, &auto).err().map(|e| e.to_string());
        assert!(err.is_some_and(|e| e.contains("without the `gpu` feature")));
        let s = select(SolverChoice::Auto, 1 << 30, &auto).unwrap();
        assert_eq!(s.solver.name(), "direct");
    }
}
