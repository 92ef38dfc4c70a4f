//! Backtracking line search on the energy (docs/MODEL.md,
//! "Line search").
//!
//! Armijo sufficient decrease, `E(q + a dq) <= E(q) + c1 a g.dq`, halving `a`
//! from its start. The start is `min(1, max_step)` where `max_step` is the
//! collision-free fraction of the step (CCD), so the search never leaves the
//! feasible set of a barrier energy. A non-finite trial energy (a barrier
//! crossed, a segment collapsed) is simply a rejected trial.
//!
//! Near convergence `E(q)` and `E(q + a dq)` agree to all printed digits and
//! the Armijo test becomes a coin toss on round-off. A slack of a few ulps of
//! `|E|` absorbs that; it cannot cause cycling because Newton's own stopping
//! tests and iteration cap bound the loop.

/// Parameters of the backtracking search.
#[derive(Clone, Copy, Debug)]
pub struct LineSearchParams {
    /// Armijo constant `c1` (fraction of the linear decrease required).
    pub armijo_c1: f64,
    /// Factor applied to the step after a rejected trial, in (0, 1).
    pub shrink: f64,
    /// Rejected trials before the search gives up.
    pub max_backtracks: usize,
    /// Round-off slack, relative to `|E(q)|`, allowed in the decrease test.
    pub energy_rel_slack: f64,
}

impl Default for LineSearchParams {
    fn default() -> Self {
        LineSearchParams {
            armijo_c1: 1e-4,
            shrink: 0.5,
            max_backtracks: 40,
            energy_rel_slack: 1e-13,
        }
    }
}

/// An accepted step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSearchStep {
    /// Accepted step length `a`.
    pub alpha: f64,
    /// `E(q + a dq)`.
    pub energy: f64,
    /// Energy evaluations used, the accepted one included.
    pub trials: usize,
}

/// Backtracks from `alpha0` until `energy_at(a)` satisfies Armijo.
///
/// `e0 = E(q)`, `slope = g . dq` (must be negative for a descent direction).
/// Returns `None` when every trial was rejected or `alpha0` is not positive.
pub fn backtracking_armijo(
    mut energy_at: impl FnMut(f64) -> f64,
    e0: f64,
    slope: f64,
    alpha0: f64,
    p: &LineSearchParams,
) -> Option<LineSearchStep> {
    // Also rejects NaN.
    if !(alpha0.is_finite() && alpha0 > 0.0) {
        return None;
    }
    let slack = p.energy_rel_slack * e0.abs();
    let mut alpha = alpha0;
    for trial in 1..=p.max_backtracks + 1 {
        let e = energy_at(alpha);
        if e.is_finite() && e <= e0 + p.armijo_c1 * alpha * slope + slack {
            return Some(LineSearchStep {
                alpha,
                energy: e,
                trials: trial,
            });
        }
        alpha *= p.shrink;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_step_on_a_parabola_and_backtracks_on_overshoot() {
        // E(a) = (a - 1)^2 along dq: the minimum is at a = 1, slope -2.
        let p = LineSearchParams::default();
        let s = backtracking_armijo(|a| (a - 1.0) * (a - 1.0), 1.0, -2.0, 1.0, &p).unwrap();
        assert_eq!((s.alpha, s.trials), (1.0, 1));
        // Starting at 4 overshoots: E(4) = 9, E(2) = 1 (no decrease), E(1) = 0.
        let s = backtracking_armijo(|a| (a - 1.0) * (a - 1.0), 1.0, -2.0, 4.0, &p).unwrap();
        assert_eq!((s.alpha, s.trials), (1.0, 3));
    }

    #[test]
    fn non_finite_trials_are_rejected_and_ascent_fails() {
        let p = LineSearchParams::default();
        // A barrier at a = 0.3: infinite beyond it.
        let e = |a: f64| if a >= 0.3 { f64::INFINITY } else { -a };
        let s = backtracking_armijo(e, 0.0, -1.0, 1.0, &p).unwrap();
        assert_eq!(s.alpha, 0.25);
        // Energy increases in every direction: no step is accepted.
        assert!(backtracking_armijo(|a| a, 0.0, -1.0, 1.0, &p).is_none());
        assert!(backtracking_armijo(|a| -a, 0.0, -1.0, 0.0, &p).is_none());
    }
}
