//! knitsim: knit patterns to yarn-level simulation.
//!
//! The pipeline, one module per stage:
//! - [`pattern`]: the text format (chart, legend, repeats, written rows) to a
//!   validated, fully expanded [`pattern::Pattern`].
//! - [`topology`]: pattern to [`topology::Fabric`]: yarns as sorted `(u, x)`
//!   point lists and the persistent EoL contacts between them.
//! - [`energy`], [`rod`], [`contact`]: potentials as stencils (value,
//!   gradient, Hessian on fixed-size local vectors).
//! - [`sparse`]: the CSR matrix, block-Jacobi preconditioner and CG report
//!   that the host solvers and the GPU kernels share.
//! - [`solver`]: the mixed statics-dynamics Newton solve and its linear solvers.
//! - [`sim`]: the EoL pipeline joining the fabric and the solver: DOF
//!   layout, EIL assignment, the stencils of a step, stepping and relaxation.
//! - `gpu`: wgpu compute kernels (feature `gpu`; the module exists only with it).
//! - [`scene`]: what to simulate: pins, obstacles, layers, parameters.
//! - [`io`]: VTK, OBJ, PNG and JSON output, written atomically.
//! - [`checked`]: range checks that parameter types run while serde reads them.
//! - [`parallel`]: the thread count and the ordered parallel map that keep
//!   results independent of it.

pub mod app;
pub mod checked;
pub mod contact;
pub mod energy;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod io;
pub mod parallel;
pub mod pattern;
pub mod rod;
pub mod scene;
pub mod sim;
pub mod solver;
pub mod sparse;
pub mod topology;
