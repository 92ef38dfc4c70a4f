//! The library side of the `knitsim` commands: loading inputs the way the
//! CLI accepts them, and the relax job with its outputs. Kept in the library
//! (not the binary) so tests and examples run exactly what the CLI runs.

pub mod input;
pub mod relax_job;
pub mod study;

pub use input::{load_fabric, InputError, Loaded};
pub use relax_job::{run_relax, RelaxJob, RelaxOutcome};
