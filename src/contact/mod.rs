//! Thickness contact for non-persistent contacts: barrier, distances, broad phase, CCD (seed 003).

pub mod barrier;
pub mod broad_phase;
pub mod ccd;
pub mod distance;
pub mod filter;
pub mod rest;
pub mod set;
pub mod stencil;

#[cfg(test)]
mod test_util;
