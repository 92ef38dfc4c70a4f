//! Newton solver, assembly and linear solvers.
//!
//! - [`assembly`]: stencils to a global gradient and sparse Hessian.
//! - [`newton`] with [`line_search`]: minimisation of the incremental
//!   potential over the free coordinates (docs/MODEL.md, "Solver").
//! - [`linear`]: the solvers for each Newton step.

pub mod assembly;
pub mod line_search;
pub mod linear;
pub mod newton;

#[cfg(test)]
mod test_stencils;
