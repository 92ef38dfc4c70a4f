//! Thickness contact for non-persistent yarn-yarn contacts (docs/MODEL.md,
//! "Thickness contact"): the IPC barrier with its locking-free filter, robust
//! segment distances, a spatial-hash broad phase and additive CCD.
//!
//! Why these pieces: yarns have a real thickness `h`, but at the resolutions
//! knits need, neighbouring segments of one yarn are closer than `h` at rest.
//! A plain barrier then pushes them apart (contact locking); culling those
//! pairs lets yarns pass through themselves. The filter keeps every pair but
//! gives pairs that are close *in the rest structure* a smaller, single-phase
//! barrier ([`filter`]). CCD ([`ccd`]) caps each line-search step, so no
//! pair ever crosses its barrier's core and the solve stays intersection-free.
//!
//! Data flow for one state ([`set::ContactSet`]):
//! 1. [`broad_phase`]: candidate segment pairs within `h` (unfiltered).
//! 2. [`rest`] + [`filter`]: reference distance `dbar` and the mode's rule
//!    give each pair a barrier shape `(a, eta)` or drop it.
//! 3. [`distance`] + [`stencil`]: active pairs become 12-coordinate stencils
//!    `kappa b(d(x), a, eta)` with exact derivatives ([`barrier`] holds the
//!    scalar barrier and IPC's adaptive `kappa`).
//! 4. [`ccd`]: the largest safe step along a Newton direction.
//!
//! [`exclusion`] drops pairs joined by a persistent EoL contact. The wiring
//! into the simulator (candidate lists per solve, adaptive stiffness, the
//! CCD line-search cap) is `sim::terms::thickness_contact`; docs/CONTACT.md gives the
//! user-level view.
//!
//! Reference values: `tests/contact_ipctk.rs` compares barrier, distances
//! and CCD with ipc-toolkit (fixtures from `scripts/ipctk_fixtures.py`).

pub mod barrier;
pub mod broad_phase;
pub mod ccd;
pub mod distance;
pub mod exclusion;
pub mod filter;
pub mod rest;
pub mod set;
pub mod stencil;

pub use filter::{ContactMode, ThicknessParams};
pub use rest::ContactSegments;
pub use set::{ContactEnergy, ContactSet, ContactStencil};

#[cfg(test)]
mod test_util;
