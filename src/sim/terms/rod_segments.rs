//! The rod along each yarn's real points: stretch and inertia per segment,
//! bending per triple (docs/MODEL.md, "Energies"; "Incremental potential").
//!
//! Inertia exists only in a step with a time step (`StepInputs::inertia`);
//! its mass matrix is evaluated at the step's start and held.

use super::{set, TermInputs};
use crate::rod::{bending::Bending, inertia::Inertia, mass::segment_mass, stretch::Stretch};
use crate::sim::discretization::{arr, gather, Discretization};
use crate::solver::assembly::AnyStencilSet;

/// The `stretch`, `bending` and `inertia` sets, in that order.
pub fn build(t: &TermInputs) -> Vec<Box<dyn AnyStencilSet>> {
    let (disc, p) = (t.disc, t.params);
    let (mut st, mut sd, mut bt, mut bd, mut it, mut id) = (vec![], vec![], vec![], vec![], vec![], vec![]);
    for (y, real) in disc.real.iter().enumerate() {
        let rp = &p.yarn_rod(disc.f.yarns[y].layer);
        for d in segment_dofs(disc, y, real) {
            st.push(Stretch::new(rp.ks));
            sd.push(d);
            if let Some((h, pred)) = t.step.inertia {
                let m = segment_mass(rp.rho, &gather(t.q, &d)) / (h * h);
                it.push(Inertia {
                    m_over_h2: m,
                    pred: gather(pred, &d),
                });
                id.push(d);
            }
        }
        if p.terms.bending {
            for w in real.windows(3) {
                let mut d = Vec::with_capacity(12);
                for &pi in w {
                    disc.xu(y, pi, &mut d);
                }
                bt.push(Bending::new(rp.kb).with_hessian(p.bending_hessian));
                bd.push(arr::<12>(d));
            }
        }
    }
    vec![set("stretch", st, sd), set("bending", bt, bd), set("inertia", it, id)]
}

/// The `[x_a, u_a, x_b, u_b]` dofs of every segment between consecutive
/// real points of yarn `y`.
pub(crate) fn segment_dofs<'a>(
    disc: &'a Discretization<'a>,
    y: usize,
    real: &'a [usize],
) -> impl Iterator<Item = [u32; 8]> + 'a {
    real.windows(2).map(move |w| {
        let mut d = Vec::with_capacity(8);
        disc.xu(y, w[0], &mut d);
        disc.xu(y, w[1], &mut d);
        arr(d)
    })
}
