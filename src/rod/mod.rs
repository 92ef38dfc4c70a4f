//! Rod energies on EoL/EIL yarns (seed 000 and Cirio 2014/2017).
//!
//! Every term is a small struct holding its parameters (stiffness, rest
//! values) and implementing [`crate::energy::Stencil`] on a fixed-size local
//! vector. A stencil's local vector is the node coordinates it reads, gathered
//! in the order documented on the struct: a node contributes its position `x`
//! (3 coordinates), a yarn point its Eulerian coordinate `u` (1 coordinate).
//! The global layout, the choice of active stencils (consecutive non-EIL
//! nodes, MODEL.md sec. 2-3) and the assembly belong to the solver.
//!
//! | term | struct | local vector | N | source |
//! | --- | --- | --- | --- | --- |
//! | stretch | [`stretch::Stretch`] | `[x_a, u_a, x_b, u_b]` | 8 | seed 000 eq. 2 |
//! | bending | [`bending::Bending`] | `[x0, u0, x1, u1, x2, u2]` | 12 | seed 000 eq. 4 |
//! | EIL-EoL contact | [`eil::EilToPoint`] | `[x_a, u_a, x_c, u_c, u, x_p]` | 12 | seed 000 eq. 3, sec. 4.2 |
//! | EIL-EIL contact | [`eil::EilToEil`] | `[x_a, u_a, x_c, u_c, u, y_a, v_a, y_c, v_c, v]` | 18 | seed 000 sec. 4.2 |
//! | friction | [`friction::FrictionSpring`] | `[u]` | 1 | Cirio 2014 |
//! | wrapping | [`wrapping::Wrapping`] | `[a_prev, p, q, a_next, b_prev, b_next]` | 18 | Cirio 2017, MODEL.md sec. 3 |
//! | shear | [`shear::Shear`] | `[a_prev, a_next, b_prev, b_next]` | 12 | Cirio 2014 |
//! | parallel contact | [`parallel::ParallelContact`] | `[u1, u2]` | 2 | Cirio 2014, seed 000 sec. 4.2 |
//! | gravity | [`gravity::NodeGravity`], [`gravity::SegmentGravity`] | `[x]`, `[x_a, u_a, x_b, u_b]` | 3, 8 | - |
//! | soft pin | [`pin::SoftPin`] | `[x]` | 3 | - |
//!
//! The inertia of an EoL segment is not a potential; [`mass::segment_mass`]
//! gives its 8x8 mass matrix on `(xdot_a, udot_a, xdot_b, udot_b)`
//! (MODEL.md sec. 1). Damping lives in the incremental potential; see
//! [`damping`].
//!
//! Angles are the delicate part: the bending angle is smooth in `theta^2` at
//! `theta = 0` but its naive derivatives divide by `sin(theta)`. [`angle`]
//! writes every angle energy as a function of `cos(theta)` so straight
//! configurations have exact, finite derivatives. Where an energy is a
//! tangle of products (wrapping), [`jet`] computes exact second derivatives by
//! forward-mode differentiation instead of a hand derivation.
//!
//! Parameters for a whole fabric are gathered in [`params::RodParams`].

pub mod angle;
pub mod bending;
pub mod bending_psd;
pub mod damping;
pub mod eil;
pub mod friction;
pub mod gravity;
pub mod jet;
pub mod mass;
pub mod parallel;
pub mod params;
pub mod pin;
pub mod shear;
pub mod stretch;
pub mod wrapping;

#[cfg(test)]
pub(crate) mod testutil;

pub use params::RodParams;
