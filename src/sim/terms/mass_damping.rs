//! Mass-proportional damping (`dynamics.damping`, Rayleigh `alpha`): a
//! viscous force `-alpha M v` on every segment between real points, with
//! the segment's EoL mass matrix at the step's start (`rod::mass`), as the
//! quadratic stencil `rod::damping::ViscousDamping`. It damps the motion of
//! material, not sliding at the material speed (the mass matrix's null
//! direction). Built only in a step with a time step and `alpha > 0`.

use super::rod_segments::segment_dofs;
use super::{set, TermInputs};
use crate::rod::damping::ViscousDamping;
use crate::rod::mass::segment_mass;
use crate::sim::discretization::gather;
use crate::solver::assembly::AnyStencilSet;

/// The `damping` set.
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    let alpha = t.params.dynamics.damping;
    let Some((h, _)) = t.step.inertia else {
        return Vec::new();
    };
    if alpha <= 0.0 {
        return Vec::new();
    }
    let rho = t.params.rod.rho;
    let (mut st, mut sd) = (vec![], vec![]);
    for (y, real) in t.disc.real.iter().enumerate() {
        for d in segment_dofs(t.disc, y, real) {
            let q0 = gather(t.q, &d);
            st.push(ViscousDamping {
                d: segment_mass(rho, &q0) * alpha,
                q_start: q0,
                h,
            });
            sd.push(d);
        }
    }
    vec![set("damping", st, sd)]
}
