//! Rod energies on EoL/EIL yarns (docs/MODEL.md, "Energies").
//!
//! Every term is a small struct holding its parameters (stiffness, rest
//! values) and implementing [`crate::energy::Stencil`] on a fixed-size local
//! vector. A stencil's local vector is the node coordinates it reads, gathered
//! in the order documented on the struct: a node contributes its position `x`
//! (3 coordinates), a yarn point its Eulerian coordinate `u` (1 coordinate).
//! The global layout, the choice of active stencils (consecutive non-EIL
//! nodes, docs/MODEL.md, "Node assignment") and the assembly belong to the solver.
//!
//! | term | struct | local vector | N | docs/MODEL.md |
//! | --- | --- | --- | --- | --- |
//! | stretch | [`stretch::Stretch`] | `[x_a, u_a, x_b, u_b]` | 8 | "Stretch" |
//! | bending | [`bending::Bending`] | `[x0, u0, x1, u1, x2, u2]` | 12 | "Bending" |
//! | EIL-EoL contact | [`eil::EilToPoint`] | `[x_a, u_a, x_c, u_c, u, x_p]` | 12 | "EIL constraint spring" |
//! | EIL-EIL contact | [`eil::EilToEil`] | `[x_a, u_a, x_c, u_c, u, y_a, v_a, y_c, v_c, v]` | 18 | "EIL constraint spring" |
//! | friction | [`friction::FrictionSpring`] | `[u]` | 1 | "Friction anchors" |
//! | wrapping | [`wrapping::Wrapping`] | `[a_prev, p, q, a_next, b_prev, b_next]` | 18 | "Wrapping" |
//! | shear | [`shear::Shear`] | `[a_prev, a_next, b_prev, b_next]` | 12 | "Crossing shear" |
//! | parallel contact | [`parallel_contact::ParallelContact`] | `[u1, u2]` | 2 | "Parallel-yarn contact" |
//! | gravity | [`gravity::NodeGravity`], [`gravity::SegmentGravity`] | `[x]`, `[x_a, u_a, x_b, u_b]` | 3, 8 | "Gravity and obstacles" |
//! | obstacle | [`obstacle::ObstaclePenalty`] | `[x]` | 3 | "Gravity and obstacles" |
//! | obstacle friction | [`obstacle_friction::ObstacleFriction`] | `[x]` | 3 | "Obstacle friction" |
//! | soft pin | [`pin::SoftPin`] | `[x]` | 3 | - |
//!
//! The inertia of an EoL segment is not a potential; [`mass::segment_mass`]
//! gives its 8x8 mass matrix on `(xdot_a, udot_a, xdot_b, udot_b)`
//! (docs/MODEL.md, "Segment mass matrix"), and [`inertia::Inertia`] the
//! incremental potential's quadratic term built on it. Damping lives in the incremental potential; see
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
pub mod inertia;
pub mod jet;
pub mod mass;
pub mod obstacle;
pub mod obstacle_friction;
pub mod parallel_contact;
pub mod params;
pub mod pin;
pub mod shear;
pub mod stretch;
pub mod trimesh;
pub mod wrapping;

#[cfg(test)]
pub(crate) mod testutil;

pub use params::RodParams;
