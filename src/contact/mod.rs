//! Thickness contact for non-persistent contacts: barrier, distances, broad phase, CCD (seed 003).
