//! Newton solver, assembly and linear solvers.

pub mod linear;
pub mod sparse;
