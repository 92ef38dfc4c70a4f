//! Per-iteration bounds on single coordinates: a projected Newton step
//! (Bertsekas 1982, "Projected Newton methods for optimization problems
//! with simple constraints").
//!
//! Why: one coordinate whose energy has a wall (a yarn point's `u` sliding
//! onto its neighbour, where the stretch stiffness `ks / du` grows without
//! bound) made the line search cut the *whole* step to 1/8 .. 1/256 and the
//! Levenberg damping climb for every unknown, for up to nine iterations at
//! a time.
//! A bound stops that coordinate alone: the trial point is clamped into the
//! box, and a coordinate pressed against its bound (the gradient pushing it
//! further) is held for the iteration, so the Newton system is solved on the
//! others. What happens at the bound is the problem's business (for the
//! yarn model, the next re-assignment hands the point to EIL).
//!
//! The bounds come from the problem at the start of every iteration
//! ([`Problem::bounds`](super::Problem::bounds)) and hold for that
//! iteration only; an unbounded coordinate has `-inf` / `+inf`.

use crate::sparse::CsrMatrix;

pub(super) struct Bounds {
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    /// Whether the problem gave bounds this iteration.
    pub active: bool,
    /// Coordinates held at a bound this iteration.
    pub held: Vec<usize>,
}

impl Bounds {
    pub fn new(n: usize) -> Self {
        Bounds {
            lower: vec![f64::NEG_INFINITY; n],
            upper: vec![f64::INFINITY; n],
            active: false,
            held: Vec::new(),
        }
    }

    /// Finds the free coordinates at a bound whose gradient pushes them
    /// out of the box, and removes them from this iteration's system: zero
    /// gradient, zero off-diagonal row and column (the matrix stays
    /// symmetric for the direct solver), diagonal kept.
    pub fn hold(&mut self, q: &[f64], free: &[bool], g: &mut [f64], h: &mut CsrMatrix) {
        self.held.clear();
        if !self.active {
            return;
        }
        for i in 0..q.len() {
            let pushed_down = q[i] <= self.lower[i] && g[i] > 0.0;
            let pushed_up = q[i] >= self.upper[i] && g[i] < 0.0;
            if free[i] && (pushed_down || pushed_up) {
                self.held.push(i);
            }
        }
        for &i in &self.held {
            g[i] = 0.0;
            for k in h.row_ptr[i]..h.row_ptr[i + 1] {
                let j = h.col_idx[k] as usize;
                if j != i {
                    h.values[k] = 0.0;
                    if let Some(t) = h.find(j, i) {
                        h.values[t] = 0.0;
                    }
                }
            }
        }
    }

    /// Clamps `trial` into this iteration's box.
    pub fn project(&self, trial: &mut [f64]) {
        if !self.active {
            return;
        }
        for ((t, lo), hi) in trial.iter_mut().zip(&self.lower).zip(&self.upper) {
            *t = t.clamp(*lo, *hi);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pressed_coordinate_is_held_and_the_matrix_stays_symmetric() {
        let mut h = CsrMatrix::from_pattern(3, [(0, 0), (0, 1), (1, 0), (1, 1), (1, 2), (2, 1), (2, 2)]);
        h.values.iter_mut().enumerate().for_each(|(k, v)| *v = 1.0 + k as f64);
        let mut b = Bounds::new(3);
        b.active = true;
        b.lower[1] = 0.5;
        // At its lower bound and pushed down (g > 0): held.
        let mut g = vec![1.0, 2.0, -1.0];
        b.hold(&[0.0, 0.5, 0.0], &[true; 3], &mut g, &mut h);
        assert_eq!(b.held, vec![1]);
        assert_eq!(g, vec![1.0, 0.0, -1.0]);
        for (r, c) in [(0, 1), (1, 0), (1, 2), (2, 1)] {
            assert_eq!(h.values[h.find(r, c).unwrap()], 0.0, "({r}, {c})");
        }
        assert_eq!(h.values[h.find(1, 1).unwrap()], 4.0);
        // Pulled back into the box (g < 0): free to move.
        let mut g = vec![1.0, -2.0, -1.0];
        b.hold(&[0.0, 0.5, 0.0], &[true; 3], &mut g, &mut h);
        assert!(b.held.is_empty());
        let mut t = vec![-1.0, 0.2, 9.0];
        b.project(&mut t);
        assert_eq!(t, vec![-1.0, 0.5, 9.0]);
    }
}
