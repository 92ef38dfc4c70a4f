use super::*;
use crate::solver::assembly::StencilSet;
use crate::solver::assembly::{assemble, bind_all, cancel_fixed_rows, hessian_pattern, total_energy, AnyStencilSet};
use crate::solver::linear::{CgParams, LinearSolver};
use crate::solver::test_stencils::{Gravity, Spring};
use nalgebra::{DMatrix, DVector};
use std::sync::atomic::{AtomicBool, Ordering};

/// `E = q^T A q / 2 - b^T q` with a tridiagonal SPD `A`; coordinate 0 pinned.
struct Quadratic {
    a: CsrMatrix,
    b: Vec<f64>,
    free: Vec<bool>,
    cap: f64,
}

impl Quadratic {
    fn new(n: usize, cap: f64) -> Self {
        let mut e = Vec::new();
        for i in 0..n as u32 {
            e.push((i, i));
            if i > 0 {
                e.extend([(i, i - 1), (i - 1, i)]);
            }
        }
        let mut a = CsrMatrix::from_pattern(n, e);
        for r in 0..n {
            for k in a.row_ptr[r]..a.row_ptr[r + 1] {
                a.values[k] = if a.col_idx[k] as usize == r {
                    2.5 + 0.1 * r as f64
                } else {
                    -1.0
                };
            }
        }
        let b = (0..n).map(|i| (i as f64 * 0.7).cos()).collect();
        let mut free = vec![true; n];
        free[0] = false;
        Quadratic { a, b, free, cap }
    }

    /// Minimiser over the free coordinates with q[0] held, by a dense solve.
    fn exact(&self, q0: f64) -> Vec<f64> {
        self.exact_holding(&[(0, q0)])
    }

    /// Minimiser with the coordinates `held` at the given values, by a
    /// dense solve over the others.
    fn exact_holding(&self, held: &[(usize, f64)]) -> Vec<f64> {
        let n = self.a.n;
        let ad = DMatrix::from_fn(n, n, |r, c| self.a.find(r, c).map_or(0.0, |k| self.a.values[k]));
        let rest: Vec<usize> = (0..n).filter(|i| held.iter().all(|h| h.0 != *i)).collect();
        let aff = DMatrix::from_fn(rest.len(), rest.len(), |r, c| ad[(rest[r], rest[c])]);
        let rhs = DVector::from_fn(rest.len(), |r, _| {
            self.b[rest[r]] - held.iter().map(|&(i, v)| ad[(rest[r], i)] * v).sum::<f64>()
        });
        let x = aff.lu().solve(&rhs).unwrap();
        let mut q = vec![0.0; n];
        held.iter().for_each(|&(i, v)| q[i] = v);
        rest.iter().zip(x.iter()).for_each(|(&i, &v)| q[i] = v);
        q
    }
}

impl Problem for Quadratic {
    fn energy(&mut self, q: &[f64]) -> f64 {
        let mut aq = vec![0.0; q.len()];
        self.a.mul_vec(q, &mut aq);
        (0..q.len()).map(|i| 0.5 * q[i] * aq[i] - self.b[i] * q[i]).sum()
    }
    fn gradient_hessian(&mut self, q: &[f64], g: &mut [f64], h: &mut CsrMatrix) -> Result<(), AssemblyError> {
        self.a.mul_vec(q, g);
        for (gi, bi) in g.iter_mut().zip(&self.b) {
            *gi -= bi;
        }
        for r in 0..h.n {
            for k in h.row_ptr[r]..h.row_ptr[r + 1] {
                let c = h.col_idx[k] as usize;
                h.values[k] = if self.free[r] && self.free[c] {
                    self.a.values[k]
                } else {
                    0.0
                };
            }
        }
        cancel_fixed_rows(&self.free, g, h);
        Ok(())
    }
    fn hessian_pattern(&self) -> CsrMatrix {
        self.a.clone()
    }
    fn free(&self) -> &[bool] {
        &self.free
    }
    fn max_step(&mut self, _q: &[f64], _dq: &[f64]) -> f64 {
        self.cap
    }
}

/// Newton with the direct solver and default parameters.
fn solve<P: Problem>(p: &mut P, q: &mut [f64]) -> NewtonReport {
    minimize(
        p,
        q,
        &mut LinearSolver::direct(),
        &NewtonParams::default(),
        Default::default(),
    )
    .unwrap()
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn quadratic_converges_in_one_direct_step() {
    let mut p = Quadratic::new(12, 1.0);
    let mut q = vec![0.3; 12];
    let rep = solve(&mut p, &mut q);
    assert!(rep.converged(), "{:?}", rep.status);
    assert_eq!(rep.steps(), 1);
    assert_eq!(rep.history[0].step, 1.0);
    assert!(max_diff(&q, &p.exact(0.3)) < 1e-12);
    assert_eq!(q[0], 0.3, "pinned coordinate moved");
}

/// [`Quadratic`] with optional extras: a lower bound `(k, lo)` on one
/// coordinate ([`Problem::bounds`]), and a discretization that "breaks"
/// once `q[last]` has gone more than `fraction` of the way to `target`
/// ([`Problem::must_rediscretize`]), as `(target, fraction)`.
struct Extended {
    inner: Quadratic,
    lower: Option<(usize, f64)>,
    breaks: Option<(f64, f64)>,
}

impl Problem for Extended {
    fn energy(&mut self, q: &[f64]) -> f64 {
        self.inner.energy(q)
    }
    fn gradient_hessian(&mut self, q: &[f64], g: &mut [f64], h: &mut CsrMatrix) -> Result<(), AssemblyError> {
        self.inner.gradient_hessian(q, g, h)
    }
    fn hessian_pattern(&self) -> CsrMatrix {
        self.inner.hessian_pattern()
    }
    fn free(&self) -> &[bool] {
        self.inner.free()
    }
    fn max_step(&mut self, q: &[f64], dq: &[f64]) -> f64 {
        self.inner.max_step(q, dq)
    }
    fn bounds(&self, _q: &[f64], lower: &mut [f64], _upper: &mut [f64]) -> bool {
        let Some((k, lo)) = self.lower else { return false };
        lower[k] = lo;
        true
    }
    fn must_rediscretize(&self, q: &[f64]) -> bool {
        self.breaks
            .is_some_and(|(target, fraction)| q[q.len() - 1] / target > fraction)
    }
}

#[test]
fn a_bounded_coordinate_stops_at_its_bound_and_the_rest_converge() {
    let n = 10;
    let free_min = Quadratic::new(n, 1.0).exact(0.0);
    let (k, lo) = (5, free_min[5] + 0.2);
    let mut p = Extended {
        inner: Quadratic::new(n, 1.0),
        lower: Some((k, lo)),
        breaks: None,
    };
    // The constrained minimiser: coordinates 0 and k held (a dense solve).
    let expect = p.inner.exact_holding(&[(0, 0.0), (k, lo)]);
    let mut q = vec![0.0; n];
    q[k] = lo + 1.0;
    let rep = solve(&mut p, &mut q);
    assert!(rep.converged(), "{:?}", rep.status);
    assert!(rep.history.len() <= 4, "{} iterations", rep.history.len());
    assert_eq!(q[k], lo, "the bounded coordinate ends on its bound");
    assert_eq!(rep.history.last().unwrap().held, 1);
    assert!(max_diff(&q, &expect) < 1e-10, "{q:?} against {expect:?}");
    // Without the bound the same start goes to the free minimiser, below it.
    let mut q = vec![0.0; n];
    q[k] = lo + 1.0;
    solve(&mut p.inner, &mut q);
    assert!(q[k] < lo - 0.1);
}

#[test]
fn max_step_caps_the_first_step() {
    let mut p = Quadratic::new(8, 0.25);
    let q0 = vec![0.0; 8];
    let mut q = q0.clone();
    let params = NewtonParams {
        max_iterations: 1,
        ..Default::default()
    };
    let rep = minimize(&mut p, &mut q, &mut LinearSolver::direct(), &params, Default::default()).unwrap();
    assert_eq!(rep.status, NewtonStatus::MaxIterations);
    assert_eq!(rep.history[0].step, 0.25);
    // On a quadratic the Newton step lands on the minimiser: a quarter of it was taken.
    let expect: Vec<f64> = p.exact(0.0).iter().zip(&q0).map(|(x, y)| y + 0.25 * (x - y)).collect();
    assert!(max_diff(&q, &expect) < 1e-12);
}

#[test]
fn a_step_that_leaves_the_discretization_ends_the_solve_on_that_iterate() {
    // Capped steps of 1/4 approach the minimiser geometrically; the last
    // coordinate crosses `at` on the third step.
    let target = Quadratic::new(8, 1.0).exact(0.0)[7];
    let fraction = 0.99 * (1.0 - 0.75f64.powi(3));
    assert!(target != 0.0 && 1.0 - 0.75f64.powi(2) < fraction);
    let mut p = Extended {
        inner: Quadratic::new(8, 0.25),
        lower: None,
        breaks: Some((target, fraction)),
    };
    let mut q = vec![0.0; 8];
    let rep = minimize(
        &mut p,
        &mut q,
        &mut LinearSolver::direct(),
        &NewtonParams::default(),
        Default::default(),
    )
    .unwrap();
    assert_eq!(rep.status, NewtonStatus::Rediscretize);
    assert_eq!(rep.history.len(), 3);
    // The same three iterations without the test end on the same iterate.
    let mut plain = Quadratic::new(8, 0.25);
    let mut q3 = vec![0.0; 8];
    let params = NewtonParams {
        max_iterations: 3,
        ..Default::default()
    };
    minimize(
        &mut plain,
        &mut q3,
        &mut LinearSolver::direct(),
        &params,
        Default::default(),
    )
    .unwrap();
    assert_eq!(q, q3);
    assert!(q[7] / target > fraction);
}

#[test]
fn cancellation_stops_between_iterations() {
    let stop = AtomicBool::new(false);
    let mut seen = 0;
    let mut on_iteration = |_: &IterStats| {
        seen += 1;
        stop.store(true, Ordering::Relaxed);
    };
    let (mut p, mut q) = hanging_chain(6);
    let hooks = NewtonHooks {
        on_iteration: Some(&mut on_iteration),
        cancel: Some(&stop),
        on_accepted: None,
    };
    let rep = minimize(
        &mut p,
        &mut q,
        &mut LinearSolver::direct(),
        &NewtonParams::default(),
        hooks,
    )
    .unwrap();
    assert_eq!(rep.status, NewtonStatus::Cancelled);
    assert_eq!(rep.history.len(), 1);
    assert_eq!(seen, 1);
}

#[test]
fn infeasible_start_is_an_error() {
    let mut p = Quadratic::new(4, 1.0);
    let mut q = vec![f64::NAN; 4];
    let r = minimize(
        &mut p,
        &mut q,
        &mut LinearSolver::direct(),
        &NewtonParams::default(),
        Default::default(),
    );
    assert!(matches!(r, Err(NewtonError::NonFiniteStart(_))));
}

/// Stencil sets behind the `Problem` trait, as the lead's scene will be.
struct Sets {
    sets: Vec<Box<dyn AnyStencilSet>>,
    free: Vec<bool>,
    pattern: CsrMatrix,
}

impl Problem for Sets {
    fn energy(&mut self, q: &[f64]) -> f64 {
        total_energy(&self.sets, q)
    }
    fn gradient_hessian(&mut self, q: &[f64], g: &mut [f64], h: &mut CsrMatrix) -> Result<(), AssemblyError> {
        assemble(&self.sets, q, &self.free, g, h, true)
    }
    fn hessian_pattern(&self) -> CsrMatrix {
        self.pattern.clone()
    }
    fn free(&self) -> &[bool] {
        &self.free
    }
    fn blocks(&self) -> Vec<usize> {
        (0..=self.free.len()).step_by(3).collect()
    }
}

const K: f64 = 40.0;
const REST: f64 = 1.0;
const MG: f64 = 0.5;

/// `n` springs hanging from node 0 (pinned at the origin), started
/// horizontal and zig-zagged: far from the minimum and with compressed,
/// indefinite springs on the way.
fn hanging_chain(n: usize) -> (Sets, Vec<f64>) {
    let springs = (0..n).map(|_| Spring { k: K, rest: REST }).collect();
    let dofs = (0..n as u32)
        .map(|i| {
            let (a, b) = (3 * i, 3 * i + 3);
            [a, a + 1, a + 2, b, b + 1, b + 2]
        })
        .collect();
    let gravity = (0..=n).map(|_| Gravity { mg: MG }).collect();
    let gdofs = (0..=n as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    let mut sets: Vec<Box<dyn AnyStencilSet>> = vec![
        Box::new(StencilSet::new("springs", springs, dofs)),
        Box::new(StencilSet::new("gravity", gravity, gdofs)),
    ];
    let nq = 3 * (n + 1);
    let pattern = hessian_pattern(nq, &sets);
    bind_all(&mut sets, &pattern).unwrap();
    let mut free = vec![true; nq];
    free[..3].fill(false);
    let q = (0..=n)
        .flat_map(|i| [0.8 * i as f64, 0.2 * (i % 2) as f64, 0.05 * i as f64])
        .collect();
    (Sets { sets, free, pattern }, q)
}

/// Equilibrium: spring `i` (1-based from the top) carries the weight of
/// nodes `i..=n`, so it is stretched by `(n - i + 1) mg / k`, straight down.
fn hanging_chain_exact(n: usize) -> Vec<f64> {
    let mut q = vec![0.0; 3];
    let mut z = 0.0;
    for i in 1..=n {
        z -= REST + (n - i + 1) as f64 * MG / K;
        q.extend([0.0, 0.0, z]);
    }
    q
}

#[test]
fn hanging_chain_reaches_the_analytic_equilibrium_with_both_solvers() {
    let n = 8;
    let exact = hanging_chain_exact(n);
    let params = NewtonParams {
        max_iterations: 200,
        ..Default::default()
    };
    let cg = LinearSolver::Cg(CgParams {
        rel_tol: 1e-10,
        max_iter: 500,
    });
    for mut solver in [LinearSolver::direct(), cg] {
        let (mut p, mut q) = hanging_chain(n);
        let e_start = p.energy(&q);
        let rep = minimize(&mut p, &mut q, &mut solver, &params, Default::default()).unwrap();
        assert!(
            rep.converged(),
            "{}: {:?} after {}",
            solver.name(),
            rep.status,
            rep.history.len()
        );
        assert!(
            max_diff(&q, &exact) < 1e-6,
            "{}: {}",
            solver.name(),
            max_diff(&q, &exact)
        );
        assert!(
            rep.history.len() < 60,
            "{}: {} iterations",
            solver.name(),
            rep.history.len()
        );
        // Energy never increased along the way (up to the line search's round-off slack).
        let energies: Vec<f64> = rep.history.iter().map(|s| s.energy).collect();
        assert!(energies.windows(2).all(|w| w[1] <= w[0] + 1e-12 * w[0].abs()));
        assert_eq!(energies[0], e_start);
        assert!(rep.history.iter().all(|s| s.elapsed_s >= 0.0));
    }
}

#[test]
fn every_accepted_iterate_is_reported_in_order() {
    let (mut p, mut q) = hanging_chain(6);
    let mut path: Vec<Vec<f64>> = Vec::new();
    let mut on_accepted = |x: &[f64]| path.push(x.to_vec());
    let hooks = NewtonHooks {
        on_accepted: Some(&mut on_accepted),
        ..Default::default()
    };
    let rep = minimize(
        &mut p,
        &mut q,
        &mut LinearSolver::direct(),
        &NewtonParams::default(),
        hooks,
    )
    .unwrap();
    assert!(rep.converged());
    // One state per step taken, the last one the solution returned.
    assert_eq!(path.len(), rep.steps());
    assert!(path.len() >= 2);
    assert_eq!(path.last().unwrap().as_slice(), q.as_slice());
    // Each reported state is a new one (a step moved it).
    assert!(path.windows(2).all(|w| w[0] != w[1]));
}

#[test]
fn every_iteration_times_its_phases_within_its_own_time() {
    let (mut p, mut q) = hanging_chain(40);
    let rep = minimize(
        &mut p,
        &mut q,
        &mut LinearSolver::direct(),
        &NewtonParams::default(),
        NewtonHooks::default(),
    )
    .unwrap();
    assert!(rep.converged());
    let mut previous_end = 0.0;
    for s in &rep.history {
        let phases = [s.assembly_s, s.solve_s, s.line_search_s];
        assert!(phases.iter().all(|t| t.is_finite() && *t >= 0.0), "{phases:?}");
        // The phases lie inside the iteration: between the previous
        // iteration's end and this one's.
        let sum: f64 = phases.iter().sum();
        assert!(
            sum <= s.elapsed_s - previous_end + 1e-9,
            "{sum} > {}",
            s.elapsed_s - previous_end
        );
        previous_end = s.elapsed_s;
    }
    // Every iteration assembles; every one that stepped solved and searched.
    assert!(rep.history.iter().all(|s| s.assembly_s > 0.0));
    assert!(rep
        .history
        .iter()
        .filter(|s| s.step > 0.0)
        .all(|s| s.solve_s > 0.0 && s.line_search_s > 0.0));
}
