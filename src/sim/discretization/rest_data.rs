//! Rest data fixed for a whole run: the mean rest segment of each yarn and
//! the rest wrap and shear angles of each contact, measured on the compiled
//! fabric (all points real).

use super::assignment::{rest_segment_lengths, Assignment};
use super::dofs::DofLayout;
use super::{gather, Discretization};
use crate::rod::shear::Shear;
use crate::topology::Fabric;

/// Rest-state data fixed for a whole run.
#[derive(Clone, Debug)]
pub struct RestData {
    /// Mean rest segment length per yarn.
    pub rest_seg: Vec<f64>,
    /// Rest wrap angle per (contact, role): role 0 = front yarn wraps back yarn.
    pub wrap_rest: Vec<[f64; 2]>,
    /// Rest crossing angle per contact (float and layer crossings).
    pub shear_rest: Vec<f64>,
}

/// Rest data from the compiled fabric (all points real).
pub fn rest_data(f: &Fabric, l: &DofLayout, a: &Assignment, q: &[f64]) -> RestData {
    let disc = Discretization::new(f, l, a);
    let wrap_rest = (0..f.contacts.len())
        .map(|c| {
            let w = |front| {
                disc.wrap_dofs(c, front)
                    .map_or(0.0, |d| crate::rod::wrapping::wrap_angle(&gather(q, &d)))
            };
            [w(true), w(false)]
        })
        .collect();
    let shear_rest = (0..f.contacts.len())
        .map(|c| {
            disc.shear_dofs(c)
                .map_or(0.0, |d| Shear::at_rest(1.0, 0.0, 0.0, &gather(q, &d)).rest_angle)
        })
        .collect();
    RestData {
        rest_seg: rest_segment_lengths(f),
        wrap_rest,
        shear_rest,
    }
}
