//! wgpu compute solver.
