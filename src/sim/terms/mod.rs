//! The terms layer: which stencils exist for the current discretization.
//!
//! Per yarn, the sorted non-EIL ("real") points define the rod: stretch and
//! inertia per pair, bending per triple (docs/MODEL.md, "Energies": EIL
//! points are skipped, so a degenerate segment never enters an elastic
//! term). Per contact, an EIL point gets the soft constraint to its partner
//! through the interpolation. Wrapping, shear and parallel-contact terms act
//! on real points only; when one of their points is EIL this step the term
//! is left out for the step (documented simplification: those points are by
//! construction within 10% of a segment from a real point).
//!
//! **One builder per term family.** Each file builds the stencil sets of one
//! family from the same [`TermInputs`] and knows nothing of the others;
//! [`FAMILIES`] lists them. A new energy term is one new file here and one
//! line in that list.
//!
//! **The list is ordered.** Assembly sums the sets in the order they come,
//! so the order of [`FAMILIES`] (and of the sets and stencils each builder
//! returns) fixes the floating-point sums of the gradient and Hessian. It is
//! the order the terms have always been assembled in; reordering it changes
//! results in the last bits, and with them Newton's path.
//!
//! Two files here are not families of the list:
//! - [`coulomb_limits`]: the friction springs' Coulomb limits and anchors,
//!   per-step inputs of [`friction_springs`] computed from the state;
//! - [`thickness_contact`]: non-persistent contact, whose candidate set is
//!   rebuilt inside a Newton solve (`sim::problem`) and so is attached to the
//!   problem rather than built here.

pub mod coulomb_limits;
pub mod crossing_angles;
pub mod eil_constraints;
pub mod end_stops;
pub mod friction_springs;
pub mod mass_damping;
pub mod obstacle_contact;
pub mod obstacle_friction;
pub mod parallel_yarns;
pub mod rod_segments;
pub mod segment_weight;
pub mod thickness_contact;

use super::discretization::rest_data::RestData;
use super::discretization::Discretization;
use super::params::SimParams;
use crate::energy::Stencil;
use crate::solver::assembly::{AnyStencilSet, StencilSet};

/// Inputs of a step that are not positions.
#[derive(Clone, Debug)]
pub struct StepInputs<'a> {
    /// Time step and predicted coordinates `q_n + h v_n`; `None` = statics.
    pub inertia: Option<(f64, &'a [f64])>,
    /// Friction anchors, one per global point.
    pub anchors: &'a [f64],
    /// Coulomb limit `mu |f_n|` per global point.
    pub friction_limits: &'a [f64],
}

/// Everything a term builder reads.
pub struct TermInputs<'a> {
    pub disc: &'a Discretization<'a>,
    pub q: &'a [f64],
    pub params: &'a SimParams,
    pub rest: &'a RestData,
    pub step: &'a StepInputs<'a>,
    /// The radius of every yarn (`SimParams::yarn_radii`).
    pub radii: Vec<f64>,
}

/// A term family's builder: its stencil sets, empty ones allowed.
pub type Family = fn(&TermInputs) -> Vec<Box<dyn AnyStencilSet>>;

/// Every term family, in assembly order (see the module docs).
pub const FAMILIES: &[Family] = &[
    rod_segments::build,      // stretch, bending, inertia
    segment_weight::build,    // gravity
    eil_constraints::build,   // EIL-to-point and EIL-to-EIL springs
    friction_springs::build,  // capped springs on contact `u`
    crossing_angles::build,   // wrapping, shear
    parallel_yarns::build,    // parallel-yarn contact
    end_stops::build,         // secured yarn ends
    obstacle_contact::build,  // scene obstacles
    obstacle_friction::build, // friction against obstacles (dynamics)
    mass_damping::build,      // mass-proportional damping (dynamics)
];

/// All stencil sets of a step. Terms that are off, or have no instance in
/// this fabric, produce no set.
pub fn build_sets(
    disc: &Discretization,
    q: &[f64],
    p: &SimParams,
    rest: &RestData,
    step: &StepInputs,
) -> Vec<Box<dyn AnyStencilSet>> {
    let inputs = TermInputs {
        disc,
        q,
        params: p,
        rest,
        step,
        radii: p.yarn_radii(disc.f),
    };
    FAMILIES
        .iter()
        .flat_map(|build| build(&inputs))
        .filter(|s| !s.is_empty())
        .collect()
}

/// A named stencil set, boxed for the problem's list.
pub(crate) fn set<S: Stencil<N> + Send + Sync + 'static, const N: usize>(
    name: &str,
    stencils: Vec<S>,
    dofs: Vec<[u32; N]>,
) -> Box<dyn AnyStencilSet> {
    Box::new(StencilSet::new(name, stencils, dofs))
}

#[cfg(test)]
#[path = "radii_tests.rs"]
mod radii_tests;
