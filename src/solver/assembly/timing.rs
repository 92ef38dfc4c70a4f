//! Where a run's time goes: seconds spent evaluating each stencil set
//! (energy, gradient and Hessian, PSD projection included) and in the
//! linear solver, summed over every Newton iteration of a run.
//!
//! A set exists only when its scene needs it (no obstacle, no obstacle
//! term), so the names listed are also the run's active terms. The
//! summary lists each with its share of the wall time; what the shares do
//! not cover is the rest of the run: line-search bookkeeping, contact
//! candidate search, EIL reassignment, outputs.

use serde::Serialize;
use std::collections::BTreeMap;

/// Time of one stencil set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct TermTime {
    pub seconds: f64,
    /// The most stencils the set held in one solve.
    pub stencils: usize,
}

/// Seconds per stencil set and in the linear solver.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct TermTimes {
    pub terms: BTreeMap<String, TermTime>,
    pub linear_solve_s: f64,
}

impl TermTimes {
    /// Adds `seconds` spent on the set `name` of `stencils` stencils.
    pub fn add(&mut self, name: &str, seconds: f64, stencils: usize) {
        let t = match self.terms.get_mut(name) {
            Some(t) => t,
            None => self.terms.entry(name.to_string()).or_default(),
        };
        t.seconds += seconds;
        t.stencils = t.stencils.max(stencils);
    }

    /// Adds every time of `other` to this one.
    pub fn merge(&mut self, other: &TermTimes) {
        for (name, t) in &other.terms {
            self.add(name, t.seconds, t.stencils);
        }
        self.linear_solve_s += other.linear_solve_s;
    }

    /// Seconds in the stencil sets and the linear solver together.
    pub fn total_s(&self) -> f64 {
        self.terms.values().map(|t| t.seconds).sum::<f64>() + self.linear_solve_s
    }

    /// One line for a run log: the linear solver and each term with its
    /// share of `wall_s`, largest first, then the rest of the run.
    pub fn shares_line(&self, wall_s: f64) -> String {
        let mut parts: Vec<(String, f64)> = self.terms.iter().map(|(n, t)| (n.clone(), t.seconds)).collect();
        parts.push(("linear solve".to_string(), self.linear_solve_s));
        parts.sort_by(|a, b| b.1.total_cmp(&a.1));
        let wall = wall_s.max(f64::MIN_POSITIVE);
        let pct = |s: f64| 100.0 * s / wall;
        let listed: Vec<String> = parts.iter().map(|(n, s)| format!("{n} {:.0}%", pct(*s))).collect();
        let rest = (wall_s - self.total_s()).max(0.0);
        format!(
            "time by term ({} active, of {wall_s:.1} s): {}, rest {:.0}%",
            self.terms.len(),
            listed.join(", "),
            pct(rest)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merging_sums_seconds_and_keeps_the_largest_set() {
        let mut a = TermTimes::default();
        a.add("rod", 1.0, 10);
        a.linear_solve_s = 2.0;
        let mut b = TermTimes::default();
        b.add("rod", 0.5, 12);
        b.add("obstacle", 0.25, 3);
        b.linear_solve_s = 1.0;
        a.merge(&b);
        assert_eq!(
            a.terms["rod"],
            TermTime {
                seconds: 1.5,
                stencils: 12
            }
        );
        assert_eq!(
            a.terms["obstacle"],
            TermTime {
                seconds: 0.25,
                stencils: 3
            }
        );
        assert_eq!(a.total_s(), 4.75);
    }

    #[test]
    fn the_line_lists_the_largest_share_first_and_the_rest() {
        let mut t = TermTimes::default();
        t.add("rod", 1.0, 10);
        t.add("contact", 3.0, 10);
        t.linear_solve_s = 4.0;
        let line = t.shares_line(10.0);
        assert_eq!(
            line,
            "time by term (2 active, of 10.0 s): linear solve 40%, contact 30%, rod 10%, rest 20%"
        );
    }
}
