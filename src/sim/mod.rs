//! The EoL simulation pipeline: from a [`Fabric`](crate::topology::Fabric)
//! to the generic Newton problem and back.
//!
//! This is the only place that knows both the EoL data model and the
//! solver; the energies (`rod`, `contact`) and the solver
//! (`solver`) stay generic.
//!
//! # Layers
//!
//! Each layer imports only the layers below it (and the generic modules of
//! the crate), never one above:
//!
//! 1. [`params`]: every setting ([`SimParams`] and the settings of each
//!    mechanism). Below everything, because everything reads it. Beside it,
//!    [`force_scale`]: the force a relaxation's stopping test divides by.
//! 2. [`discretization`]: the DOF layout, the per-step EIL assignment, the
//!    real points and stencil dof lists of one assignment
//!    ([`Discretization`](discretization::Discretization)), where an EIL
//!    point is (`interpolated`), rest data, and the state transfer when the
//!    assignment changes.
//! 3. [`state`]: what a run carries from step to step, in one struct.
//! 4. [`terms`]: one builder per term family, each returning its stencil
//!    sets; the list of families is `terms::FAMILIES`. Also the Coulomb
//!    limits of the friction springs and the thickness contact's candidate
//!    set.
//! 5. [`problem`]: the Newton problem of a step, with the mechanisms that
//!    act inside a solve as hooks of the generic Newton loop (slide stops,
//!    tripwire, the contact trust radius) and the solve that rebuilds the
//!    contact candidates between Newton rounds.
//! 6. [`events`]: changes of the fabric between steps (contact removal,
//!    separation), functions of the state that return an edit.
//! 7. [`schedule`], [`stepper`] and [`relax`]: [`Simulation`], which owns
//!    the state, applies the events and takes the steps, each on a
//!    [`Schedule`] passed in; and quasi-static relaxation on top of it.
//!    [`dynamics`] runs implicit dynamics on top of it (pins, prescribed
//!    motions, frames, the rest test); its settings,
//!    [`dynamics_settings`], sit at layer 1 beside [`params`].
//!
//! # Adding an energy term
//!
//! Write its stencil (in `rod`, or wherever its physics belongs), then one
//! file under `terms/` with a `build(&TermInputs) -> Vec<Box<dyn
//! AnyStencilSet>>` that returns its set (empty when the term is off), and
//! one line in `terms::FAMILIES`. A switch for it goes in [`Terms`].
//! Families are assembled in list order; a new one goes at the end so the
//! sums of the existing terms keep their order.

pub mod discretization;
pub mod dynamics;
pub mod dynamics_settings;
pub mod events;
pub mod force_scale;
pub mod layers_settings;
pub mod params;
pub mod problem;
pub mod relax;
pub mod schedule;
pub mod state;
pub mod stepper;
pub mod terms;

pub use dynamics::{DynamicsReport, StepRow};
pub use dynamics_settings::DynamicsParams;
pub use events::{RemovalCause, RemovedContact};
pub use force_scale::ForceScale;
pub use layers_settings::LayersParams;
pub use params::{AssignParams, ContactModeName, ContactParams, SeparationParams, SimParams, Terms, YarnRadii};
pub use relax::{relax, schedule as relax_schedule, RelaxOptions, RelaxReport};
pub use schedule::Schedule;
pub use stepper::{SimError, Simulation, StepReport};
