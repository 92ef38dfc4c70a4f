//! The EoL simulation pipeline: from a [`Fabric`](crate::topology::Fabric)
//! to the generic Newton problem and back.
//!
//! This is the only place that knows both the EoL data model and the solver:
//! the DOF layout, the per-step EIL assignment, which stencils exist for the
//! current discretization, and the time-stepping and relaxation loops. The
//! energies themselves (`rod`, `contact`, `scene`) and the solver (`solver`)
//! stay generic.

pub mod assignment;
pub mod contact_terms;
pub mod dofs;
pub mod end_stops;
pub mod force_scale;
pub mod friction;
pub mod inertia;
pub mod params;
pub mod problem;
pub mod relax;
pub mod removal;
pub mod separation;
pub mod simulation;
pub mod slide_stops;
pub mod system;
pub mod transfer;
pub mod tripwire;

pub use contact_terms::{ContactModeName, ContactParams};
pub use force_scale::ForceScale;
pub use params::{SimParams, Terms, YarnRadii};
pub use relax::{configure as configure_relax, relax, RelaxOptions, RelaxReport};
pub use separation::SeparationParams;
pub use simulation::{SimError, Simulation, StepReport};
