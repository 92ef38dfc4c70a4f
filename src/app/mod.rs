//! The library side of the `knitsim` commands: loading inputs the way the
//! CLI accepts them, and the relax and drape jobs with their outputs. Kept in the library
//! (not the binary) so tests and examples run exactly what the CLI runs.

pub mod checks;
pub mod drape;
pub mod input;
pub mod relax_job;
pub mod stability;
pub mod study;
pub mod summary;

pub use checks::{check_state, Limits, NotConverged, RunStatus, StateChecks};
pub use drape::{run_drape, DrapeJob, DrapeOutcome};
pub use input::{load_fabric, InputError, Loaded};
pub use relax_job::{run_relax, RelaxJob, RelaxOutcome};
pub use summary::Summary;
