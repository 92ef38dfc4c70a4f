//! Which candidate pairs become contact stencils, and with which barrier:
//! the compared methods and the filter of docs/MODEL.md, "Thickness contact".
//!
//! - **Barrier** (plain IPC): every pair uses the material thickness, `a = h`,
//!   with the hard core `eta`. At fine resolution neighbours along a yarn
//!   are closer than `h` at rest and push each other apart ("contact
//!   locking").
//! - **Culled**: as Barrier, but pairs within `window`
//!   segments of each other on the same yarn are dropped entirely; no
//!   locking, but also no protection against pull-through there.
//! - **Filtered**: pairs whose rest distance `dbar >= h`
//!   keep `b(d, h, eta)`; pairs with `0 < dbar < h` get the single-phase
//!   barrier `b(d, dbar_min, 0)`. Since `dbar_min <= dbar`, such a pair is
//!   inactive at rest along a straight yarn, yet it still diverges at
//!   `d = 0`, so the yarn can never pass through itself. The filter drops the
//!   core for these pairs (`eta = 0`) because `dbar_min - eta` could be tiny
//!   or negative, which would make the barrier stiff and CCD degenerate.
//! - **Penalty** (the older yarn models): `k/2 (h - d)^2` for `d < h` on
//!   every pair, no CCD; it lets yarns interpenetrate under load.
//!
//! The broad phase always uses the unfiltered activation distance `h`
//! (docs/MODEL.md, "Thickness contact"), so one candidate list serves every mode.

use super::barrier::BarrierShape;

/// The contact treatment of non-persistent yarn-yarn contacts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ContactMode {
    /// No contact between yarns (beyond the persistent EoL contacts).
    None,
    /// Stiff quadratic penalty `k/2 (h - d)^2`.
    Penalty,
    /// Plain IPC thickness barrier on every pair (*Codimensional IPC*).
    Barrier,
    /// Barrier with same-yarn pairs within `window` segments removed.
    Culled { window: u32 },
    /// The filtered barrier of docs/MODEL.md, "Thickness contact".
    #[default]
    Filtered,
}

/// Thickness settings shared by all stencils.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThicknessParams {
    /// Material thickness `h`: the centreline distance at which two yarns
    /// touch (twice the yarn radius). Also the activation distance.
    pub thickness: f64,
    /// Hard core `eta` in `[0, h)`: barriers diverge at this distance
    /// (the biphasic model of *Codimensional IPC*; 0 = single phase).
    /// *Unlocking Thickness Modeling for Codimensional Contact Simulation* uses
    /// `0.9 h` for its own method and `0.9 min(h, dbar_min)` when comparing
    /// with Barrier and Culled (see [`ThicknessParams::comparison_core`]).
    pub core: f64,
    /// Stiffness `k` of the Penalty mode.
    pub penalty_stiffness: f64,
}

impl Default for ThicknessParams {
    /// The thinnest yarn of *Unlocking Thickness Modeling for Codimensional Contact Simulation*
    /// (150D/72F, 0.177 mm) in metres, single phase.
    fn default() -> Self {
        Self {
            thickness: 0.177e-3,
            core: 0.0,
            penalty_stiffness: 1e3,
        }
    }
}

impl ThicknessParams {
    /// As in the appendix of
    /// *Unlocking Thickness Modeling for Codimensional Contact Simulation*:
    /// the core used for the Barrier and Culled
    /// comparisons, which fail at the first solve with a larger one.
    pub fn comparison_core(&self, dbar_min: f64) -> f64 {
        0.9 * self.thickness.min(dbar_min)
    }
}

/// What the filter needs to know about a candidate pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairRest {
    /// Both segments on the same yarn.
    pub same_yarn: bool,
    /// `|index_i - index_j|` along the yarn (meaningful when `same_yarn`).
    pub index_gap: u32,
    /// Reference distance `dbar_ij` (infinite when at least `h`).
    pub dbar: f64,
}

/// The barrier of a candidate pair, or `None` when the pair is skipped.
/// For [`ContactMode::Penalty`] the returned shape's activation is the
/// penalty's thickness.
pub fn stencil_shape(
    mode: ContactMode,
    pair: &PairRest,
    params: &ThicknessParams,
    dbar_min: f64,
) -> Option<BarrierShape> {
    let h = params.thickness;
    let full = BarrierShape::biphasic(h, params.core);
    match mode {
        ContactMode::None => None,
        ContactMode::Penalty => Some(BarrierShape::single_phase(h)),
        ContactMode::Barrier => Some(full),
        ContactMode::Culled { window } => (!(pair.same_yarn && pair.index_gap <= window)).then_some(full),
        ContactMode::Filtered => {
            if pair.dbar >= h {
                Some(full)
            } else if pair.dbar > 0.0 {
                Some(BarrierShape::single_phase(dbar_min))
            } else {
                None
            }
        }
    }
}

/// Whether a mode needs the reference distances `dbar` (graph searches).
pub fn needs_reference_distance(mode: ContactMode) -> bool {
    matches!(mode, ContactMode::Filtered)
}

/// Whether a mode guards its stencils with CCD (barrier modes only).
pub fn uses_ccd(mode: ContactMode) -> bool {
    matches!(
        mode,
        ContactMode::Barrier | ContactMode::Culled { .. } | ContactMode::Filtered
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: ThicknessParams = ThicknessParams {
        thickness: 0.3,
        core: 0.2,
        penalty_stiffness: 1.0,
    };

    fn pair(same_yarn: bool, index_gap: u32, dbar: f64) -> PairRest {
        PairRest {
            same_yarn,
            index_gap,
            dbar,
        }
    }

    #[test]
    fn filtered_rule_is_seed_003_eq_4() {
        let dbar_min = 0.1;
        // Far along the yarn: full thickness, biphasic.
        let s = stencil_shape(ContactMode::Filtered, &pair(true, 9, f64::INFINITY), &P, dbar_min);
        assert_eq!(s, Some(BarrierShape::biphasic(0.3, 0.2)));
        let s = stencil_shape(ContactMode::Filtered, &pair(true, 3, 0.3), &P, dbar_min);
        assert_eq!(s, Some(BarrierShape::biphasic(0.3, 0.2)));
        // Closer than h: dbar_min, single phase.
        let s = stencil_shape(ContactMode::Filtered, &pair(true, 2, 0.15), &P, dbar_min);
        assert_eq!(s, Some(BarrierShape::single_phase(0.1)));
        // Sharing a node: not a stencil.
        assert_eq!(
            stencil_shape(ContactMode::Filtered, &pair(false, 0, 0.0), &P, dbar_min),
            None
        );
    }

    #[test]
    fn other_modes() {
        let near = pair(true, 3, 0.15);
        let other_yarn = pair(false, 3, 0.15);
        let full = Some(BarrierShape::biphasic(0.3, 0.2));
        assert_eq!(stencil_shape(ContactMode::Barrier, &near, &P, 0.1), full);
        assert_eq!(stencil_shape(ContactMode::Culled { window: 5 }, &near, &P, 0.1), None);
        assert_eq!(stencil_shape(ContactMode::Culled { window: 2 }, &near, &P, 0.1), full);
        assert_eq!(
            stencil_shape(ContactMode::Culled { window: 5 }, &other_yarn, &P, 0.1),
            full
        );
        assert_eq!(stencil_shape(ContactMode::None, &near, &P, 0.1), None);
        assert_eq!(
            stencil_shape(ContactMode::Penalty, &near, &P, 0.1),
            Some(BarrierShape::single_phase(0.3))
        );
        assert!((P.comparison_core(0.1) - 0.09).abs() < 1e-15);
    }
}
