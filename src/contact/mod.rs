//! Thickness contact for non-persistent contacts: barrier, distances, broad phase, CCD (seed 003).

pub mod barrier;
pub mod distance;
