//! Linear solvers for the Newton system `H dq = -g`.
//!
//! - [`cg`]: block-Jacobi preconditioned conjugate gradients on [`CsrMatrix`],
//!   the scalable CPU path and the reference for the GPU kernels.

pub mod cg;

pub use cg::{pcg, BlockJacobi, CgParams, CgResult};
